// The counter-based generator is a specification (docs/RENDERING.md): the GPU port must
// reproduce these exact words, so the values are pinned, not just "looks random".
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <utility>

#include "vastray/core/Random.h"
#include "vastray/core/RayOffset.h"
#include "vastray/core/Sampling.h"

namespace vastray {
namespace {

TEST(Random, PcgHashMatchesTheSpecification) {
    // Computed from the formula in docs/RENDERING.md by an independent Python script.
    EXPECT_EQ(pcgHash(0u), 129708002u);
    EXPECT_EQ(pcgHash(1u), 2831084092u);
    EXPECT_EQ(pcgHash(0xFFFFFFFFu), 3861530882u);
}

TEST(Random, KeyedBitsMatchTheSpecification) {
    EXPECT_EQ(randomBits({0, 0, 0}, 0, 0), 920646579u);
    EXPECT_EQ(randomBits({123, 4, 2}, 3, 7), 1189489015u);
}

TEST(Random, EveryKeyFieldChangesTheNumber) {
    const RandomKey base{10, 3, 1};
    const uint32_t reference = randomBits(base, 2, 5);
    EXPECT_NE(randomBits({11, 3, 1}, 2, 5), reference);
    EXPECT_NE(randomBits({10, 4, 1}, 2, 5), reference);
    EXPECT_NE(randomBits({10, 3, 2}, 2, 5), reference);
    EXPECT_NE(randomBits(base, 3, 5), reference);
    EXPECT_NE(randomBits(base, 2, 6), reference);
}

TEST(Random, FloatsAreUniformInTheUnitInterval) {
    // 100k draws: the mean of U[0,1) has standard error 1/sqrt(12 * 1e5) ~ 9e-4; 5 sigma.
    double sum = 0;
    constexpr uint32_t kCount = 100000;
    for (uint32_t i = 0; i < kCount; ++i) {
        const float u = randomFloat({i, 0, 0}, 0, 1);
        ASSERT_GE(u, 0.0f);
        ASSERT_LT(u, 1.0f);
        sum += u;
    }
    EXPECT_NEAR(sum / kCount, 0.5, 5 * 9.2e-4);
}

// A wall's normal has z = +0 or -0 depending on how its corners are ordered; the frame (and so
// every bounce direction) must be the same for both.
TEST(Sampling, FrameIgnoresTheSignOfZero) {
    for (const Vec3f n : {Vec3f{1, 0, 0}, Vec3f{0, 1, 0}, Vec3f{0, -1, 0}, normalize(Vec3f{0.6f, -0.8f, 0})}) {
        const Frame plus = frameAround({n.x, n.y, 0.0f}), minus = frameAround({n.x, n.y, -0.0f});
        for (const auto& [a, b] : {std::pair{plus.tangent, minus.tangent}, std::pair{plus.bitangent, minus.bitangent}}) {
            EXPECT_EQ(a.x, b.x);
            EXPECT_EQ(a.y, b.y);
            EXPECT_EQ(a.z, b.z);
        }
        EXPECT_NEAR(dot(plus.tangent, n), 0.0f, 1e-6f);
        EXPECT_NEAR(dot(plus.bitangent, n), 0.0f, 1e-6f);
        EXPECT_NEAR(dot(plus.tangent, plus.bitangent), 0.0f, 1e-6f);
    }
}

TEST(Sampling, CosineDirectionsAreUnitAndAboveTheSurface) {
    const Vec3f normal = normalize({0.3f, -0.8f, 0.52f});
    const Frame frame = frameAround(normal);
    double cosineSum = 0;
    for (uint32_t i = 0; i < 20000; ++i) {
        const Vec3f d =
            frame.toWorld(cosineHemisphere(randomFloat({i, 0, 0}, 2, 0), randomFloat({i, 0, 0}, 3, 0)));
        ASSERT_NEAR(length(d), 1.0f, 1e-5f);  // float rounding of an orthonormal basis
        ASSERT_GE(dot(d, normal), -1e-6f);
        cosineSum += dot(d, normal);
    }
    // E[cos] under a cosine-weighted pdf is 2/3; std of cos is sqrt(1/2 - 4/9) ~ 0.236,
    // so the mean of 20k has standard error 1.7e-3; tolerance 5 sigma.
    EXPECT_NEAR(cosineSum / 20000, 2.0 / 3.0, 5 * 1.7e-3);
}

TEST(RayOffset, MovesByUlpsAwayFromTheOriginAndAbsolutelyNearIt) {
    const Vec3f n{0, 0, 1};
    const Vec3f far = offsetRayOrigin({1000, 1000, 1000}, n);
    EXPECT_EQ(far.x, 1000.0f);
    EXPECT_GT(far.z, 1000.0f);
    EXPECT_EQ(far.z, std::nextafter(1000.0f, 2000.0f) + 255 * (std::nextafter(1000.0f, 2000.0f) - 1000.0f));
    const Vec3f nearOrigin = offsetRayOrigin({0, 0, 0}, n);
    EXPECT_FLOAT_EQ(nearOrigin.z, 1.0f / 65536.0f);
    const Vec3f negative = offsetRayOrigin({0, 0, -1000}, n);
    EXPECT_GT(negative.z, -1000.0f);  // towards +z even for negative coordinates
}

}  // namespace
}  // namespace vastray
