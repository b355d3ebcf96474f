// A surface on a volume's face: a floor at y = 0 under a fog slab whose voxels start at y = 0, lit
// by the sun alone (docs/RENDERING.md, "Volumes"). The shadow rays of next-event estimation start
// a hair above the floor (offsetRayOrigin), just inside the slab, and their ratio tracking must
// give the same transmittance on both backends. The floor also lies on a boundary of the slab's
// brick cells, where the camera rays end a rounding error before or after it (the backends' hit
// distances differ in the last bits): tracking must draw its random numbers per tentative
// collision, not per cell. With an absorbing fog the floor's mean is the sun's Beer-Lambert
// attenuation through the slab times the Lambertian reflection.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "../VolumePackageForge.h"
#include "../VolumeTestSupport.h"
#include "StreamTestSupport.h"
#include "vastray/core/Camera.h"
#include "vastray/core/Random.h"
#include "vastray/core/Sampling.h"
#include "vastray/core/VecMath.h"

namespace vastray {
namespace {

constexpr float kFloorAlbedo = 0.5f;
constexpr float kSun = 3.0f;

// A Lambertian plane y = 0 over [-20, 20]^2.
TriangleMesh floorPlane() {
    TriangleMesh mesh;
    mesh.positions = {{-20, 0, -20}, {20, 0, -20}, {20, 0, 20}, {-20, 0, 20}};
    mesh.indices = {0, 2, 1, 0, 3, 2};
    Material m{"floor"};
    m.baseColor = {kFloorAlbedo, kFloorAlbedo, kFloorAlbedo, 1.0f};
    mesh.materials.push_back(m);
    return mesh;
}

// An absorbing fog slab of voxels 0..15 x 0..5 x 0..15 (a checkerboard of densities 0.6 and 1.0,
// voxels of 0.125) whose lowest voxels lie at y = lift.
Volume fogSlab(float lift) {
    VolumeMaterial fog;
    fog.albedo = {0, 0, 0};
    fog.anisotropy = 0.0f;
    fog.densityScale = 0.8f;
    return test::makeVolume({0, 0, 0}, {15, 5, 15},
                            [](int32_t i, int32_t, int32_t k) { return 0.6f + 0.4f * float((i / 4 + k / 4) % 2); },
                            0.125f, {-1, lift, -1}, fog);
}

struct FaceScene {
    std::string path;
    RenderOptions options;
};

FaceScene faceScene(const std::string& name, float lift, uint32_t samples) {
    FaceScene s;
    s.path = test::writeVolumePackage("volume-face", name, floorPlane(), {fogSlab(lift)});
    auto reader = PackageReader::open(s.path);
    EXPECT_TRUE(reader) << reader.message();
    auto volumes = (*reader)->readVolumes();
    EXPECT_TRUE(volumes) << volumes.message();
    RenderOptions& o = s.options;
    o.width = o.height = 16, o.samplesPerPixel = samples, o.maxDepth = 1;
    o.frameScene = false;
    o.camera = {{0, 0.5f, 3}, {0, 0.3f, 0}, {0, 1, 0}, 40.0f};
    o.environment.zenith = o.environment.horizon = o.environment.ground = {0, 0, 0};
    o.environment.sunIrradiance = {kSun, kSun, kSun};
    o.volumes = *volumes;
    return s;
}

struct Images {
    RenderImage device, embree;
};

Images renderBoth(const FaceScene& s) {
    Images images;
    auto device = test::renderVulkan(s.path, s.options, 256ull << 20);
    EXPECT_TRUE(device) << device.message();
    auto embree = test::renderEmbree(s.path, s.options);
    EXPECT_TRUE(embree) << embree.message();
    if (device && embree) images = {std::move(device).value(), std::move(embree).value()};
    return images;
}

// The extinction's integral along the world segment origin + s direction, s in [0, length]: the
// midpoint rule over 4,096 steps (the trilinear density is linear between voxel planes, so the
// rule's error is far below the tolerances here).
double opticalDepth(const Volume& v, Vec3f origin, Vec3f direction, float length) {
    constexpr int kSteps = 4096;
    const auto& m = v.worldToIndex;
    const double h = double(length) / kSteps;
    double sum = 0;
    for (int i = 0; i < kSteps; ++i) {
        const Vec3f p = origin + direction * float((i + 0.5) * h);
        const Vec3f index{m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3], m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
                          m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]};
        sum += volumeDensity(v, index);
    }
    return sum * h * v.material.densityScale;
}

