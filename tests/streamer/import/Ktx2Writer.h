#pragma once
// Writes KTX 2.0 files for tests: identifier, header, index, a level index, a basic DFD of one
// sample, key/value data and level 0's bytes, each field settable so that hostile files are one
// assignment away from valid ones.
#include <zstd.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

namespace vastray::test {

struct Ktx2Spec {
    uint32_t vkFormat = 43;  // R8G8B8A8_SRGB
    uint32_t typeSize = 1, width = 1, height = 1, depth = 0, layers = 0, faces = 1, levels = 1;
    uint32_t supercompression = 0;
    std::vector<uint8_t> level;      // level 0 as stored
    uint64_t uncompressedLength = 0;  // 0: level.size() (supercompression none)
    uint8_t colorModel = 1, transfer = 2;  // KHR_DF_MODEL_RGBSDA, KHR_DF_TRANSFER_SRGB
    uint8_t channelId = 0;                 // the sample's channel (UASTC: 3 = RGBA)
    std::vector<std::pair<std::string, std::string>> keyValues;
    std::vector<uint8_t> globalData;  // supercompression global data (BasisLZ)
};

// Offsets of the header fields, to forge them after writing.
namespace ktx2at {
constexpr size_t kWidth = 20, kHeight = 24, kDfdOffset = 48, kDfdLength = 52, kLevelOffset = 80, kLevelLength = 88,
                 kLevelUncompressed = 96;
}

inline void putU32(std::vector<uint8_t>& b, size_t at, uint32_t v) { std::memcpy(b.data() + at, &v, 4); }
inline void putU64(std::vector<uint8_t>& b, size_t at, uint64_t v) { std::memcpy(b.data() + at, &v, 8); }

inline std::vector<uint8_t> writeKtx2(const Ktx2Spec& s) {
    static const uint8_t id[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
    const uint32_t entries = s.levels > 0 ? s.levels : 1;
    const size_t dfdOffset = 80 + 24 * size_t(entries), dfdLength = 44;
    std::vector<uint8_t> kvd;
    for (const auto& [key, value] : s.keyValues) {
        std::vector<uint8_t> entry(key.begin(), key.end());
        entry.push_back(0);
        entry.insert(entry.end(), value.begin(), value.end());
        entry.push_back(0);
        const size_t at = kvd.size();
        kvd.resize(at + 4);
        putU32(kvd, at, uint32_t(entry.size()));
        kvd.insert(kvd.end(), entry.begin(), entry.end());
        kvd.resize((kvd.size() + 3) / 4 * 4);
    }
    const size_t kvdOffset = dfdOffset + dfdLength;
    size_t sgdOffset = (kvdOffset + kvd.size() + 7) / 8 * 8;
    size_t levelOffset = (sgdOffset + s.globalData.size() + 15) / 16 * 16;
    std::vector<uint8_t> b(levelOffset + s.level.size());
    std::memcpy(b.data(), id, 12);
    const uint32_t header[9] = {s.vkFormat, s.typeSize, s.width, s.height, s.depth, s.layers, s.faces, s.levels,
                                s.supercompression};
    for (int i = 0; i < 9; ++i) putU32(b, 12 + 4 * size_t(i), header[i]);
    putU32(b, 48, uint32_t(dfdOffset));
    putU32(b, 52, uint32_t(dfdLength));
    putU32(b, 56, kvd.empty() ? 0 : uint32_t(kvdOffset));
    putU32(b, 60, uint32_t(kvd.size()));
    putU64(b, 64, s.globalData.empty() ? 0 : sgdOffset);
    putU64(b, 72, s.globalData.size());
    for (uint32_t i = 0; i < entries; ++i) {  // every level points at level 0's bytes (only level 0 is read)
        putU64(b, 80 + 24 * size_t(i), levelOffset);
        putU64(b, 88 + 24 * size_t(i), s.level.size());
        putU64(b, 96 + 24 * size_t(i), s.uncompressedLength ? s.uncompressedLength : s.level.size());
    }
    putU32(b, dfdOffset, uint32_t(dfdLength));
    putU32(b, dfdOffset + 4, 0);                                   // Khronos vendor, basic block
    putU32(b, dfdOffset + 8, 2u | (uint32_t(dfdLength - 4) << 16));  // version 2, block size 40
    b[dfdOffset + 12] = s.colorModel;
    b[dfdOffset + 13] = 1;  // BT.709 primaries
    b[dfdOffset + 14] = s.transfer;
    b[dfdOffset + 15] = 0;
    b[dfdOffset + 16] = s.colorModel >= 160 ? 3 : 0;  // texel block 4x4 (Basis) or 1x1
    b[dfdOffset + 17] = s.colorModel >= 160 ? 3 : 0;
    b[dfdOffset + 20] = s.colorModel >= 160 ? 16 : uint8_t(s.vkFormat == 43 || s.vkFormat == 37 ? 4 : 1);
    putU32(b, dfdOffset + 28, uint32_t(s.channelId) << 24);
    if (!kvd.empty()) std::memcpy(b.data() + kvdOffset, kvd.data(), kvd.size());
    if (!s.globalData.empty()) std::memcpy(b.data() + sgdOffset, s.globalData.data(), s.globalData.size());
    if (!s.level.empty()) std::memcpy(b.data() + levelOffset, s.level.data(), s.level.size());
    return b;
}

// `texels` Zstandard-compressed into one frame that records its size.
inline std::vector<uint8_t> zstdFrame(const std::vector<uint8_t>& texels, int level = 3) {
    std::vector<uint8_t> out(ZSTD_compressBound(texels.size()));
    out.resize(ZSTD_compress(out.data(), out.size(), texels.data(), texels.size(), level));
    return out;
}

}  // namespace vastray::test
