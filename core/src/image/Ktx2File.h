#pragma once
// KTX 2.0 containers (Khronos KTX File Format Specification 2.0): the identifier, header, index,
// level index, data format descriptor (DFD) and key/value data, read and checked against the
// file's size before any texel is touched. Only what a 2D texture's level 0 needs is kept; the
// renderer makes its own mips. Ktx2Image.cpp turns level 0 into RGBA8 texels.
#include <cstdint>
#include <string>
#include <vector>

#include "vastray/core/Result.h"

namespace vastray::ktx2 {

// vkFormat values (Vulkan's VkFormat) of the uncompressed formats read here.
enum VkFormat : uint32_t {
    kUndefined = 0,  // Basis Universal (ETC1S with BasisLZ, or UASTC)
    kR8Unorm = 9,
    kR8Srgb = 15,
    kR8G8Unorm = 16,
    kR8G8Srgb = 22,
    kR8G8B8Unorm = 23,
    kR8G8B8Srgb = 29,
    kR8G8B8A8Unorm = 37,
    kR8G8B8A8Srgb = 43,
};

enum Supercompression : uint32_t { kNone = 0, kBasisLz = 1, kZstandard = 2, kZlib = 3 };

// DFD colour models (Khronos Data Format Specification) of Basis Universal's two formats.
constexpr uint8_t kColorModelEtc1s = 163;
constexpr uint8_t kColorModelUastc = 166;
constexpr uint8_t kTransferSrgb = 2;

struct Container {
    uint32_t vkFormat = 0, typeSize = 0, width = 0, height = 0, levelCount = 0, supercompression = 0;
    // Level 0's bytes as stored (supercompressed or not) and its uncompressed length.
    uint64_t levelOffset = 0, levelLength = 0, levelUncompressedLength = 0;
    uint8_t colorModel = 0, transferFunction = 0;
    // Key/value data read here: "KTXswizzle" ("rgba" when absent) and "KTXorientation" ("rd").
    std::string swizzle = "rgba", orientation = "rd";
};

// Checks the container and returns what level 0 needs. Errors name `name` and the field ("image
// 2 ('x.ktx2') of model.gltf: KTX2 level 0 byte length 99 exceeds the file's 50 bytes"): a wrong
// identifier, a header, index or level index past the end of the file, sides of 0 or beyond
// kMaxTextureSide, a 1D, 3D, array (more than one layer) or cube map texture, more levels than
// the sides allow, an unknown supercompression scheme, a DFD or key/value data that lies outside
// the file or does not parse, a KTXswizzle or KTXorientation value not of the specification.
Result<Container> readContainer(const std::string& name, const std::vector<uint8_t>& bytes);

// Bytes per texel of an uncompressed format read here; 0 for any other vkFormat.
uint32_t texelBytes(uint32_t vkFormat);

// "R8G8B8A8_SRGB", "UASTC", "ETC1S", or "vkFormat 131 (BC1_RGB_UNORM_BLOCK)": what warnings call a format.
std::string formatName(const Container& c);

}  // namespace vastray::ktx2
