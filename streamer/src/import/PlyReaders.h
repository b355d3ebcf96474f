#pragma once
// Value readers for the PLY body, one per encoding, with the same interface so that the
// element walkers are written once (templates, no virtual call per value).
#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>

#include "import/PlyHeader.h"

namespace vastray::import {

// A float-typed integer (list count, index) must be integral and within +-2^53 (exact in a
// double); converting 1e300 to int64 is undefined and printed as -9223372036854775808.
inline bool integralValue(double value, int64_t& out, const char*& failure) {
    if (!std::isfinite(value) || value != std::floor(value)) {
        failure = "non-integral value";
        return false;
    }
    if (std::fabs(value) > 9007199254740992.0) {
        failure = "integer value beyond +-2^53";
        return false;
    }
    out = static_cast<int64_t>(value);
    return true;
}

class PlyBinaryReader {
public:
    PlyBinaryReader(const char* p, const char* end, bool bigEndian)
        : p_(p), end_(end), swap_(bigEndian != (std::endian::native == std::endian::big)) {}

    bool readReal(PlyType t, double& out) {
        switch (t) {
            case PlyType::Int8: return readAs<int8_t>(out);
            case PlyType::UInt8: return readAs<uint8_t>(out);
            case PlyType::Int16: return readAs<int16_t>(out);
            case PlyType::UInt16: return readAs<uint16_t>(out);
            case PlyType::Int32: return readAs<int32_t>(out);
            case PlyType::UInt32: return readAs<uint32_t>(out);
            case PlyType::Float32: return readAs<float>(out);
            case PlyType::Float64: return readAs<double>(out);
        }
        return false;
    }

    // Integers only; a float-typed index must hold an integral value.
    bool readInt(PlyType t, int64_t& out) {
        double value;
        if (!readReal(t, value)) return false;
        return integralValue(value, out, failure_);
    }

    bool skip(PlyType t) { return skipBytes(plySize(t)); }
    bool skipBytes(uint64_t n) {
        if (n > static_cast<uint64_t>(end_ - p_)) return false;
        p_ += n;
        return true;
    }
    bool canSkipRowsInBulk() const { return true; }
    const char* failure() const { return failure_ ? failure_ : "unexpected end of file"; }

private:
    template <typename T>
    bool readAs(double& out) {
        if (static_cast<size_t>(end_ - p_) < sizeof(T)) return false;
        unsigned char raw[sizeof(T)];
        std::memcpy(raw, p_, sizeof(T));
        if (swap_) std::reverse(raw, raw + sizeof(T));
        T value;
        std::memcpy(&value, raw, sizeof(T));
        out = static_cast<double>(value);
        p_ += sizeof(T);
        return true;
    }

    const char* p_;
    const char* end_;
    bool swap_;
    const char* failure_ = nullptr;
};

// ASCII rows are whitespace-separated values; line breaks carry no meaning for the walker.
class PlyAsciiReader {
public:
    PlyAsciiReader(const char* p, const char* end) : p_(p), end_(end) {}

    bool readReal(PlyType, double& out) { return parse(out); }
    bool readInt(PlyType t, int64_t& out) {
        if (!isFloatType(t)) return parse(out);
        double value;
        if (!parse(value)) return false;
        return integralValue(value, out, failure_);
    }
    bool skip(PlyType) {
        skipSpace();
        const char* start = p_;
        while (p_ < end_ && !isSpace(*p_)) ++p_;
        return p_ != start;
    }
    bool skipBytes(uint64_t) { return false; }
    bool canSkipRowsInBulk() const { return false; }
    const char* failure() const {
        return failure_ ? failure_ : p_ >= end_ ? "unexpected end of file" : "malformed value";
    }

private:
    static bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }
    void skipSpace() {
        while (p_ < end_ && isSpace(*p_)) ++p_;
    }
    template <typename T>
    bool parse(T& out) {
        skipSpace();
        const char* start = (p_ < end_ && *p_ == '+') ? p_ + 1 : p_;
        const auto [next, ec] = std::from_chars(start, end_, out);
        if (ec != std::errc() || next == start || (next < end_ && !isSpace(*next))) return false;
        p_ = next;
        return true;
    }

    const char* p_;
    const char* end_;
    const char* failure_ = nullptr;
};

}  // namespace vastray::import
