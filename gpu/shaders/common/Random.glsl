// core/Random.h in GLSL, bit for bit: counter-based random numbers keyed by (pixel, sample,
// bounce, dimension, seed). docs/RENDERING.md specifies them.
#ifndef VASTRAY_RANDOM_GLSL
#define VASTRAY_RANDOM_GLSL

const uint kDimPixelX = 0u;
const uint kDimPixelY = 1u;
const uint kDimDirectionU = 2u;
const uint kDimDirectionV = 3u;
const uint kDimRoulette = 4u;
const uint kDimLightPick = 5u;
const uint kDimLightU = 6u;
const uint kDimLightV = 7u;
const uint kDimLobe = 8u;
const uint kDimPunctual = 9u;
const uint kDimEmitter = 10u;
const uint kDimEmitterPick = 11u;
const uint kDimEmitterKeep = 12u;
const uint kDimEmitterU = 13u;
const uint kDimEmitterV = 14u;
const uint kDimAlpha = 15u;

uint pcgHash(uint v) {
    const uint state = v * 747796405u + 2891336453u;
    const uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

uint randomBits(uint pixel, uint sampleIndex, uint bounce, uint dimension, uint seed) {
    uint h = pcgHash(seed);
    h = pcgHash(h ^ pixel);
    h = pcgHash(h ^ sampleIndex);
    h = pcgHash(h ^ bounce);
    return pcgHash(h ^ dimension);
}

// Uniform in [0, 1): the top 24 bits times 2^-24 (exact, never 1).
float randomFloat(uint pixel, uint sampleIndex, uint bounce, uint dimension, uint seed) {
    return float(randomBits(pixel, sampleIndex, bounce, dimension, seed) >> 8u) * (1.0 / 16777216.0);
}

#endif  // VASTRAY_RANDOM_GLSL
