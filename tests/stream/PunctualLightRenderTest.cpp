// Issue 13 ("Real assets"): punctual lights (glTF KHR_lights_punctual) lit by next-event
// estimation on both backends. Closed forms: a point light of intensity I at height h over a
// Lambertian plane of albedo a shows a/pi * I/h^2 below it; a spot shows the same inside its
// inner cone and nothing outside its outer one; a directional light equals the same --sun. The
// device agrees with the Embree reference, and a streamed render equals the in-core one.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "../VolumePackageForge.h"
#include "../VolumeTestSupport.h"
#include "StreamTestSupport.h"
#include "TestTmp.h"
#include "vastray/core/VecMath.h"
#include "vastray/streamer/Generate.h"
#include "vastray/streamer/PackageBuilder.h"

namespace vastray {
namespace {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kAlbedo = 0.5f;
constexpr uint32_t kSide = 41;       // odd: the centre pixel looks straight down the axis
constexpr float kEyeHeight = 4.0f;   // the camera looks down at the plane y = 0 from here
constexpr float kFovDegrees = 60.0f;

std::string package(const std::string& name, TriangleMesh mesh) {
    return test::meshPackage("punctual-lights", name, std::move(mesh));
}

// The square [-50, 50]^2 of the plane y = 0, facing +y, white Lambertian of albedo kAlbedo.
TriangleMesh whitePlane(std::vector<PunctualLight> lights) {
    TriangleMesh mesh;
    mesh.positions = {{-50, 0, -50}, {50, 0, -50}, {50, 0, 50}, {-50, 0, 50}};
    mesh.indices = {0, 2, 1, 0, 3, 2};
    Material white{"white"};
    white.baseColor = {kAlbedo, kAlbedo, kAlbedo, 1};
    mesh.materials = {white};
    mesh.lights = std::move(lights);
    return mesh;
}

PunctualLight pointLight(float intensity, float height) {
    PunctualLight l{"bulb", LightType::Point, {1, 1, 1}, intensity};
    l.position = {0, height, 0};
    return l;
}

// Looking straight down at the plane; sky and sun off, one scattering event (the plane's
// bounces only reach the black sky).
RenderOptions topView(const std::string& path) {
    RenderOptions o;
    o.width = o.height = kSide;
    o.samplesPerPixel = 4;
    o.maxDepth = 1;
    o.frameScene = false;
    o.camera = {{0, kEyeHeight, 0}, {0, 0, 0}, {0, 0, -1}, kFovDegrees};
    o.environment.zenith = o.environment.horizon = o.environment.ground = {0, 0, 0};
    o.environment.sunIrradiance = {0, 0, 0};
    auto reader = PackageReader::open(path);
    EXPECT_TRUE(reader) << reader.message();
    if (reader) applySceneLights((*reader)->info().lights, (*reader)->info().bounds, o);
    return o;
}

// The distance from the plane's origin to where pixel (x, y)'s centre ray meets the plane.
float pixelRadius(uint32_t x, uint32_t y) {
    const float half = kEyeHeight * std::tan(kFovDegrees * kPi / 360.0f);
    const float u = ((x + 0.5f) / kSide * 2 - 1) * half, v = ((y + 0.5f) / kSide * 2 - 1) * half;
    return std::sqrt(u * u + v * v);
}
constexpr float kPixelOnPlane = 2 * 2.3094011f / kSide;  // a pixel's width on the plane

struct Images {
    RenderImage embree, device;
};
Images renderBoth(const std::string& path, const RenderOptions& o) {
    auto reference = test::renderEmbree(path, o);
    EXPECT_TRUE(reference) << reference.message();
    auto device = test::renderVulkan(path, o, 256ull << 20);
    EXPECT_TRUE(device) << device.message();
    return {reference ? std::move(*reference) : RenderImage{}, device ? std::move(*device) : RenderImage{}};
}

TEST(PunctualLightRender, PointLightOverAWhitePlaneShowsAOverPiTimesIOverHSquared) {
    const float intensity = 7.0f, height = 1.5f;
    const std::string path = package("point-over-plane", whitePlane({pointLight(intensity, height)}));
    const Images images = renderBoth(path, topView(path));
    ASSERT_EQ(images.device.rgb.size(), size_t(3 * kSide * kSide));
    // The only light: next-event estimation picks it every time, so a sample is exact but for
    // the jitter within the pixel (r <= 0.08: radiance falls by (1 + r^2/h^2)^-1.5, 0.5 % at
    // most) and float rounding. Tolerance 0.6 %.
    const float expected = kAlbedo / kPi * intensity / (height * height);
    const size_t centre = 3 * (kSide / 2 * kSide + kSide / 2);
    for (const RenderImage* image : {&images.embree, &images.device})
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(image->rgb[centre + c], expected, 0.006f * expected);
    // Off the axis, the inverse-square law and the cosine: a/pi * I h / (h^2 + r^2)^1.5 for the
    // pixel centre, within the pixel's spread of radii.
    for (uint32_t x : {0u, 10u, 30u}) {
        const float r = pixelRadius(x, kSide / 2), spread = 0.5f * kPixelOnPlane;
        auto at = [&](float radius) { return kAlbedo / kPi * intensity * height / std::pow(height * height + radius * radius, 1.5f); };
        const float value = images.embree.rgb[3 * (kSide / 2 * kSide + x)];
        EXPECT_LE(value, at(std::max(0.0f, r - spread)) * 1.001f) << "pixel " << x;
        EXPECT_GE(value, at(r + spread) * 0.999f) << "pixel " << x;
    }
    std::printf("point light: centre %.6f (Embree), %.6f (device), expected %.6f\n", images.embree.rgb[centre],
                images.device.rgb[centre], expected);
    EXPECT_LE(test::relativeRmse(images.device.rgb, images.embree.rgb), 1e-4);
}

TEST(PunctualLightRender, SpotLightIsThePointLightInsideItsInnerConeAndDarkOutsideItsOuter) {
    const float intensity = 5.0f, height = 1.0f, inner = 0.3f, outer = 0.5f;
    PunctualLight spot = pointLight(intensity, height);
    spot.type = LightType::Spot;
    spot.direction = {0, -1, 0};
    spot.innerConeAngle = inner, spot.outerConeAngle = outer;
    const std::string spotPath = package("spot-over-plane", whitePlane({spot}));
    const std::string pointPath = package("point-over-plane-spot", whitePlane({pointLight(intensity, height)}));
    const Images spotImages = renderBoth(spotPath, topView(spotPath));
    const Images pointImages = renderBoth(pointPath, topView(pointPath));
    // A pixel's samples land within 0.75 pixel widths of its centre's radius.
    const float margin = 0.75f * kPixelOnPlane;
    uint32_t inside = 0, outside = 0;
    for (uint32_t y = 0; y < kSide; ++y)
        for (uint32_t x = 0; x < kSide; ++x) {
            const float r = pixelRadius(x, y);
            const size_t i = 3 * (size_t(y) * kSide + x);
            if (r + margin < height * std::tan(inner)) {
                ++inside;  // the cone's falloff is exactly 1 there: the same floats as the point light
                EXPECT_EQ(spotImages.embree.rgb[i], pointImages.embree.rgb[i]) << x << "," << y;
                EXPECT_EQ(spotImages.device.rgb[i], pointImages.device.rgb[i]) << x << "," << y;
            } else if (r - margin > height * std::tan(outer)) {
                ++outside;
                EXPECT_EQ(spotImages.embree.rgb[i], 0.0f) << x << "," << y;
                EXPECT_EQ(spotImages.device.rgb[i], 0.0f) << x << "," << y;
            }
        }
    EXPECT_GT(inside, 8u);
    EXPECT_GT(outside, 1000u);
}

// A city lit by the default sun's colour: once as --sun DIR,I, once as a directional light of
// colour kSunTint and intensity I shining along -DIR. Both backends give the same floats either
// way (the light's irradiance and direction are the sun's, bit for bit).
TEST(PunctualLightRender, DirectionalLightEqualsTheSameSun) {
    auto generated = generateMesh({GeneratorKind::City, 20000, 3});
    ASSERT_TRUE(generated) << generated.message();
    const Vec3f towardsSun{0.3f, 0.8f, -0.4f};
    const float intensity = 2.5f;
    PunctualLight directional{"sun", LightType::Directional, kSunTint, intensity};
    directional.direction = normalize(towardsSun * -1.0f);
    TriangleMesh lit = *generated;
    lit.lights = {directional};
    const std::string sunPath = package("city-sun", std::move(*generated));
    const std::string lightPath = package("city-directional", std::move(lit));
    RenderOptions sun;
    sun.width = 40, sun.height = 30, sun.samplesPerPixel = 2, sun.maxDepth = 3;
    sun.environment.sunDirection = towardsSun;
    for (int c = 0; c < 3; ++c) sun.environment.sunIrradiance[c] = kSunTint[c] * intensity;
    RenderOptions light = sun;
    light.environment.sunIrradiance = {0, 0, 0};
    auto reader = PackageReader::open(lightPath);
    ASSERT_TRUE(reader) << reader.message();
    applySceneLights((*reader)->info().lights, (*reader)->info().bounds, light);
    const Images bySun = renderBoth(sunPath, sun), byLight = renderBoth(lightPath, light);
    ASSERT_FALSE(bySun.embree.rgb.empty());
    EXPECT_EQ(std::memcmp(bySun.embree.rgb.data(), byLight.embree.rgb.data(), bySun.embree.rgb.size() * 4), 0);
    ASSERT_EQ(bySun.device.rgb.size(), byLight.device.rgb.size());
    EXPECT_EQ(std::memcmp(bySun.device.rgb.data(), byLight.device.rgb.data(), bySun.device.rgb.size() * 4), 0);
}

// Every kind of light with the sun and the sky: the device agrees with the Embree reference
// (the tolerance of the other cross-backend tests: the device's sqrt, division and cos round
// differently in the last bits) and a render through two chunk slots equals the in-core one.
TEST(PunctualLightRender, DeviceAgreesWithEmbreeAndStreamsTheSame) {
    auto generated = generateMesh({GeneratorKind::City, 20000, 5});
    ASSERT_TRUE(generated) << generated.message();
    TriangleMesh mesh = std::move(generated).value();
    const Aabb box = mesh.bounds();
    const Vec3f centre = (box.lo + box.hi) * 0.5f, size = box.hi - box.lo;
    PunctualLight directional{"moon", LightType::Directional, {0.6f, 0.7f, 1.0f}, 0.5f};
    directional.direction = normalize(Vec3f{-0.5f, -1, 0.3f});
    PunctualLight bulb = pointLight(4.0f * size.y * size.y, 0);
    bulb.position = centre + Vec3f{0.1f * size.x, 0.3f * size.y, 0};
    PunctualLight spot = bulb;
    spot.type = LightType::Spot, spot.color = {1, 0.6f, 0.3f};
    spot.position = centre + Vec3f{-0.2f * size.x, 0.8f * size.y, 0.1f * size.z};
    spot.direction = {0, -1, 0}, spot.innerConeAngle = 0.3f, spot.outerConeAngle = 0.7f;
    mesh.lights = {directional, bulb, spot};
    const std::string path = package("city-lights", std::move(mesh));
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    RenderOptions o;
    o.width = 48, o.height = 36, o.samplesPerPixel = 2, o.maxDepth = 3;
    applySceneLights((*reader)->info().lights, (*reader)->info().bounds, o);
    const Images images = renderBoth(path, o);
    ASSERT_FALSE(images.device.rgb.empty());
    const double error = test::relativeRmse(images.device.rgb, images.embree.rgb);
    std::printf("punctual lights: device vs Embree relative RMSE %.2e\n", error);
    EXPECT_LE(error, 1e-3);
    RenderOptions unlit = o;
    unlit.lights.reset();
    auto withoutLights = test::renderEmbree(path, unlit);
    ASSERT_TRUE(withoutLights) << withoutLights.message();
    EXPECT_GT(test::relativeRmse(withoutLights->rgb, images.embree.rgb), 0.05) << "the lights change the image";
    test::expectTwoSlotRenderEquals(path, o, 0, images.device, (*reader)->info().chunks.size());
}

// A fog cube seen against black (no sky, no sun, the only triangle behind the camera) with a
// point light above it: every pixel's light is the point light scattered in the fog (next-event
// estimation from a point in a volume, its shadow ray through the fog up to the light). Both
// backends agree within the volume tests' tolerance (5e-3: the device's exp and division round
// differently, and a tracking step that falls within them takes another turn), and without the
// light the image is black.
TEST(PunctualLightRender, FogScattersAPointLightOnBothBackends) {
    VolumeMaterial fog;
    fog.albedo = {0.9f, 0.9f, 0.8f};
    fog.anisotropy = 0.3f;
    fog.densityScale = 0.6f;  // an optical depth of about 1 across the cube at density 0.8
    Volume cube = test::makeVolume({0, 0, 0}, {15, 15, 15},
                                   [](int32_t i, int32_t, int32_t k) { return 0.6f + 0.4f * float((i / 4 + k / 4) % 2); },
                                   0.125f, {-1, -1, -1}, fog);
    TriangleMesh mesh = test::farTriangle(50.0f);
    mesh.lights = {pointLight(6.0f, 1.6f)};
    const std::string path = test::writeVolumePackage("punctual-lights", "fog-point", std::move(mesh), {std::move(cube)});
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    auto volumes = (*reader)->readVolumes();
    ASSERT_TRUE(volumes) << volumes.message();
    RenderOptions o;
    o.width = o.height = 16, o.samplesPerPixel = 16, o.maxDepth = 2;
    o.frameScene = false;
    o.camera = {{0, 0, 6}, {0, 0, 0}, {0, 1, 0}, 30.0f};
    o.environment.zenith = o.environment.horizon = o.environment.ground = {0, 0, 0};
    o.environment.sunIrradiance = {0, 0, 0};
    o.volumes = *volumes;
    applySceneLights((*reader)->info().lights, (*reader)->info().bounds, o);
    const Images images = renderBoth(path, o);
    ASSERT_FALSE(images.device.rgb.empty());
    double sum = 0;
    for (float v : images.embree.rgb) sum += v;
    EXPECT_GT(sum / double(images.embree.rgb.size()), 0.01) << "the fog scatters the light";
    const double error = test::relativeRmse(images.device.rgb, images.embree.rgb);
    std::printf("fog and a point light: device vs Embree relative RMSE %.2e\n", error);
    EXPECT_LE(error, 5e-3);
    RenderOptions dark = o;
    dark.lights.reset();
    auto unlit = test::renderEmbree(path, dark);
    ASSERT_TRUE(unlit) << unlit.message();
    for (float v : unlit->rgb) ASSERT_EQ(v, 0.0f) << "no light but the point light";
}

}  // namespace
}  // namespace vastray
