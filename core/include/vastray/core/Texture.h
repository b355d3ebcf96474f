#pragma once
// Textures as the package stores them and every backend samples them (docs/RENDERING.md,
// "Textures"): an image of 8-bit RGBA texels, mip-mapped down to 1 x 1, each level cut into
// pages of kTexturePageTexels x kTexturePageTexels texels. A page is stored with one more
// column (the texel right of its last one) and one more row (the texel below its last one), so
// that a bilinear footprint never leaves its page: the renderer fetches pages, never texels of
// two pages. What lies beyond a level's right or bottom edge is the wrap mode's texel (repeat:
// the first column or row; clamp and mirror: the last), so the wrap mode is part of a stored
// texture. A texture is addressed by page: level L's page (px, py) is page
// levels[L].firstPage + py * levels[L].pagesX + px of the texture.
//
// Sampling (sampleTexture below; shaders/common/Texture.glsl will be its GLSL twin): the wrap
// mode maps u to [0, 1] (mirror: reflected; clamp: clamped; repeat: its fraction); then
// x = u * width - 0.5, clamped to [0, width - 1] for clamp and mirror, and the footprint is
// texels floor(x) and floor(x) + 1 (repeat: floor(x) = -1 is the last texel). Colour maps
// (TextureEncoding::Srgb) are decoded to linear before filtering; alpha is always linear.
// Trilinear between the two levels around the level of detail, which ray cones give
// (textureLod).
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "vastray/core/Result.h"

namespace vastray {

constexpr uint32_t kTexturePageTexels = 128;
constexpr uint32_t kTexturePageSide = kTexturePageTexels + 1;  // with the column and row beyond
constexpr uint32_t kTexturePageBytes = kTexturePageSide * kTexturePageSide * 4;
// Largest width or height a texture may have (16,384: the largest a GPU image may have on most
// consumer GPUs, and 1 GiB of level-0 texels); its levels then number at most 15.
constexpr uint32_t kMaxTextureSide = 16384;
constexpr uint32_t kMaxTextureLevels = 15;

// glTF's sampler wrap modes (10497, 33071, 33648).
enum class TextureWrap : uint32_t { Repeat = 0, Clamp = 1, Mirror = 2 };
// How texels' RGB are encoded: Srgb for colour maps (base colour, emissive), Linear for data
// (metallic-roughness, normal, occlusion).
enum class TextureEncoding : uint32_t { Srgb = 0, Linear = 1 };

const char* textureWrapName(TextureWrap wrap);

struct TextureLevel {
    uint32_t width = 0, height = 0;
    uint32_t pagesX = 0, pagesY = 0;
    uint32_t firstPage = 0;  // of the texture
};

// The levels of a width x height texture: each level max(1, floor(previous / 2)) per axis,
// down to 1 x 1, and their pages in level order.
struct TextureLayout {
    uint32_t width = 0, height = 0;
    uint32_t levelCount = 0, pageCount = 0;
    std::array<TextureLevel, kMaxTextureLevels> levels{};
};

// Errors (a zero or larger-than-kMaxTextureSide side) name the size and the limit.
Result<TextureLayout> makeTextureLayout(uint32_t width, uint32_t height);

// The texel of a level that a stored index names: for the texel beyond a page's last column or
// row (index == size), the wrap mode's texel; any index < size is itself.
uint32_t storedTexelIndex(uint32_t index, uint32_t size, TextureWrap wrap);

// Where a bilinear footprint lies: the page (of the texture), the local coordinates of its
// upper-left texel in that page (each in [0, kTexturePageTexels - 1]) and the weights of the
// texels right of and below it.
struct TextureFootprint {
    uint32_t page = 0;
    uint32_t localX = 0, localY = 0;
    float fx = 0.0f, fy = 0.0f;
};
TextureFootprint textureFootprint(const TextureLayout& layout, uint32_t level, TextureWrap wrapS,
                                  TextureWrap wrapT, float u, float v);

// The linear value of an 8-bit sRGB-encoded channel (exact to float: a table).
float srgb8ToLinear(uint8_t value);

// The level of detail of a ray cone (Akenine-Moeller et al., "Improved Shader and Texture Level
// of Detail Using Ray Cones", JCGT 2021): 0.5 * log2(texelArea / worldArea) + log2(coneWidth /
// |cos|), where texelArea is twice the triangle's area in texels of level 0 (|uv edge cross| *
// width * height) and worldArea twice its area in world units. Degenerate inputs (a zero area,
// a grazing cosine, a zero cone) give level 0 rather than a non-finite level.
float textureLod(float texelArea, float worldArea, float coneWidth, float cosTheta);

struct TextureSample {
    float r = 0.0f, g = 0.0f, b = 0.0f, a = 0.0f;
};

// Fetches page `page` of the texture: kTexturePageBytes bytes, RGBA8 rows of kTexturePageSide
// texels.
using TexturePageFetch = std::function<const uint8_t*(uint32_t page)>;

// A texture with every page in memory (a renderer that holds the whole scene: the Embree reference).
struct DecodedTexture {
    TextureLayout layout;
    TextureWrap wrapS = TextureWrap::Repeat, wrapT = TextureWrap::Repeat;
    TextureEncoding encoding = TextureEncoding::Srgb;
    std::vector<uint8_t> pages;  // layout.pageCount * kTexturePageBytes
};

// Trilinear sample at (u, v) and level of detail `lod` (clamped to the levels there are):
// linear RGB (sRGB decoded for TextureEncoding::Srgb) and alpha in [0, 1].
TextureSample sampleTexture(const TextureLayout& layout, TextureWrap wrapS, TextureWrap wrapT,
                            TextureEncoding encoding, const TexturePageFetch& fetch, float u, float v, float lod);
TextureSample sampleTexture(const DecodedTexture& texture, float u, float v, float lod);

}  // namespace vastray
