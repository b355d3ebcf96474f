#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

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

// A package keeps 64 bytes of a camera's name: the cut never splits a UTF-8 character.
TEST(SceneCameraName, LongNamesAreCutAtACharacterBoundary) {
    EXPECT_EQ(storedCameraName("Front"), "Front");
    EXPECT_EQ(storedCameraName(std::string(64, 'a')), std::string(64, 'a')) << "64 bytes fit the field";
    EXPECT_EQ(storedCameraName(std::string(100, 'a')), std::string(64, 'a'));
    std::string twoByte;  // "é" is 2 bytes: 32 of them end exactly at 64
    for (int i = 0; i < 50; ++i) twoByte += "\xC3\xA9";
    EXPECT_EQ(storedCameraName(twoByte), twoByte.substr(0, 64));
    std::string threeByte;  // "€" is 3 bytes: 21 of them take 63, the 22nd would straddle 64
    for (int i = 0; i < 40; ++i) threeByte += "\xE2\x82\xAC";
    EXPECT_EQ(storedCameraName(threeByte), threeByte.substr(0, 63));
    const std::string fourByte = std::string(62, 'a') + "\xF0\x9F\x8E\xA5";  // a 4-byte emoji over 62..65
    EXPECT_EQ(storedCameraName(fourByte), std::string(62, 'a'));
    EXPECT_EQ(storedCameraName(std::string("Cam\0era", 7)), "Cam") << "the field is zero-padded: a NUL ends it";
}

TEST(RenderOptions, ALongCameraNamePicksTheCameraStoredUnderItsCut) {
    const std::string longName = std::string(70, 'x') + "-left";
    std::vector<SceneCamera> cameras(3);
    cameras[0] = {"Front", {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 45}};
    cameras[1] = {storedCameraName(longName), {{5, 0, 0}, {0, 0, 0}, {0, 1, 0}, 30}};
    cameras[2] = {"Top", {{0, 5, 0.1f}, {0, 0, 0}, {0, 1, 0}, 20}};
    for (const std::string& choice : {longName, storedCameraName(longName)}) {
        RenderOptions options;
        ASSERT_TRUE(applySceneCamera(cameras, choice, options)) << choice;
        EXPECT_EQ(options.camera.fovYDegrees, 30.0f) << choice;
    }
    RenderOptions options;
    const Status unknown = applySceneCamera(cameras, std::string(70, 'y'), options);
    ASSERT_FALSE(unknown);
    EXPECT_NE(unknown.message().find("no camera of that name or index; the scene has 0 'Front', 1 '" +
                                     std::string(64, 'x') + "', 2 'Top'"),
              std::string::npos)
        << unknown.message();

    // Two names alike in their first 64 bytes are stored alike: the long name cannot say which.
    cameras[2].name = storedCameraName(std::string(70, 'x') + "-right");
    const Status ambiguous = applySceneCamera(cameras, longName, options);
    ASSERT_FALSE(ambiguous);
    EXPECT_NE(ambiguous.message().find("cameras 1 and 2 are both stored as '" + std::string(64, 'x') +
                                       "' (names are kept to 64 bytes); pick one by index"),
              std::string::npos)
        << ambiguous.message();
    ASSERT_TRUE(applySceneCamera(cameras, "2", options)) << "the index still picks either";
    EXPECT_EQ(options.camera.fovYDegrees, 20.0f);
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

// p' = [x y z 1] * M (row vectors, M row by row), then divided by w'.
std::array<float, 4> transform(const std::array<float, 16>& m, Vec3f p) {
    std::array<float, 4> out{};
    const float in[4] = {p.x, p.y, p.z, 1};
    for (int col = 0; col < 4; ++col)
        for (int k = 0; k < 4; ++k) out[col] += in[k] * m[4 * k + col];
    return out;
}

// OpenEXR's conventions: camera space left-handed with x right, y up, z the view direction and
// the eye at the origin; NDC (0, 0) the top-left corner of the frame, (1, 1) the bottom-right.
TEST(Camera, RecordedMatricesFollowOpenExrConventions) {
    const Camera camera{{1, 2, 3}, {-2, 0.5f, 1}, {0, 1, 0}, 40};
    const uint32_t width = 65, height = 33;
    RenderImage image;
    recordCamera(image, camera, width, height);
    ASSERT_TRUE(image.hasCamera);
    const auto eye = transform(image.worldToCamera, camera.eye);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(eye[a], 0, 1e-5f) << a;
    const auto target = transform(image.worldToCamera, camera.target);
    EXPECT_NEAR(target[0], 0, 1e-5f);
    EXPECT_NEAR(target[1], 0, 1e-5f);
    EXPECT_NEAR(target[2], length(camera.target - camera.eye), 1e-5f);
    const CameraRays rays(camera, width, height);
    const auto above = transform(image.worldToCamera, camera.eye + rays.up());  // up in the image: +y
    EXPECT_GT(above[1], 0);
    const auto right = transform(image.worldToCamera, camera.eye + rays.right());  // right: +x
    EXPECT_GT(right[0], 0);
    // Points along pixel rays land on those pixels in NDC, at any distance.
    for (auto [x, y, jx, jy] : {std::array<float, 4>{0, 0, 0, 0}, {64, 32, 1, 1}, {10, 20, 0.5f, 0.5f}, {40, 3, 0.25f, 0.75f}}) {
        const Ray ray = rays.primary(uint32_t(x), uint32_t(y), jx, jy);
        for (float t : {0.5f, 7.0f}) {
            const auto ndc = transform(image.worldToNdc, ray.origin + ray.direction * t);
            EXPECT_NEAR(ndc[0] / ndc[3], (x + jx) / width, 1e-5f) << x << "," << y;
            EXPECT_NEAR(ndc[1] / ndc[3], (y + jy) / height, 1e-5f) << x << "," << y;
        }
    }
}

}  // namespace
}  // namespace vastray
