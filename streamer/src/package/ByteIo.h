#pragma once
// Little-endian field-by-field serialization, so package bytes never depend on struct
// padding or the compiler, and a reader never reads past what it was given.
#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace vastray {

static_assert(std::endian::native == std::endian::little, "the package format is little-endian");

class ByteWriter {
public:
    template <typename T>
    void put(T value) {
        static_assert(std::is_trivially_copyable_v<T>);
        const size_t at = bytes_.size();
        bytes_.resize(at + sizeof(T));
        std::memcpy(bytes_.data() + at, &value, sizeof(T));
    }
    void putBytes(const void* data, size_t size) {
        const size_t at = bytes_.size();
        bytes_.resize(at + size);
        if (size) std::memcpy(bytes_.data() + at, data, size);
    }
    template <typename T>
    void putArray(const std::vector<T>& values) { putBytes(values.data(), values.size() * sizeof(T)); }
    void putFixedString(const std::string& text, size_t width) {
        std::string padded = text.substr(0, width);
        padded.resize(width, '\0');
        putBytes(padded.data(), width);
    }
    void padTo(size_t size) { bytes_.resize(std::max(bytes_.size(), size), 0); }
    size_t size() const { return bytes_.size(); }
    std::vector<uint8_t>& bytes() { return bytes_; }

private:
    std::vector<uint8_t> bytes_;
};

class ByteReader {
public:
    ByteReader(const uint8_t* data, size_t size) : data_(data), size_(size) {}

    template <typename T>
    bool get(T& value) {
        if (sizeof(T) > size_ - pos_) return fail();
        std::memcpy(&value, data_ + pos_, sizeof(T));
        pos_ += sizeof(T);
        return true;
    }
    // Reads `count` elements after checking they fit in what is left: never allocates for a
    // count the data cannot hold.
    template <typename T>
    bool getArray(std::vector<T>& values, uint64_t count) {
        if (count > (size_ - pos_) / sizeof(T)) return fail();
        values.resize(count);
        if (count) std::memcpy(values.data(), data_ + pos_, count * sizeof(T));
        pos_ += count * sizeof(T);
        return true;
    }
    bool getFixedString(std::string& text, size_t width) {
        if (width > size_ - pos_) return fail();
        const char* begin = reinterpret_cast<const char*>(data_ + pos_);
        text.assign(begin, strnlen(begin, width));
        pos_ += width;
        return true;
    }
    bool skip(size_t count) {
        if (count > size_ - pos_) return fail();
        pos_ += count;
        return true;
    }
    const uint8_t* current() const { return data_ + pos_; }
    size_t position() const { return pos_; }
    size_t remaining() const { return size_ - pos_; }
    bool ok() const { return ok_; }

private:
    bool fail() {
        ok_ = false;
        return false;
    }
    const uint8_t* data_;
    size_t size_;
    size_t pos_ = 0;
    bool ok_ = true;
};

}  // namespace vastray
