#pragma once
// Per-vertex shading attributes as the package stores them and every backend reads them
// (docs/RENDERING.md, "Vertex attributes"): a shading normal in 32 bits (octahedral, two
// 16-bit signed-normalized words) and a colour in 32 bits (8-bit sRGB-encoded R, G, B and
// 255). At a hit the three corners are interpolated with the hit's barycentrics and the result
// is quantized again for the hit record (the GPU keeps it in 32 bits per path): the normal with
// the same octahedral code, the colour as 10-bit linear R, G, B. shaders/common/Attributes.glsl
// is the GLSL twin of these functions. Texture coordinates are kept as two floats per vertex and
// interpolated in f32 (interpolateUv).
#include <array>
#include <cstdint>

#include "vastray/core/Vec3.h"

namespace vastray {

// A vertex without an authored normal (the geometric normal is used at hits next to it):
// both words -32768, a code encodeOctahedral never produces (it clamps to -32767).
constexpr uint32_t kNoNormal = 0x80008000u;
// A vertex without an authored colour: white.
constexpr uint32_t kWhiteColor = 0xFFFFFFFFu;

// Unit (or any non-zero, finite) vector to its octahedral code; kNoNormal for a zero or
// non-finite vector.
uint32_t encodeOctahedral(Vec3f n);
// The unit vector of a code (kNoNormal decodes to +Z; callers test for it first).
Vec3f decodeOctahedral(uint32_t code);

// 8-bit sRGB-encoded channels (as PLY files and 8-bit colour maps store them) to a packed colour.
uint32_t packSrgb8(uint8_t r, uint8_t g, uint8_t b);
// Linear [0, 1] channels (glTF COLOR_0) to a packed colour: the sRGB transfer function, rounded.
uint32_t packLinearColor(float r, float g, float b);
// A packed colour's linear RGB.
Vec3f unpackColor(uint32_t packed);

// The hit record's shading normal: the corners' normals weighted by (1 - u - v, u, v),
// normalized and encoded; kNoNormal when a corner has none or the sum vanishes.
uint32_t interpolateNormal(uint32_t n0, uint32_t n1, uint32_t n2, float u, float v);
// The hit record's colour: the corners' linear colours weighted likewise, 10 bits per channel.
uint32_t interpolateColor(uint32_t c0, uint32_t c1, uint32_t c2, float u, float v);
Vec3f unpackHitColor(uint32_t packed);

// The largest |u| or |v| an importer or the package reader accepts: far beyond any tiling a file
// uses on purpose (larger is a corrupt or hostile file), and f32 still steps by 1/16 there.
constexpr float kMaxAbsUv = 1e6f;
// The hit's texture coordinates: the corners' weighted by (1 - u - v, u, v) in f32, in exactly
// this order (w * uv0 + u * uv1 + v * uv2, no fused multiply-add; Attributes.glsl too).
std::array<float, 2> interpolateUv(std::array<float, 2> uv0, std::array<float, 2> uv1, std::array<float, 2> uv2,
                                   float u, float v);

}  // namespace vastray
