// Structs that cross the host/device line for textures (core/Texture.h describes the layout and
// the sampling; common/Texture.glsl is its GLSL twin), compiled both as C++ (layout checked by
// static_assert below) and as GLSL (std430, scalar members and fixed arrays only).
// GLSL needs GL_EXT_shader_explicit_arithmetic_types_int64 enabled before including this.
#ifndef VASTRAY_GPU_SHARED_TEXTURE_TYPES_H
#define VASTRAY_GPU_SHARED_TEXTURE_TYPES_H

#ifdef __cplusplus
#include <cstddef>
#include <cstdint>
namespace vastray::gpu {
using uint = uint32_t;
#endif

// A page as the pool holds it: kTexturePageSide^2 texels, one word each (R in bits 0-7, then G,
// B, A), rows of kTexturePageSide texels.
const uint kGpuTexturePageSide = 129u;
const uint kGpuTexturePageWords = 129u * 129u;
const uint kGpuTexturePageTexels = 128u;
// A page-table entry of a page the pool does not hold.
const uint kTexturePageAbsent = 0xFFFFFFFFu;
// A material's map that names no texture (core kNoTexture).
const uint kNoGpuTexture = 0xFFFFFFFFu;
const uint kMaxGpuTextureLevels = 16u;

// GpuTexture::flags: wrap S in bits 0-1, wrap T in bits 2-3 (core TextureWrap's values), bit 4
// set for linear texels (TextureEncoding::Linear), clear for sRGB.
const uint kTextureFlagLinear = 16u;

// One texture: its size, levels, and where its pages' entries start in the page table (entry
// pageTable + levelFirstPage[level] + row * pagesX + column holds the pool slot of that page, or
// kTexturePageAbsent).
struct GpuTexture {
    uint width;
    uint height;
    uint levelCount;
    uint flags;
    uint pageTable;
    uint padding0;
    uint padding1;
    uint padding2;
    uint levelFirstPage[16];
};

// texture_probe.comp: sample `queryCount` queries (a texture index, u, v, level of detail) into
// results (linear RGBA) and missing (the page-table entry of a page that was absent, or
// kTexturePageAbsent when every page was there).
struct TextureQuery {
    uint texture;
    float u;
    float v;
    float lod;
};

struct TextureProbePushConstants {
    uint64_t textures;   // GpuTexture[]
    uint64_t pageTable;  // uint[]
    uint64_t pool;       // uint[] (kGpuTexturePageWords per slot)
    uint64_t queries;    // TextureQuery[]
    uint64_t results;    // vec4[]
    uint64_t missing;    // uint[]
    uint queryCount;
    uint padding;
};

#ifdef __cplusplus
static_assert(sizeof(GpuTexture) == 96 && offsetof(GpuTexture, levelFirstPage) == 32);
static_assert(sizeof(TextureQuery) == 16);
static_assert(sizeof(TextureProbePushConstants) == 56 && sizeof(TextureProbePushConstants) <= 128,
              "128 bytes is the push-constant size every Vulkan device guarantees");
}  // namespace vastray::gpu
#endif

#endif  // VASTRAY_GPU_SHARED_TEXTURE_TYPES_H
