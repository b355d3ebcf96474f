#include "Ktx2File.h"

#include <algorithm>
#include <cstring>

#include "vastray/core/Texture.h"

namespace vastray::ktx2 {
namespace {

constexpr uint8_t kIdentifier[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
constexpr uint64_t kHeaderBytes = 80;      // identifier, header and index
constexpr uint64_t kLevelEntryBytes = 24;  // byteOffset, byteLength, uncompressedByteLength
// A basic DFD block: its six header words (colour model, transfer function, ...) before the samples.
constexpr uint64_t kBasicBlockBytes = 24;

uint32_t u32(const std::vector<uint8_t>& b, uint64_t at) {
    uint32_t v;
    std::memcpy(&v, b.data() + at, 4);
    return v;  // KTX2 is little endian, as are the hosts vastray runs on
}

uint64_t u64(const std::vector<uint8_t>& b, uint64_t at) {
    uint64_t v;
    std::memcpy(&v, b.data() + at, 8);
    return v;
}

// Whether [offset, offset + length) lies inside `size` bytes, without overflowing.
bool inside(uint64_t offset, uint64_t length, uint64_t size) { return offset <= size && length <= size - offset; }

std::string bytesOf(uint64_t n) { return std::to_string(n) + " bytes"; }

// An error when the region does not lie in the file: "DFD (offset 90, 44 bytes) ends past the file's 100 bytes".
Status regionInFile(const std::string& what, uint64_t offset, uint64_t length, uint64_t size) {
    if (inside(offset, length, size)) return Status::ok();
    return Status::error(what + " (offset " + std::to_string(offset) + ", " + bytesOf(length) + ") ends past the file's " +
                         bytesOf(size));
}

Status checkShape(Container& c, const std::vector<uint8_t>& b) {
    const uint32_t depth = u32(b, 28), layers = u32(b, 32), faces = u32(b, 36);
    c.width = u32(b, 20);
    c.height = u32(b, 24);
    if (c.width == 0 || c.height == 0)
        return Status::error("pixelWidth " + std::to_string(c.width) + " x pixelHeight " + std::to_string(c.height) +
                             ": a 2D texture has both sides above 0");
    if (c.width > kMaxTextureSide || c.height > kMaxTextureSide)
        return Status::error("pixelWidth " + std::to_string(c.width) + " x pixelHeight " + std::to_string(c.height) +
                             " is beyond the " + std::to_string(kMaxTextureSide) + " texels a texture side may have");
    if (depth != 0) return Status::error("pixelDepth " + std::to_string(depth) + ": a 3D texture, not a 2D one");
    if (layers > 1) return Status::error("layerCount " + std::to_string(layers) + ": an array texture, not a 2D one");
    if (faces != 1)
        return Status::error("faceCount " + std::to_string(faces) + (faces == 6 ? ": a cube map" : ": not 1") +
                             ", not a 2D texture");
    uint32_t maxLevels = 1;
    for (uint32_t side = std::max(c.width, c.height); side > 1; side /= 2) ++maxLevels;
    if (c.levelCount > maxLevels)
        return Status::error("levelCount " + std::to_string(c.levelCount) + " is more than the " +
                             std::to_string(maxLevels) + " levels a " + std::to_string(c.width) + "x" +
                             std::to_string(c.height) + " texture has");
    if (c.supercompression > kZlib)
        return Status::error("supercompressionScheme " + std::to_string(c.supercompression) +
                             " is not one of 0 (none), 1 (BasisLZ), 2 (Zstandard), 3 (ZLIB)");
    return Status::ok();
}

Status readLevelIndex(Container& c, const std::vector<uint8_t>& b) {
    const uint64_t entries = std::max<uint32_t>(c.levelCount, 1);
    VASTRAY_TRY(regionInFile("level index of " + std::to_string(entries) + " levels", kHeaderBytes,
                             entries * kLevelEntryBytes, b.size()));
    c.levelOffset = u64(b, kHeaderBytes);
    c.levelLength = u64(b, kHeaderBytes + 8);
    c.levelUncompressedLength = u64(b, kHeaderBytes + 16);
    if (c.levelLength == 0) return Status::error("level 0 byte length is 0");
    if (c.levelOffset > b.size()) return Status::error("level 0 byte offset " + std::to_string(c.levelOffset) +
                                                       " is past the file's " + bytesOf(b.size()));
    if (!inside(c.levelOffset, c.levelLength, b.size()))
        return Status::error("level 0 byte length " + std::to_string(c.levelLength) + " at offset " +
                             std::to_string(c.levelOffset) + " exceeds the file's " + bytesOf(b.size()));
    return Status::ok();
}

// The basic descriptor block's colour model and transfer function (KDFS 5: vendor 0, type 0).
Status readDfd(Container& c, const std::vector<uint8_t>& b) {
    const uint64_t offset = u32(b, 48), length = u32(b, 52);
    VASTRAY_TRY(regionInFile("DFD", offset, length, b.size()));
    if (length < 4 + kBasicBlockBytes)
        return Status::error("DFD byte length " + std::to_string(length) + " is less than the " +
                             std::to_string(4 + kBasicBlockBytes) + " of a basic descriptor block");
    const uint32_t total = u32(b, offset);
    if (total != length)
        return Status::error("DFD total size " + std::to_string(total) + " is not its byte length " + std::to_string(length));
    const uint32_t vendorAndType = u32(b, offset + 4), blockSize = u32(b, offset + 8) >> 16;
    if (vendorAndType != 0)
        return Status::error("DFD's first block is not a Khronos basic descriptor block (vendor and type word " +
                             std::to_string(vendorAndType) + ")");
    if (blockSize < kBasicBlockBytes || blockSize > length - 4)
        return Status::error("DFD basic block size " + std::to_string(blockSize) + " is outside [" +
                             std::to_string(kBasicBlockBytes) + ", " + std::to_string(length - 4) + "]");
    c.colorModel = b[offset + 12];
    c.transferFunction = b[offset + 14];
    return Status::ok();
}

Status readKeyValue(Container& c, const std::string& key, const std::string& value) {
    if (key == "KTXswizzle") {
        const bool valid = value.size() == 4 && std::all_of(value.begin(), value.end(), [](char ch) {
            return std::strchr("rgba01", ch) != nullptr && ch != '\0';
        });
        if (!valid) return Status::error("KTXswizzle '" + value + "' is not four of r, g, b, a, 0, 1");
        c.swizzle = value;
    } else if (key == "KTXorientation") {
        if (value.size() < 2 || (value[0] != 'r' && value[0] != 'l') || (value[1] != 'd' && value[1] != 'u'))
            return Status::error("KTXorientation '" + value + "' does not start with r or l, then d or u");
        c.orientation = value.substr(0, 2);
    }
    return Status::ok();
}

// Key/value entries: a 4-byte length, a NUL-terminated key, the value, padding to 4 bytes.
Status readKeyValueData(Container& c, const std::vector<uint8_t>& b) {
    const uint64_t offset = u32(b, 56), length = u32(b, 60);
    VASTRAY_TRY(regionInFile("key/value data", offset, length, b.size()));
    for (uint64_t at = offset, end = offset + length; at < end;) {
        if (end - at < 4)
            return Status::error("key/value data: entry at offset " + std::to_string(at) + " has no length");
        const uint64_t entry = u32(b, at);
        if (entry > end - at - 4)
            return Status::error("key/value data: entry of " + bytesOf(entry) + " at offset " + std::to_string(at) +
                                 " ends past the data's end at " + std::to_string(end));
        const char* text = reinterpret_cast<const char*>(b.data() + at + 4);
        const size_t keyLength = strnlen(text, entry);
        if (keyLength == entry)
            return Status::error("key/value data: the key at offset " + std::to_string(at + 4) + " has no NUL");
        std::string value(text + keyLength + 1, entry - keyLength - 1);
        while (!value.empty() && value.back() == '\0') value.pop_back();
        VASTRAY_TRY(readKeyValue(c, std::string(text, keyLength), value));
        at += std::min<uint64_t>(4 + (entry + 3) / 4 * 4, end - at);
    }
    return Status::ok();
}

Result<Container> read(const std::vector<uint8_t>& b) {
    if (b.size() < sizeof(kIdentifier) || std::memcmp(b.data(), kIdentifier, sizeof(kIdentifier)) != 0)
        return Status::error("the file does not start with the KTX 2.0 identifier");
    if (b.size() < kHeaderBytes)
        return Status::error("header and index need " + bytesOf(kHeaderBytes) + "; the file has " + bytesOf(b.size()));
    Container c;
    c.vkFormat = u32(b, 12);
    c.typeSize = u32(b, 16);
    c.levelCount = u32(b, 40);
    c.supercompression = u32(b, 44);
    VASTRAY_TRY(checkShape(c, b));
    VASTRAY_TRY(readLevelIndex(c, b));
    VASTRAY_TRY(readDfd(c, b));
    VASTRAY_TRY(readKeyValueData(c, b));
    const uint64_t sgdOffset = u64(b, 64), sgdLength = u64(b, 72);
    VASTRAY_TRY(regionInFile("supercompression global data", sgdOffset, sgdLength, b.size()));
    if (c.supercompression == kBasisLz && sgdLength == 0)
        return Status::error("supercompressionScheme 1 (BasisLZ) without supercompression global data");
    return c;
}

}  // namespace

Result<Container> readContainer(const std::string& name, const std::vector<uint8_t>& bytes) {
    auto c = read(bytes);
    if (!c) return c.status().withContext(name + ": KTX2 ");
    return c;
}

uint32_t texelBytes(uint32_t vkFormat) {
    switch (vkFormat) {
        case kR8Unorm:
        case kR8Srgb: return 1;
        case kR8G8Unorm:
        case kR8G8Srgb: return 2;
        case kR8G8B8Unorm:
        case kR8G8B8Srgb: return 3;
        case kR8G8B8A8Unorm:
        case kR8G8B8A8Srgb: return 4;
    }
    return 0;
}

std::string formatName(const Container& c) {
    switch (c.vkFormat) {
        case kR8Unorm: return "R8_UNORM";
        case kR8Srgb: return "R8_SRGB";
        case kR8G8Unorm: return "R8G8_UNORM";
        case kR8G8Srgb: return "R8G8_SRGB";
        case kR8G8B8Unorm: return "R8G8B8_UNORM";
        case kR8G8B8Srgb: return "R8G8B8_SRGB";
        case kR8G8B8A8Unorm: return "R8G8B8A8_UNORM";
        case kR8G8B8A8Srgb: return "R8G8B8A8_SRGB";
        case kUndefined:
            if (c.supercompression == kBasisLz) return "ETC1S";
            if (c.colorModel == kColorModelUastc) return "UASTC";
            return "vkFormat 0 (UNDEFINED) with DFD colour model " + std::to_string(c.colorModel);
    }
    const std::string number = "vkFormat " + std::to_string(c.vkFormat);
    if (c.vkFormat >= 131 && c.vkFormat <= 146) return number + " (a BC1-BC7 block format)";
    if (c.vkFormat >= 147 && c.vkFormat <= 156) return number + " (an ETC2/EAC block format)";
    if (c.vkFormat >= 157 && c.vkFormat <= 184) return number + " (an ASTC block format)";
    return number;
}

}  // namespace vastray::ktx2
