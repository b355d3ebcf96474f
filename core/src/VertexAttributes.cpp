#include "vastray/core/VertexAttributes.h"

#include <algorithm>
#include <cmath>

#include "vastray/core/VecMath.h"

namespace vastray {
namespace {

float signNotZero(float v) { return v < 0.0f ? -1.0f : 1.0f; }

uint32_t snorm16(float v) {
    const float clamped = std::clamp(v, -1.0f, 1.0f);
    return uint32_t(int32_t(std::lround(clamped * 32767.0f))) & 0xFFFFu;
}

float fromSnorm16(uint32_t word) { return std::max(float(int16_t(uint16_t(word))) / 32767.0f, -1.0f); }

float srgbToLinear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }
float linearToSrgb(float c) { return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f; }

uint32_t unorm(float v, float scale) { return uint32_t(std::lround(std::clamp(v, 0.0f, 1.0f) * scale)); }

}  // namespace

uint32_t encodeOctahedral(Vec3f n) {
    const float sum = std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z);
    if (!(sum > 0.0f) || !std::isfinite(sum)) return kNoNormal;
    float x = n.x / sum, y = n.y / sum;
    if (n.z < 0.0f) {
        const float fx = (1.0f - std::fabs(y)) * signNotZero(x), fy = (1.0f - std::fabs(x)) * signNotZero(y);
        x = fx, y = fy;
    }
    return snorm16(x) | (snorm16(y) << 16);
}

Vec3f decodeOctahedral(uint32_t code) {
    float x = fromSnorm16(code & 0xFFFFu), y = fromSnorm16(code >> 16);
    const float z = 1.0f - std::fabs(x) - std::fabs(y);
    if (z < 0.0f) {
        const float fx = (1.0f - std::fabs(y)) * signNotZero(x), fy = (1.0f - std::fabs(x)) * signNotZero(y);
        x = fx, y = fy;
    }
    return normalize(Vec3f{x, y, z});
}

uint32_t packSrgb8(uint8_t r, uint8_t g, uint8_t b) {
    return uint32_t(r) | (uint32_t(g) << 8) | (uint32_t(b) << 16) | 0xFF000000u;
}

uint32_t packLinearColor(float r, float g, float b) {
    auto channel = [](float c) { return uint8_t(unorm(linearToSrgb(std::clamp(c, 0.0f, 1.0f)), 255.0f)); };
    return packSrgb8(channel(r), channel(g), channel(b));
}

Vec3f unpackColor(uint32_t packed) {
    return {srgbToLinear(float(packed & 0xFFu) / 255.0f), srgbToLinear(float((packed >> 8) & 0xFFu) / 255.0f),
            srgbToLinear(float((packed >> 16) & 0xFFu) / 255.0f)};
}

uint32_t interpolateNormal(uint32_t n0, uint32_t n1, uint32_t n2, float u, float v) {
    if (n0 == kNoNormal || n1 == kNoNormal || n2 == kNoNormal) return kNoNormal;
    const float w = 1.0f - u - v;
    return encodeOctahedral(decodeOctahedral(n0) * w + decodeOctahedral(n1) * u + decodeOctahedral(n2) * v);
}

uint32_t interpolateColor(uint32_t c0, uint32_t c1, uint32_t c2, float u, float v) {
    const float w = 1.0f - u - v;
    const Vec3f c = unpackColor(c0) * w + unpackColor(c1) * u + unpackColor(c2) * v;
    return unorm(c.x, 1023.0f) | (unorm(c.y, 1023.0f) << 10) | (unorm(c.z, 1023.0f) << 20);
}

std::array<float, 2> interpolateUv(std::array<float, 2> uv0, std::array<float, 2> uv1, std::array<float, 2> uv2,
                                   float u, float v) {
    const float w = 1.0f - u - v;
    std::array<float, 2> out;
    for (int i = 0; i < 2; ++i) {
        // Separate roundings: the GLSL twin's `precise` products and sums round the same way.
        const float a = w * uv0[i], b = u * uv1[i], c = v * uv2[i];
        const float ab = a + b;
        out[i] = ab + c;
    }
    return out;
}

Vec3f unpackHitColor(uint32_t packed) {
    return {float(packed & 1023u) / 1023.0f, float((packed >> 10) & 1023u) / 1023.0f,
            float((packed >> 20) & 1023u) / 1023.0f};
}

}  // namespace vastray
