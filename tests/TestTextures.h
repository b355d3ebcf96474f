#pragma once
// Shared by the texture tests (core, package, gpu): images of random texels.
#include <cstdint>
#include <random>
#include <vector>

#include "vastray/core/ImageFile.h"

namespace vastray::test {

// A w x h RGBA8 image of random texels, each channel `rng() & mask` (a smaller mask compresses
// better, as photographs do).
inline Rgba8Image noiseImage(uint32_t w, uint32_t h, uint32_t seed, uint8_t mask = 0xFF) {
    std::mt19937 rng(seed);
    Rgba8Image image{w, h, std::vector<uint8_t>(size_t(w) * h * 4)};
    for (uint8_t& t : image.texels) t = uint8_t(rng() & mask);
    return image;
}

}  // namespace vastray::test
