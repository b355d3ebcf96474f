// The per-vertex attribute codes (core/VertexAttributes.h): octahedral normals within the
// 16-bit grid's error everywhere on the sphere, the no-normal code never produced by an
// encoding, sRGB colours exact at 8 bits, and the hit record's interpolation.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "vastray/core/VecMath.h"
#include "vastray/core/VertexAttributes.h"

namespace vastray::test {
namespace {

TEST(VertexAttributes, OctahedralNormalsRoundTripWithinTheGrid) {
    std::mt19937 rng(7);
    std::normal_distribution<float> g;
    float worst = 0;
    for (int i = 0; i < 200000; ++i) {
        Vec3f n{g(rng), g(rng), g(rng)};
        if (i < 6) n = Vec3f{0, 0, 0}, n[i % 3] = i < 3 ? 1.0f : -1.0f;  // the axes, both signs
        const uint32_t code = encodeOctahedral(n);
        ASSERT_NE(code, kNoNormal);
        const Vec3f back = decodeOctahedral(code);
        EXPECT_NEAR(length(back), 1.0f, 1e-6f);
        // The angle in double (acos of a float dot product near 1 is off by ~3e-4 rad itself).
        const Vec3f e = normalize(n), c = cross(back, e);
        const double sine = std::sqrt(double(c.x) * c.x + double(c.y) * c.y + double(c.z) * c.z);
        const double cosine = double(back.x) * e.x + double(back.y) * e.y + double(back.z) * e.z;
        worst = std::max(worst, float(std::atan2(sine, cosine)));
    }
    // Two 16-bit words: about 1e-4 rad at worst (the grid's spacing over the octahedron).
    EXPECT_LT(worst, 1.5e-4f);
    EXPECT_GT(worst, 0.0f);
}

TEST(VertexAttributes, DegenerateNormalsBecomeTheNoNormalCode) {
    EXPECT_EQ(encodeOctahedral({0, 0, 0}), kNoNormal);
    EXPECT_EQ(encodeOctahedral({NAN, 1, 0}), kNoNormal);
    EXPECT_EQ(encodeOctahedral({INFINITY, 1, 0}), kNoNormal);
    // Opposite corner normals interpolate to nothing at the midpoint: no normal, not garbage.
    const uint32_t up = encodeOctahedral({0, 0, 1}), down = encodeOctahedral({0, 0, -1});
    EXPECT_EQ(interpolateNormal(up, down, down, 0.5f, 0.0f), kNoNormal);
    EXPECT_EQ(interpolateNormal(up, kNoNormal, up, 0.2f, 0.2f), kNoNormal);
}

TEST(VertexAttributes, InterpolatedNormalsAreNormalizedBlends) {
    const uint32_t x = encodeOctahedral({1, 0, 0}), y = encodeOctahedral({0, 1, 0}), z = encodeOctahedral({0, 0, 1});
    const Vec3f corner = decodeOctahedral(interpolateNormal(x, y, z, 0.0f, 0.0f));
    EXPECT_NEAR(corner.x, 1.0f, 1e-4f);
    const Vec3f middle = decodeOctahedral(interpolateNormal(x, y, z, 1.0f / 3, 1.0f / 3));
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(middle[a], 1.0f / std::sqrt(3.0f), 2e-4f);
    const Vec3f edge = decodeOctahedral(interpolateNormal(x, y, z, 0.5f, 0.0f));
    EXPECT_NEAR(edge.x, std::sqrt(0.5f), 2e-4f);
    EXPECT_NEAR(edge.y, std::sqrt(0.5f), 2e-4f);
}

TEST(VertexAttributes, ColoursAreSrgbEncodedBytes) {
    EXPECT_EQ(packSrgb8(255, 255, 255), kWhiteColor);
    const Vec3f white = unpackColor(kWhiteColor), black = unpackColor(packSrgb8(0, 0, 0));
    EXPECT_FLOAT_EQ(white.x, 1.0f);
    EXPECT_FLOAT_EQ(black.y, 0.0f);
    // sRGB 128 is linear 0.2158605 (IEC 61966-2-1).
    EXPECT_NEAR(unpackColor(packSrgb8(128, 0, 0)).x, 0.2158605f, 1e-6f);
    // Linear input (glTF COLOR_0) round-trips through the byte it encodes to.
    for (int byte = 0; byte < 256; ++byte) {
        const float linear = unpackColor(packSrgb8(uint8_t(byte), 0, 0)).x;
        EXPECT_EQ(packLinearColor(linear, 0, 0) & 0xFFu, uint32_t(byte)) << byte;
    }
}

TEST(VertexAttributes, HitColoursAreTenBitLinearBlends) {
    const uint32_t red = packSrgb8(255, 0, 0), blue = packSrgb8(0, 0, 255);
    const Vec3f mid = unpackHitColor(interpolateColor(red, blue, blue, 0.25f, 0.25f));
    EXPECT_NEAR(mid.x, 0.5f, 0.5f / 1023);
    EXPECT_NEAR(mid.y, 0.0f, 1e-6f);
    EXPECT_NEAR(mid.z, 0.5f, 0.5f / 1023);
    const Vec3f whiteHit = unpackHitColor(interpolateColor(kWhiteColor, kWhiteColor, kWhiteColor, 0.3f, 0.3f));
    EXPECT_FLOAT_EQ(whiteHit.x, 1.0f);
}

}  // namespace
}  // namespace vastray::test
