#pragma once
// Counter-based random numbers: every number is a pure function of
// (pixel, sample, bounce, dimension, seed), so any backend, thread count or tile order
// draws the same sequence. docs/RENDERING.md specifies it; the GLSL port must match bit
// for bit (32-bit unsigned arithmetic wraps, shifts are logical).
#include <cstdint>

namespace vastray {

// PCG-RXS-M-XS 32-bit output permutation (Jarzynski & Olano, "Hash Functions for GPU
// Rendering", JCGT 9(3), 2020). A bijection on 32-bit words.
constexpr uint32_t pcgHash(uint32_t v) {
    const uint32_t state = v * 747796405u + 2891336453u;
    const uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// What a random number is keyed by. pixel = y * width + x.
struct RandomKey {
    uint32_t pixel = 0;
    uint32_t sample = 0;
    uint32_t bounce = 0;
};

// Dimensions in use (docs/RENDERING.md): at bounce 0, 0 and 1 jitter the pixel; at every
// bounce, 2 and 3 pick the scattered (or ambient occlusion) direction, 4 decides Russian
// roulette; with an environment map, 5 picks the light of next-event estimation (sun or map,
// when both shine) and 6 and 7 the map's direction; with punctual lights, 9 picks between them
// and the sun or map, and which of them; with sampled emissive triangles, 10 picks between them
// and the other lights, 11 and 12 which triangle (the alias method's column bits and its keep
// test) and 13 and 14 the point on it; with blended materials, 15 keys each ray's coins (one per
// triangle it meets); volumes draw from 16 up.
enum RandomDimension : uint32_t {
    kDimPixelX = 0,
    kDimPixelY = 1,
    kDimDirectionU = 2,
    kDimDirectionV = 3,
    kDimRoulette = 4,
    kDimLightPick = 5,
    kDimLightU = 6,
    kDimLightV = 7,
    kDimLobe = 8,  // the metallic-roughness BSDF's choice of lobe
    kDimPunctual = 9,  // next-event estimation: a punctual light (and which), or the sun or map
    kDimEmitter = 10,      // next-event estimation: an emissive triangle, or the other lights
    kDimEmitterPick = 11,  // which triangle: the alias column (all 32 bits, randomBits)
    kDimEmitterKeep = 12,  // which triangle: the column's own, or its alias
    kDimEmitterU = 13,     // the point on it
    kDimEmitterV = 14,
    kDimAlpha = 15,  // blended materials: the key of a ray's coin per triangle (alphaRayBase)
    // Volumes: tracking takes dimensions kDimVolume, kDimVolume + 1, ... in the order it draws
    // them (free flight along the ray, then transmittance towards the light).
    kDimVolume = 16,
};

constexpr uint32_t randomBits(RandomKey key, uint32_t dimension, uint32_t seed) {
    uint32_t h = pcgHash(seed);
    h = pcgHash(h ^ key.pixel);
    h = pcgHash(h ^ key.sample);
    h = pcgHash(h ^ key.bounce);
    return pcgHash(h ^ dimension);
}

// Uniform in [0, 1): the top 24 bits scaled by 2^-24 (exact in float, never 1).
constexpr float randomFloat(RandomKey key, uint32_t dimension, uint32_t seed) {
    return float(randomBits(key, dimension, seed) >> 8u) * (1.0f / 16777216.0f);
}

}  // namespace vastray
