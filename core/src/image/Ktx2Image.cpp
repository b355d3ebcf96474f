// describeKtx2Image and the KTX2 reader behind decodeRgba8Image(".ktx2") (vastray/core/ImageFile.h):
// level 0 of an uncompressed 8-bit format, stored as it is or Zstandard-supercompressed, or of
// Basis Universal (Ktx2Basis.h), as RGBA8 texels. No OpenImageIO: the module is not loaded.
#include "Ktx2Image.h"

#include <zstd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

#include "Ktx2Basis.h"
#include "Ktx2File.h"

namespace vastray {
namespace {

using ktx2::Container;

bool isBasis(const Container& c) {
    return c.vkFormat == ktx2::kUndefined &&
           (c.supercompression == ktx2::kBasisLz || c.colorModel == ktx2::kColorModelUastc);
}

bool readable(const Container& c) {
    if (isBasis(c)) return c.supercompression != ktx2::kZlib;
    return ktx2::texelBytes(c.vkFormat) != 0 && (c.supercompression == ktx2::kNone || c.supercompression == ktx2::kZstandard);
}

std::string unreadableReason(const Container& c) {
    if (c.supercompression == ktx2::kZlib) return "supercompressionScheme 3 (ZLIB) is not read";
    if (ktx2::texelBytes(c.vkFormat) == 0) return ktx2::formatName(c) + " is not read";
    return "supercompressionScheme " + std::to_string(c.supercompression) + " with " + ktx2::formatName(c) +
           " is not read";
}

// Level 0's lengths against the `expected` bytes its sides give (texels, or UASTC's 16-byte
// blocks), before anything is allocated for it: the uncompressed length, and the stored length
// (none) or the size a Zstandard frame records.
Status checkLevelLengths(const std::string& name, const Container& c, const std::vector<uint8_t>& bytes,
                         uint64_t expected, const std::string& what) {
    const std::string at = name + ": KTX2 level 0 ";
    if (c.levelUncompressedLength != expected)
        return Status::error(at + "uncompressed byte length " + std::to_string(c.levelUncompressedLength) +
                             " is not the " + std::to_string(expected) + " of " + what);
    if (c.supercompression == ktx2::kNone) {
        if (c.levelLength != expected)
            return Status::error(at + "byte length " + std::to_string(c.levelLength) + " is not its uncompressed " +
                                 std::to_string(expected) + " (supercompression none)");
        return Status::ok();
    }
    const unsigned long long frameSize = ZSTD_getFrameContentSize(bytes.data() + c.levelOffset, c.levelLength);
    if (frameSize == ZSTD_CONTENTSIZE_ERROR)
        return Status::error(at + "is not a Zstandard frame (supercompressionScheme 2)");
    if (frameSize != ZSTD_CONTENTSIZE_UNKNOWN && frameSize != expected)
        return Status::error(at + "Zstandard frame inflates to " + std::to_string(frameSize) + " bytes, not the " +
                             std::to_string(expected) + " its uncompressed byte length gives");
    return Status::ok();
}

// Level 0 of an uncompressed format, its supercompression undone: exactly width x height texels.
Result<std::vector<uint8_t>> levelZeroTexels(const std::string& name, const Container& c,
                                             const std::vector<uint8_t>& bytes) {
    const uint64_t expected = uint64_t(c.width) * c.height * ktx2::texelBytes(c.vkFormat);
    VASTRAY_TRY(checkLevelLengths(name, c, bytes, expected,
                                  std::to_string(c.width) + "x" + std::to_string(c.height) + " " +
                                      ktx2::formatName(c) + " texels"));
    const uint8_t* stored = bytes.data() + c.levelOffset;
    if (c.supercompression == ktx2::kNone) return std::vector<uint8_t>(stored, stored + expected);
    std::vector<uint8_t> texels(expected);
    const size_t inflated = ZSTD_decompress(texels.data(), texels.size(), stored, c.levelLength);
    if (ZSTD_isError(inflated))
        return Status::error(name + ": KTX2 level 0 Zstandard data does not inflate to its " + std::to_string(expected) +
                             " bytes: " + ZSTD_getErrorName(inflated));
    if (inflated != expected)
        return Status::error(name + ": KTX2 level 0 Zstandard data inflates to " + std::to_string(inflated) +
                             " bytes, not the " + std::to_string(expected) + " its uncompressed byte length gives");
    return texels;
}

// What the transcoder is handed is first checked here: a UASTC level of exactly its blocks (the
// transcoder would allocate any uncompressed length below 2 GiB before inflating), an ETC1S
// level of uncompressed length 0 (its sizes are in the global data).
Status checkBasisLevel(const std::string& name, const Container& c, const std::vector<uint8_t>& bytes) {
    if (c.levelCount == 0) return Status::error(name + ": KTX2 levelCount 0 (mips to be generated) with Basis Universal data");
    if (c.supercompression == ktx2::kBasisLz) {
        if (c.levelUncompressedLength != 0)
            return Status::error(name + ": KTX2 level 0 uncompressed byte length " +
                                 std::to_string(c.levelUncompressedLength) + " is not 0 (BasisLZ)");
        return Status::ok();
    }
    const uint64_t blocks = uint64_t((c.width + 3) / 4) * ((c.height + 3) / 4);
    return checkLevelLengths(name, c, bytes, blocks * 16, std::to_string(blocks) + " UASTC blocks");
}

// `channels` bytes a texel to RGBA through the KTXswizzle (absent: Vulkan's identity mapping, in
// which a missing G or B reads 0 and a missing alpha 1), rows and columns flipped to KTXorientation "rd".
Rgba8Image toRgba8(const Container& c, const std::vector<uint8_t>& texels, uint32_t channels) {
    Rgba8Image image;
    image.width = c.width;
    image.height = c.height;
    image.texels.resize(uint64_t(c.width) * c.height * 4);
    const bool flipX = c.orientation[0] == 'l', flipY = c.orientation[1] == 'u';
    for (uint32_t y = 0; y < c.height; ++y) {
        for (uint32_t x = 0; x < c.width; ++x) {
            const uint64_t from = uint64_t(flipY ? c.height - 1 - y : y) * c.width + (flipX ? c.width - 1 - x : x);
            const uint8_t* s = texels.data() + from * channels;
            const uint8_t source[4] = {s[0], channels > 1 ? s[1] : uint8_t(0), channels > 2 ? s[2] : uint8_t(0),
                                       channels > 3 ? s[3] : uint8_t(255)};
            uint8_t* d = image.texels.data() + (uint64_t(y) * c.width + x) * 4;
            for (int k = 0; k < 4; ++k) {
                const char w = c.swizzle[size_t(k)];
                d[k] = w == '0' ? 0 : w == '1' ? 255 : source[w == 'r' ? 0 : w == 'g' ? 1 : w == 'b' ? 2 : 3];
            }
        }
    }
    return image;
}

}  // namespace

Result<Ktx2Description> describeKtx2Image(const std::string& name, const std::vector<uint8_t>& bytes) {
    auto c = ktx2::readContainer(name, bytes);
    if (!c) return c.status();
    Ktx2Description d;
    d.format = ktx2::formatName(*c);
    d.readable = readable(*c);
    d.srgb = c->transferFunction == ktx2::kTransferSrgb;
    return d;
}

Result<Rgba8Image> decodeKtx2Image(const std::string& name, const std::vector<uint8_t>& bytes, uint64_t maxPixels) {
    auto c = ktx2::readContainer(name, bytes);
    if (!c) return c.status();
    if (!readable(*c)) return Status::error(name + ": KTX2 " + unreadableReason(*c));
    if (uint64_t(c->width) * c->height > maxPixels)
        return Status::error(name + ": " + std::to_string(c->width) + "x" + std::to_string(c->height) +
                             " pixels is more than the " + std::to_string(maxPixels) + " a texture may have");
    if (isBasis(*c)) {
        VASTRAY_TRY(checkBasisLevel(name, *c, bytes));
        auto rgba = ktx2::transcodeBasis(name, bytes);
        if (!rgba) return rgba.status();
        if (rgba->size() != uint64_t(c->width) * c->height * 4)
            return Status::error(name + ": KTX2 Basis Universal level 0 transcodes to " + std::to_string(rgba->size() / 4) +
                                 " texels, not " + std::to_string(c->width) + "x" + std::to_string(c->height));
        return toRgba8(*c, *rgba, 4);
    }
    auto texels = levelZeroTexels(name, *c, bytes);
    if (!texels) return texels.status();
    return toRgba8(*c, *texels, ktx2::texelBytes(c->vkFormat));
}

Result<Rgba8Image> readKtx2Image(const std::string& path, uint64_t maxPixels) {
    std::ifstream file(path, std::ios::binary);
    if (!file) return Status::error(path + ": cannot read: " + std::strerror(errno));
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    if (file.bad()) return Status::error(path + ": cannot read: " + std::strerror(errno));
    return decodeKtx2Image(path, bytes, maxPixels);
}

}  // namespace vastray
