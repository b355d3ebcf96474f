#include "vastray/core/MaterialTextures.h"

#include <cmath>
#include <cstring>

namespace vastray {

const char* textureSlotName(TextureSlot slot) {
    switch (slot) {
        case TextureSlot::BaseColor: return "baseColorTexture";
        case TextureSlot::MetallicRoughness: return "metallicRoughnessTexture";
        case TextureSlot::Normal: return "normalTexture";
        case TextureSlot::Emissive: return "emissiveTexture";
        case TextureSlot::Occlusion: return "occlusionTexture";
        case TextureSlot::Clearcoat: return "clearcoatTexture";
        case TextureSlot::ClearcoatRoughness: return "clearcoatRoughnessTexture";
    }
    return "unknown texture";
}

TextureEncoding slotEncoding(TextureSlot slot) {
    return slot == TextureSlot::BaseColor || slot == TextureSlot::Emissive ? TextureEncoding::Srgb
                                                                            : TextureEncoding::Linear;
}

UvTransform khrTextureTransform(float offsetU, float offsetV, float rotation, float scaleU, float scaleV) {
    // The ratified extension's GLSL: mat3(cos, -sin, 0, sin, cos, 0, 0, 0, 1), column-major.
    const float c = std::cos(rotation), s = std::sin(rotation);
    return {c * scaleU, s * scaleV, offsetU, -s * scaleU, c * scaleV, offsetV};
}

std::string imageSignatureExtension(const std::vector<uint8_t>& bytes) {
    static const uint8_t png[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
    static const uint8_t ktx2[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
    if (bytes.size() >= 8 && std::memcmp(bytes.data(), png, 8) == 0) return ".png";
    if (bytes.size() >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF) return ".jpg";
    if (bytes.size() >= 12 && std::memcmp(bytes.data(), ktx2, 12) == 0) return ".ktx2";
    return "";
}

}  // namespace vastray
