// core/NormalMap.h (docs/RENDERING.md, "Normal maps"): the UV derivatives of a triangle, the
// texel's decoding, and the bent normal's frame: +X along +u, +Y up the image (-v in glTF's
// texture space) on plain and on mirrored charts; flat texels and degenerate UVs leave the
// normal bit for bit; nothing non-finite comes out.
#include <gtest/gtest.h>

#include <cmath>

#include "vastray/core/NormalMap.h"
#include "vastray/core/VecMath.h"

namespace vastray {
namespace {

// The unit square's lower-right triangle at z = 0, its UVs as a glTF file gives the image on it
// seen from +z: u along +x, v down (the image's top row at y = 1). `mirrored`: u along -x.
UvDerivatives squareDerivatives(bool mirrored) {
    const float u0 = mirrored ? 1.0f : 0.0f, u1 = mirrored ? 0.0f : 1.0f;
    return uvDerivatives(kIdentityUvTransform, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {u0, 1}, {u1, 1}, {u1, 0});
}

TEST(NormalMap, DerivativesFollowTheUvAxes) {
    const UvDerivatives d = squareDerivatives(false);
    ASSERT_TRUE(d.valid);
    EXPECT_EQ(d.dpdu, (Vec3f{1, 0, 0}));
    EXPECT_EQ(d.dpdv, (Vec3f{0, -1, 0}));  // v grows down the image, y up the square
    // A map's UV transform scales them: u twice as fast is half the distance per unit of u.
    const UvDerivatives scaled = uvDerivatives({2, 0, 0, 0, 1, 0}, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1}, {1, 1},
                                               {1, 0});
    ASSERT_TRUE(scaled.valid);
    EXPECT_EQ(scaled.dpdu, (Vec3f{0.5f, 0, 0}));
}

TEST(NormalMap, TexelsDecodeAsGltfSays) {
    const Vec3f n = decodeNormalTexel(1.0f, 0.25f, 0.75f, 0.5f);
    EXPECT_EQ(n, (Vec3f{0.5f, -0.25f, 0.5f}));  // x and y times the scale, z not
}

TEST(NormalMap, PlusXBendsTowardsPlusUAndPlusYUpTheImage) {
    const Vec3f up{0, 0, 1};
    const float s = std::sqrt(0.5f);
    for (bool mirrored : {false, true}) {
        const UvDerivatives d = squareDerivatives(mirrored);
        const Vec3f alongU = perturbNormal(up, d, {1, 0, 1});
        const Vec3f upImage = perturbNormal(up, d, {0, 1, 1});
        // +u is +x, or -x on the mirrored chart; up the image is +y on both.
        EXPECT_NEAR(alongU.x, mirrored ? -s : s, 1e-6f) << mirrored;
        EXPECT_NEAR(alongU.y, 0.0f, 1e-6f) << mirrored;
        EXPECT_NEAR(upImage.x, 0.0f, 1e-6f) << mirrored;
        EXPECT_NEAR(upImage.y, s, 1e-6f) << mirrored;
        EXPECT_NEAR(upImage.z, s, 1e-6f) << mirrored;
    }
}

TEST(NormalMap, TheFrameIsMadeOrthogonalToTheShadingNormal) {
    // A shading normal leaning towards +x: T is dp/du minus its part along the normal, and the
    // bent normal stays unit and on the normal's side for a moderate tilt.
    const Vec3f n = normalize(Vec3f{0.3f, 0, 1});
    const Vec3f bent = perturbNormal(n, squareDerivatives(false), {0.2f, 0, 1});
    const Vec3f t = normalize(Vec3f{1, 0, 0} - n * dot(n, Vec3f{1, 0, 0}));
    const Vec3f expected = normalize(t * 0.2f + n);
    EXPECT_NEAR(length(bent), 1.0f, 1e-6f);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(bent[c], expected[c], 1e-6f) << c;
}

TEST(NormalMap, AFlatTexelLeavesTheNormalBitForBit) {
    const Vec3f n = normalize(Vec3f{0.1f, -0.7f, 0.3f});
    const UvDerivatives d = squareDerivatives(false);
    EXPECT_EQ(perturbNormal(n, d, {0, 0, 1}), n);
    EXPECT_EQ(perturbNormal(n, d, decodeNormalTexel(0.9f, 0.1f, 1.0f, 0.0f)), n);  // normal scale 0
    EXPECT_EQ(perturbNormal(n, d, {0, 0, 2}), n);
}

TEST(NormalMap, DegenerateUvsLeaveTheNormalAndStayFinite) {
    const Vec3f n{0, 0, 1};
    // All three corners at one UV, and three UVs on a line: no area in texture space.
    const UvDerivatives point = uvDerivatives(kIdentityUvTransform, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0.5f, 0.5f},
                                              {0.5f, 0.5f}, {0.5f, 0.5f});
    const UvDerivatives line = uvDerivatives(kIdentityUvTransform, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0},
                                             {0.5f, 0.5f}, {1, 1});
    EXPECT_FALSE(point.valid);
    EXPECT_FALSE(line.valid);
    EXPECT_EQ(perturbNormal(n, point, {1, 0, 1}), n);
    EXPECT_EQ(perturbNormal(n, line, {1, 0, 1}), n);
    // dp/du along the normal itself (a shading normal far from the triangle's): T vanishes.
    UvDerivatives along;
    along.valid = true;
    along.dpdu = {0, 0, 2};
    along.dpdv = {0, 1, 0};
    EXPECT_EQ(perturbNormal(n, along, {1, 0, 1}), n);
    // A texel that cancels the normal: the sum vanishes.
    EXPECT_EQ(perturbNormal(n, squareDerivatives(false), {0, 0, 0}), n);
    // Non-finite inputs.
    const float inf = INFINITY;
    EXPECT_FALSE(
        uvDerivatives(kIdentityUvTransform, {0, 0, 0}, {inf, 0, 0}, {1, 1, 0}, {0, 1}, {1, 1}, {1, 0}).valid);
    EXPECT_EQ(perturbNormal(n, squareDerivatives(false), {NAN, 0, 1}), n);
    // A tiny but non-zero UV area (the square's UVs times 1e-10) still bends the normal.
    const UvDerivatives tiny = uvDerivatives(kIdentityUvTransform, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1e-10f},
                                             {1e-10f, 1e-10f}, {1e-10f, 0});
    ASSERT_TRUE(tiny.valid);
    const Vec3f bent = perturbNormal(n, tiny, {1, 0, 1});
    EXPECT_NEAR(bent.x, std::sqrt(0.5f), 1e-6f);
    EXPECT_NEAR(bent.z, std::sqrt(0.5f), 1e-6f);
}

}  // namespace
}  // namespace vastray
