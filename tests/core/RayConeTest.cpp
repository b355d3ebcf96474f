// Ray cones (core/RayCone.h, docs/RENDERING.md "Texture level of detail"): the spread a scattering
// event adds, a triangle's world area per UV area, a map's level under its UV transform, and the
// camera's pixel angle.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "vastray/core/Camera.h"
#include "vastray/core/RayCone.h"
#include "vastray/core/Sampling.h"

namespace vastray {
namespace {

TEST(RayCone, DiffuseScatteringAddsTheWholeSpreadAndSharperLobesLess) {
    EXPECT_FLOAT_EQ(scatterSpread(1.0f / kPi, kConeScatterSpread), kConeScatterSpread);
    EXPECT_FLOAT_EQ(scatterSpread(0.2f / kPi, kConeScatterSpread), kConeScatterSpread);  // a cosine lobe's tail
    EXPECT_FLOAT_EQ(scatterSpread(10.0f / kPi, kConeScatterSpread), 0.1f * kConeScatterSpread);
    EXPECT_FLOAT_EQ(scatterSpread(0.0f, kConeScatterSpread), kConeScatterSpread);
    EXPECT_FLOAT_EQ(scatterSpread(std::numeric_limits<float>::infinity(), kConeScatterSpread), kConeScatterSpread);
    EXPECT_FLOAT_EQ(scatterSpread(std::nanf(""), kConeScatterSpread), kConeScatterSpread);
    EXPECT_EQ(scatterSpread(10.0f, 0.0f), 0.0f) << "--texture-lod finest adds nothing";
}

TEST(RayCone, AConeWidensAlongItsRayAndKeepsItsWidthAtAScatteringEvent) {
    const RayCone camera{0.0f, 0.01f};
    EXPECT_FLOAT_EQ(coneWidthAt(camera, 3.0f), 0.03f);
    const RayCone bounced = scatterCone(camera, 3.0f, 1.0f / kPi, kConeScatterSpread);
    EXPECT_FLOAT_EQ(bounced.width, 0.03f);
    EXPECT_FLOAT_EQ(bounced.spread, 0.01f + kConeScatterSpread);
    EXPECT_FLOAT_EQ(coneWidthAt(bounced, 2.0f), 0.03f + 2.0f * (0.01f + kConeScatterSpread));
}

TEST(RayCone, WorldAreaPerUvAreaOfATriangle) {
    // Legs 2 and 3 in the world, 0.5 and 0.25 in UV: world cross 6, UV cross 0.125.
    EXPECT_FLOAT_EQ(worldPerUvArea({0, 0, 0}, {2, 0, 0}, {0, 3, 0}, {0.0f, 0.0f}, {0.5f, 0.0f}, {0.0f, 0.25f}), 48.0f);
    // Mirrored UVs: the same area.
    EXPECT_FLOAT_EQ(worldPerUvArea({0, 0, 0}, {2, 0, 0}, {0, 3, 0}, {0.0f, 0.0f}, {-0.5f, 0.0f}, {0.0f, 0.25f}), 48.0f);
    // UVs on a line, or not finite: 0 (level 0).
    EXPECT_EQ(worldPerUvArea({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.0f, 0.0f}, {1.0f, 1.0f}, {2.0f, 2.0f}), 0.0f);
    EXPECT_EQ(worldPerUvArea({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.0f, 0.0f}, {std::nanf(""), 0.0f}, {0.0f, 1.0f}), 0.0f);
}

TEST(RayCone, AMapsLevelFollowsItsSizeAndUvTransform) {
    // A 256 x 256 map on a unit square (world per UV area 1): a cone 1/256 wide head-on is one
    // texel (level 0); twice as wide, level 1; a UV transform scaling by 2 shows each texel half as
    // wide, one level more; at 60 degrees the footprint stretches by 2, one level more.
    const MapFootprint texel{1.0f, 1.0f / 256.0f, 1.0f}, twoTexels{1.0f, 2.0f / 256.0f, 1.0f};
    EXPECT_NEAR(mapLod(kIdentityUvTransform, 256, 256, texel), 0.0f, 1e-5f);
    EXPECT_NEAR(mapLod(kIdentityUvTransform, 256, 256, twoTexels), 1.0f, 1e-5f);
    EXPECT_NEAR(mapLod({2, 0, 0.3f, 0, 2, 0.1f}, 256, 256, texel), 1.0f, 1e-5f);
    EXPECT_NEAR(mapLod({0, -2, 0, 2, 0, 0}, 256, 256, texel), 1.0f, 1e-5f) << "turned: the same area";
    EXPECT_NEAR(mapLod(kIdentityUvTransform, 256, 256, {1.0f, 1.0f / 256.0f, -0.5f}), 1.0f, 1e-5f);
    EXPECT_NEAR(mapLod(kIdentityUvTransform, 512, 128, texel), 0.0f, 1e-5f) << "the texel area decides";
    EXPECT_EQ(mapLod(kIdentityUvTransform, 256, 256, {0.0f, 1.0f, 1.0f}), 0.0f) << "UVs of no area: level 0";
    EXPECT_EQ(mapLod(kIdentityUvTransform, 256, 256, {1.0f, 0.0f, 1.0f}), 0.0f) << "no cone: level 0";
}

TEST(RayCone, ACameraRaysSpreadIsAPixelsAngle) {
    Camera camera;
    camera.fovYDegrees = 90.0f;  // tan(45 deg) = 1: the image plane 2 high at distance 1
    EXPECT_NEAR(CameraRays(camera, 160, 100).coneSpread(), 2.0f / 100.0f, 1e-7f);
    camera.fovYDegrees = 45.0f;
    EXPECT_NEAR(CameraRays(camera, 100, 200).coneSpread(), 2.0f * std::tan(22.5f * kPi / 180.0f) / 200.0f, 1e-7f);
}

TEST(RayCone, ModesAreNamed) {
    EXPECT_STREQ(textureLodModeName(TextureLodMode::Cone), "cone");
    EXPECT_STREQ(textureLodModeName(TextureLodMode::Finest), "finest");
}

}  // namespace
}  // namespace vastray
