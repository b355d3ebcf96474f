#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "vastray/core/Camera.h"
#include "vastray/core/RenderOptions.h"
#include "vastray/core/VecMath.h"

namespace vastray {
namespace {

TEST(Camera, CentreRayOfAnOddImageGoesThroughTheTarget) {
    Camera camera{{1, 2, 3}, {-2, 0.5f, 1}, {0, 1, 0}, 40};
    const Ray ray = CameraRays(camera, 65, 33).primary(32, 16, 0.5f, 0.5f);
    const Vec3f expected = normalize(camera.target - camera.eye);
    // Unit vectors from two float computations: a few ulps apart.
    EXPECT_NEAR(ray.direction.x, expected.x, 1e-6f);
    EXPECT_NEAR(ray.direction.y, expected.y, 1e-6f);
    EXPECT_NEAR(ray.direction.z, expected.z, 1e-6f);
}

TEST(Camera, TopLeftPixelLooksUpAndLeft) {
    Camera camera{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 60};
    const Ray ray = CameraRays(camera, 64, 64).primary(0, 0, 0.5f, 0.5f);
    EXPECT_LT(ray.direction.x, 0.0f);
    EXPECT_GT(ray.direction.y, 0.0f);
}

TEST(Camera, FramingKeepsTheBoundingSphereInView) {
    Aabb box{{-1, -2, -3}, {4, 5, 6}};
    Camera camera = frameBounds(box, 45, 2.0f);
    ASSERT_TRUE(validateCamera(camera));
    const Vec3f centre = (box.lo + box.hi) * 0.5f;
    const float radius = 0.5f * length(box.extent());
    const float distance = length(camera.eye - centre);
    // The sphere's angular radius must fit half the vertical field of view.
    EXPECT_LE(std::asin(radius / distance), 0.5f * 45.0f * 3.14159265f / 180.0f);
}

TEST(Camera, RotateFromYUpTakesYOntoUpAndKeepsLengths) {
    const Vec3f v{0.4f, 0.8f, 0.3f};
    EXPECT_EQ(rotateFromYUp({0, 1, 0}, v), v);
    const Vec3f z = rotateFromYUp({0, 0, 1}, v);  // (x, y, z) -> (x, -z, y), exactly
    EXPECT_EQ(z, (Vec3f{0.4f, -0.3f, 0.8f}));
    EXPECT_EQ(rotateFromYUp({0, 0, 1}, {0, 1, 0}), (Vec3f{0, 0, 1}));
    EXPECT_EQ(rotateFromYUp({0, -1, 0}, {0, 1, 0}), (Vec3f{0, -1, 0}));
    const Vec3f up = normalize(Vec3f{1, 2, -3});
    const Vec3f y = rotateFromYUp(up, {0, 1, 0});
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(y[a], up[a], 1e-6f);
    EXPECT_NEAR(length(rotateFromYUp(up, v)), length(v), 1e-6f);
    EXPECT_NEAR(dot(rotateFromYUp(up, v), y), dot(v, Vec3f{0, 1, 0}), 1e-6f);  // angles kept
}

// Z up: the same view as Y up, turned: from above along +Z, with +Z as the camera's up.
TEST(Camera, FramingLooksDownAlongTheUpVector) {
    const Aabb box{{-1, -1, -1}, {1, 1, 1}};
    const Camera y = frameBounds(box, 45, 1.5f), z = frameBounds(box, 45, 1.5f, {0, 0, 1});
    EXPECT_EQ(z.up, (Vec3f{0, 0, 1}));
    EXPECT_EQ(z.eye, (Vec3f{y.eye.x, -y.eye.z, y.eye.y}));
    EXPECT_GT(z.eye.z, 0.0f);
    ASSERT_TRUE(validateCamera(z));
}

TEST(Camera, RejectsNanEyeEqualTargetParallelUpAndBadFov) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_FALSE(validateCamera({{nan, 0, 0}, {0, 0, 0}, {0, 1, 0}, 45}));
    EXPECT_NE(validateCamera({{1, 1, 1}, {1, 1, 1}, {0, 1, 0}, 45}).message().find("eye equals target"),
              std::string::npos);
    EXPECT_FALSE(validateCamera({{0, 5, 0}, {0, 0, 0}, {0, 1, 0}, 45}));
    EXPECT_FALSE(validateCamera({{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 180}));
    EXPECT_TRUE(validateCamera({{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 45}));
}

TEST(RenderOptions, ParsesAovsAndIntegratorsAndRejectsUnknownNames) {
    auto aovs = parseAovList("primid,depth");
    ASSERT_TRUE(aovs);
    EXPECT_EQ(*aovs, uint32_t(kAovPrimId | kAovDepth));
    EXPECT_FALSE(parseAovList("depth,colour"));
    EXPECT_FALSE(parseAovList("depth,"));
    EXPECT_TRUE(parseIntegrator("ao"));
    EXPECT_FALSE(parseIntegrator("whitted"));
}

TEST(RenderOptions, RejectsZeroAndHugeSizesAndSampleCounts) {
    RenderOptions o;
    EXPECT_TRUE(validateRenderOptions(o));
    o.width = 0;
    EXPECT_FALSE(validateRenderOptions(o));
    o.width = kMaxImageSide + 1;
    EXPECT_FALSE(validateRenderOptions(o));
    o = RenderOptions{};
    o.samplesPerPixel = 0;
    EXPECT_FALSE(validateRenderOptions(o));
    o.samplesPerPixel = kMaxSamplesPerPixel + 1;
    EXPECT_FALSE(validateRenderOptions(o));
}

}  // namespace
}  // namespace vastray
