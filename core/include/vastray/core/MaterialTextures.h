#pragma once
// The textures a material reads (docs/RENDERING.md, "Textures"): glTF's five core maps and
// KHR_materials_clearcoat's coat and coat roughness maps, each a
// texture of the scene and an affine map of the mesh's UVs (KHR_texture_transform), and the
// textures themselves as an importer finds them (an image, its wrap modes and how its texels
// are encoded). core/Texture.h says how a texture is stored and sampled.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "vastray/core/Texture.h"

namespace vastray {

// Clearcoat: KHR_materials_clearcoat's clearcoatTexture (its R channel scales the coat's weight);
// ClearcoatRoughness: its clearcoatRoughnessTexture (G scales the coat's roughness). Package
// format 13 brought those two.
enum class TextureSlot : uint32_t {
    BaseColor = 0,
    MetallicRoughness = 1,
    Normal = 2,
    Emissive = 3,
    Occlusion = 4,
    Clearcoat = 5,
    ClearcoatRoughness = 6
};
constexpr uint32_t kTextureSlotCount = 7;
constexpr uint32_t kNoTexture = 0xFFFFFFFFu;

const char* textureSlotName(TextureSlot slot);
// Colour maps are sRGB-encoded, data maps linear (glTF 2.0, "Materials").
TextureEncoding slotEncoding(TextureSlot slot);

// A UV transform's inputs as files give them (offsets, scales, rotation: KHR_texture_transform,
// MTL -s/-o, aiUVTransform) are refused beyond this (UVs that far out lose their texel
// precision long before); the matrix they make stays within kMaxUvTransformEntry (a v-up file's
// offset becomes 1 - scale - offset, assimp's pivot adds a little), which a package reader
// holds every stored transform to.
constexpr float kMaxUvTransformValue = 1e6f;
constexpr float kMaxUvTransformEntry = 4e6f;

// uv' = (m[0] u + m[1] v + m[2], m[3] u + m[4] v + m[5]).
using UvTransform = std::array<float, 6>;
constexpr UvTransform kIdentityUvTransform{1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f};

// KHR_texture_transform's translation * rotation * scale, as the ratified extension writes it
// in GLSL: rotation r turns the UVs counter-clockwise (the image clockwise) on glTF's UV axes.
UvTransform khrTextureTransform(float offsetU, float offsetV, float rotation, float scaleU, float scaleV);
inline void applyUvTransform(const UvTransform& m, float u, float v, float& outU, float& outV) {
    outU = m[0] * u + m[1] * v + m[2];
    outV = m[3] * u + m[4] * v + m[5];
}

struct TextureBinding {
    uint32_t texture = kNoTexture;  // index into the scene's textures
    UvTransform transform = kIdentityUvTransform;
};

struct MaterialTextures {
    std::array<TextureBinding, kTextureSlotCount> slots{};
    float normalScale = 1.0f;        // glTF normalTexture.scale
    float occlusionStrength = 1.0f;  // glTF occlusionTexture.strength
    bool any() const {
        for (const TextureBinding& b : slots)
            if (b.texture != kNoTexture) return true;
        return false;
    }
};

// A texture of a scene before import stores it: the image's encoded bytes (PNG, JPEG) and how
// it is sampled. Two materials that read one image with one sampler and one encoding share it.
struct TextureSource {
    std::string name;        // what errors and `info` call it: "image 2 ('bricks.png') of house.glb"
    std::string extension;   // ".png" or ".jpg": the format the bytes were recognised as
    std::vector<uint8_t> bytes;
    TextureWrap wrapS = TextureWrap::Repeat, wrapT = TextureWrap::Repeat;
    TextureEncoding encoding = TextureEncoding::Srgb;
};

// The format of an image's bytes by their signature: ".png", ".jpg", ".ktx2", or "" (unknown).
std::string imageSignatureExtension(const std::vector<uint8_t>& bytes);

}  // namespace vastray
