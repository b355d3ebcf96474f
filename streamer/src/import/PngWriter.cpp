#include "import/PngWriter.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <string>

namespace vastray::import {
namespace {

void putBigEndian(std::vector<uint8_t>& out, uint32_t value) {
    for (int shift = 24; shift >= 0; shift -= 8) out.push_back(uint8_t(value >> shift));
}

// A chunk: length, type, data, CRC of type and data.
void putChunk(std::vector<uint8_t>& out, const char (&type)[5], const uint8_t* data, uint32_t size) {
    putBigEndian(out, size);
    const size_t typeAt = out.size();
    out.insert(out.end(), type, type + 4);
    out.insert(out.end(), data, data + size);
    putBigEndian(out, uint32_t(crc32(0, out.data() + typeAt, uInt(size + 4))));
}

// Feeds `size` bytes to `z` (flush: Z_NO_FLUSH, or Z_FINISH with none), appending its output.
int deflateInto(z_stream& z, const uint8_t* data, size_t size, int flush, std::vector<uint8_t>& out) {
    std::array<uint8_t, 1 << 16> buffer;
    z.next_in = const_cast<uint8_t*>(data);
    z.avail_in = uInt(size);
    int result = Z_OK;
    do {
        z.next_out = buffer.data();
        z.avail_out = uInt(buffer.size());
        result = deflate(&z, flush);
        if (result == Z_STREAM_ERROR) return result;
        out.insert(out.end(), buffer.data(), buffer.data() + (buffer.size() - z.avail_out));
    } while (z.avail_out == 0 || (flush == Z_FINISH && result != Z_STREAM_END));
    return result;
}

// The zlib stream of the rows, each after its filter byte (0: none).
Result<std::vector<uint8_t>> deflateRows(uint32_t height, size_t rowBytes, const uint8_t* texels) {
    z_stream z{};
    if (deflateInit(&z, Z_BEST_SPEED) != Z_OK) return Status::error("PNG encoder: zlib could not start");
    std::vector<uint8_t> out;
    const uint8_t filter = 0;
    int result = Z_OK;
    for (uint32_t row = 0; row < height && result != Z_STREAM_ERROR; ++row) {
        result = deflateInto(z, &filter, 1, Z_NO_FLUSH, out);
        if (result != Z_STREAM_ERROR) result = deflateInto(z, texels + row * rowBytes, rowBytes, Z_NO_FLUSH, out);
    }
    if (result != Z_STREAM_ERROR) result = deflateInto(z, nullptr, 0, Z_FINISH, out);
    deflateEnd(&z);
    if (result != Z_STREAM_END) return Status::error("PNG encoder: zlib failed");
    return out;
}

}  // namespace

Result<std::vector<uint8_t>> encodePng(uint32_t width, uint32_t height, uint32_t channels,
                                       const std::vector<uint8_t>& texels) {
    static constexpr uint8_t kColourType[5] = {0, 0, 4, 2, 6};  // by channel count
    if (width == 0 || height == 0 || channels == 0 || channels > 4 ||
        texels.size() != uint64_t(width) * height * channels)
        return Status::error("PNG encoder: " + std::to_string(texels.size()) + " bytes are not " +
                             std::to_string(width) + "x" + std::to_string(height) + "x" + std::to_string(channels) +
                             " texels");
    auto data = deflateRows(height, size_t(width) * channels, texels.data());
    if (!data) return data.status();
    std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
    std::vector<uint8_t> header;
    putBigEndian(header, width);
    putBigEndian(header, height);
    header.insert(header.end(), {8, kColourType[channels], 0, 0, 0});  // depth, colour type, deflate, no filter, no interlace
    putChunk(png, "IHDR", header.data(), uint32_t(header.size()));
    // IDAT chunks of at most 1 MiB each (a chunk's length is 31 bits).
    constexpr size_t kIdatBytes = size_t(1) << 20;
    for (size_t at = 0; at < data->size(); at += kIdatBytes)
        putChunk(png, "IDAT", data->data() + at, uint32_t(std::min(kIdatBytes, data->size() - at)));
    putChunk(png, "IEND", nullptr, 0);
    return png;
}

}  // namespace vastray::import