// What a pixel's samples give on average: for each camera ray (the renderers' jitter) that meets
// the floor, the camera ray's Beer-Lambert transmittance to the floor times the sun's through the
// slab (an absorbing fog scatters nothing in) times the Lambertian floor's albedo / pi x E cos.
double expectedPixel(const FaceScene& s, const Volume& v, uint32_t x, uint32_t y) {
    const RenderOptions& o = s.options;
    const CameraRays camera(o.camera, o.width, o.height);
    const Vec3f sun = normalize(o.environment.sunDirection);
    const float up = v.worldBounds.hi.y;  // no density above the grid
    double sum = 0;
    for (uint32_t sample = 0; sample < o.samplesPerPixel; ++sample) {
        const RandomKey key{y * o.width + x, sample, 0};
        const Ray ray = camera.primary(x, y, randomFloat(key, kDimPixelX, o.seed), randomFloat(key, kDimPixelY, o.seed));
        if (!(ray.direction.y < 0.0f)) continue;
        const float t = -ray.origin.y / ray.direction.y;
        const Vec3f floor = ray.origin + ray.direction * t;
        if (std::fabs(floor.x) > 20.0f || std::fabs(floor.z) > 20.0f) continue;
        const double tau = opticalDepth(v, ray.origin, ray.direction, t) + opticalDepth(v, floor, sun, up / sun.y);
        sum += std::exp(-tau) * (kFloorAlbedo / kPi) * kSun * sun.y;
    }
    return sum / o.samplesPerPixel;
}

// The image's mean residual against expectedPixel, in standard errors (of the residuals' mean
// over the pixels: independent pixels, each an unbiased estimate of its expectation).
double residualInStandardErrors(const FaceScene& s, const Volume& v, const RenderImage& image, double* meanValue) {
    const uint32_t n = s.options.width * s.options.height;
    std::vector<double> residual(n);
    double sum = 0, value = 0;
    for (uint32_t p = 0; p < n; ++p) {
        residual[p] = image.rgb[3 * p] - expectedPixel(s, v, p % s.options.width, p / s.options.width);
        sum += residual[p], value += image.rgb[3 * p];
    }
    const double mean = sum / n;
    double squares = 0;
    for (double r : residual) squares += (r - mean) * (r - mean);
    *meanValue = value / n;
    return mean / std::sqrt(squares / (double(n) * (n - 1)));
}

TEST(VolumeFace, ShadowRaysFromAFloorOnTheSlabsFaceAgree) {
    const FaceScene s = faceScene("on-face", 0.0f, 1);
    const Images images = renderBoth(s);
    ASSERT_FALSE(images.device.rgb.empty());
    double sum = 0;
    for (float v : images.embree.rgb) sum += v;
    EXPECT_GT(sum, 0.0) << "the sun reaches the floor through the fog";
    // The backends draw the same random numbers and should agree as without volumes (1e-7): a
    // tracking that spent a number on a sliver of a cell (the camera ray ending a rounding error
    // past the cell boundary under the floor) shifted every number after it (2.2e-1 before).
    const double error = test::relativeRmse(images.device.rgb, images.embree.rgb);
    std::printf("floor on the slab's face: device vs Embree relative RMSE %.2e\n", error);
    EXPECT_LE(error, 1e-4);
}

TEST(VolumeFace, ShadowRaysFromAFloorUnderAFloatingSlabAgree) {
    const FaceScene s = faceScene("floating", 0.25f, 1);
    const Images images = renderBoth(s);
    ASSERT_FALSE(images.device.rgb.empty());
    const double error = test::relativeRmse(images.device.rgb, images.embree.rgb);
    std::printf("floor under a floating slab: device vs Embree relative RMSE %.2e\n", error);
    EXPECT_LE(error, 1e-4);
}

// At 16 spp, the floor on the slab's face against Beer-Lambert on both backends: the mean residual
// within 4 standard errors (a false alarm about once in 16,000 runs), and the backends agree.
TEST(VolumeFace, FloorOnTheSlabsFaceIsLitByBeerLambertOnBothBackends) {
    const FaceScene s = faceScene("on-face-16", 0.0f, 16);
    const Volume& v = (*s.options.volumes)[0];
    const Images images = renderBoth(s);
    ASSERT_FALSE(images.device.rgb.empty());
    double mean = 0;
    const double embree = residualInStandardErrors(s, v, images.embree, &mean);
    std::printf("Embree: mean %.5f, residual %.2f standard errors\n", mean, embree);
    EXPECT_GT(mean, 0.05);
    EXPECT_LE(std::fabs(embree), 4.0);
    const double device = residualInStandardErrors(s, v, images.device, &mean);
    std::printf("device: mean %.5f, residual %.2f standard errors\n", mean, device);
    EXPECT_LE(std::fabs(device), 4.0);
    const double error = test::relativeRmse(images.device.rgb, images.embree.rgb);
    std::printf("16 spp: device vs Embree relative RMSE %.2e\n", error);
    EXPECT_LE(error, 1e-4);
}

}  // namespace
}  // namespace vastray
