#pragma once
// Integer hashing and a small PRNG written out here so that generated scenes are identical
// on every machine and standard library (std::*_distribution and std::rand are not).
// Only +, -, *, / and sqrt are used on floats afterwards: all are correctly rounded in IEEE
// arithmetic, and ISO C++ mode (-std=c++20) keeps GCC from contracting them into FMAs.
#include <cstdint>

#include "vastray/core/Vec3.h"

namespace vastray::gen {

// splitmix64 finalizer: a bijective avalanche mix of 64 bits.
inline uint64_t mix64(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

inline uint64_t hashCombine(uint64_t a, uint64_t b) {
    return mix64(a ^ (mix64(b) + 0x9E3779B97F4A7C15ull + (a << 6) + (a >> 2)));
}

// splitmix64 stream; seeded per element (triangle, box) so each element is independent of
// how many draws its predecessors needed.
class Rng {
public:
    explicit Rng(uint64_t seed) : state_(seed) {}

    uint64_t next() {
        state_ += 0x9E3779B97F4A7C15ull;
        return mix64(state_);
    }
    // Uniform in [0, 1) with 24 random bits: every value is exactly representable.
    float uniform01() { return static_cast<float>(next() >> 40) * 0x1p-24f; }
    // Uniform in (0, 1]: safe to divide by.
    float uniformOpen01() { return static_cast<float>((next() >> 40) + 1) * 0x1p-24f; }
    float uniform(float lo, float hi) { return lo + (hi - lo) * uniform01(); }
    // A point uniform in [-1, 1)^3 on a 2^-20 grid, from a single draw (3 x 21 bits): the
    // soup needs four of these per triangle, and one mix per point halves its cost.
    Vec3f cubePoint() {
        uint64_t bits = next();
        auto coordinate = [](uint64_t b) { return static_cast<float>(b & 0x1FFFFF) * 0x1p-20f - 1.0f; };
        return {coordinate(bits >> 43), coordinate(bits >> 22), coordinate(bits >> 1)};
    }

private:
    uint64_t state_;
};

}  // namespace vastray::gen
