// Renders whose correct answer is known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "TestRenders.h"
#include "TestScenes.h"
#include "vastray/cpu/EmbreeRenderer.h"

namespace vastray {
namespace {

using test::renderEmbree;

RenderOptions smallRender(uint32_t width, uint32_t height, uint32_t spp) {
    RenderOptions o;
    o.width = width;
    o.height = height;
    o.samplesPerPixel = spp;
    return o;
}

void lookFrom(RenderOptions& o, Vec3f eye, Vec3f target) {
    o.frameScene = false;
    o.camera.eye = eye;
    o.camera.target = target;
}

void uniformSkyNoSun(RenderOptions& o, float radiance) {
    o.environment.zenith = o.environment.horizon = o.environment.ground = {radiance, radiance, radiance};
    o.environment.sunIrradiance = {0, 0, 0};
}

TEST(AnalyticRender, UnitSphereFromDistanceThreeIsTwoAwayAtTheCentre) {
    const RenderScene sphere = test::unitSphere();
    ASSERT_GT(sphere.mesh.triangleCount(), 0u);
    RenderOptions o = smallRender(65, 65, 1);  // odd: the centre pixel's centre ray is the axis
    lookFrom(o, {0, 0, 3}, {0, 0, 0});
    o.aovs = kAovDepth | kAovPrimId | kAovNormal;
    const RenderImage image = renderEmbree(sphere, o);
    const size_t centre = 32 * 65 + 32;
    // Every vertex lies on the unit sphere, so the facet is at most 1 from the origin
    // (depth >= 2) and at least the smallest facet-plane distance h (depth <= 3 - h).
    // 1e-5 absorbs float rounding of vertices and t at this scale.
    const float h = test::minPlaneDistanceFromOrigin(sphere.mesh);
    EXPECT_GE(image.depth[centre], 2.0f - 1e-5f);
    EXPECT_LE(image.depth[centre], 3.0f - h + 1e-5f);
    EXPECT_NE(image.primId[centre], kMissPrimId);
    EXPECT_GT(image.normal[3 * centre + 2], 0.99f);  // facing the camera, along +z
    EXPECT_EQ(image.primId[0], kMissPrimId);         // corner: the sphere fills ~1/3 of the view
    EXPECT_TRUE(std::isinf(image.depth[0]));
}

// Furnace: a convex diffuse object of albedo a under a uniform sky L shows a * L. A
// bounce off a convex surface always escapes, so every sample equals a * L: the only
// error is float rounding of one product (relative 1e-6).
TEST(AnalyticRender, ConvexDiffuseSphereUnderUniformSkyShowsAlbedoTimesSky) {
    RenderScene sphere = test::unitSphere(5000);
    ASSERT_GT(sphere.mesh.triangleCount(), 0u);
    const float albedo = 0.6f, sky = 1.5f;
    sphere.mesh.materials[0].baseColor = {albedo, albedo, albedo, 1};
    RenderOptions o = smallRender(48, 48, 4);
    lookFrom(o, {0, 0.5f, 3}, {0, 0, 0});
    uniformSkyNoSun(o, sky);
    const RenderImage image = renderEmbree(sphere, o);
    uint64_t covered = 0;
    for (size_t p = 0; p < image.pixelCount(); ++p) {
        const float expected = image.alpha[p] == 1.0f ? albedo * sky : (image.alpha[p] == 0.0f ? sky : NAN);
        if (std::isnan(expected)) continue;  // silhouette pixels mix sphere and sky
        covered += image.alpha[p] == 1.0f;
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(image.rgb[3 * p + c], expected, 1e-6f * expected) << "pixel " << p;
    }
    EXPECT_GT(covered, 300u);
}

// Furnace: inside a closed diffuse sphere of emission E and albedo a, a path of at most d
// bounces collects E * (1 + a + ... + a^d) = E (1 - a^(d+1)) / (1 - a). The sun is on:
// its shadow rays must all be blocked by the closed sphere.
double insideSphereMean(uint32_t maxDepth, double* standardError) {
    RenderScene sphere = test::unitSphere(5000);
    Material& m = sphere.mesh.materials[0];
    m.baseColor = {0.5f, 0.5f, 0.5f, 1};
    m.emissive = {1, 1, 1};
    m.doubleSided = true;
    RenderOptions o = smallRender(32, 32, 8);
    lookFrom(o, {0.1f, 0.2f, 0.05f}, {0.3f, -0.2f, -1});
    o.camera.fovYDegrees = 90;
    o.maxDepth = maxDepth;
    const RenderImage image = renderEmbree(sphere, o);
    double sum = 0, sumSquares = 0;
    for (size_t p = 0; p < image.pixelCount(); ++p) {
        sum += image.rgb[3 * p];
        sumSquares += double(image.rgb[3 * p]) * image.rgb[3 * p];
    }
    const double n = double(image.pixelCount()), mean = sum / n;
    *standardError = std::sqrt(std::fmax(sumSquares / n - mean * mean, 0.0) / n);
    return mean;
}

TEST(AnalyticRender, InsideAnEmissiveSphereShallowPathsAreExact) {
    // Up to depth 2 Russian roulette never fires, so every sample is the exact sum;
    // tolerance: float rounding of a 3-term sum (1e-6 relative).
    for (uint32_t d : {0u, 1u, 2u}) {
        double se = 0;
        const double expected = (1 - std::pow(0.5, d + 1)) / 0.5;
        EXPECT_NEAR(insideSphereMean(d, &se), expected, 1e-6 * expected) << "max depth " << d;
        EXPECT_LT(se, 1e-6) << "no noise expected at depth " << d;
    }
}

TEST(AnalyticRender, InsideAnEmissiveSphereRouletteIsUnbiased) {
    // At depth 8 roulette terminates paths: the mean must match within 4 standard errors
    // of the per-pixel means (1024 pixels of 8 samples; false-failure rate ~6e-5).
    double se = 0;
    const double expected = (1 - std::pow(0.5, 9)) / 0.5;
    const double mean = insideSphereMean(8, &se);
    EXPECT_GT(se, 0.0);
    EXPECT_NEAR(mean, expected, 4 * se);
}

TEST(AnalyticRender, SingleSidedPlaneIsInvisibleFromBehindDoubleSidedIsNot) {
    for (bool doubleSided : {false, true}) {
        RenderScene scene;
        scene.mesh = test::quadFacingPlusZ(doubleSided);
        RenderOptions o = smallRender(16, 16, 1);
        lookFrom(o, {0, 0, -3}, {0, 0, 0});  // behind the quad
        o.aovs = kAovPrimId | kAovNormal;
        const RenderImage image = renderEmbree(scene, o);
        const size_t centre = 8 * 16 + 8;
        if (!doubleSided) {
            EXPECT_EQ(image.primId[centre], kMissPrimId);
            EXPECT_EQ(image.alpha[centre], 0.0f);
        } else {
            EXPECT_NE(image.primId[centre], kMissPrimId);
            EXPECT_EQ(image.alpha[centre], 1.0f);
            EXPECT_FLOAT_EQ(image.normal[3 * centre + 2], -1.0f);  // shaded with the normal facing the ray
        }
    }
}

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

TEST(AnalyticRender, BitIdenticalAcrossRunsAndThreadCounts) {
    const std::string path = test::tmpPath("city-20k.ply");
    GenerateOptions g;
    g.kind = GeneratorKind::City;
    g.triangles = 20000;
    ASSERT_TRUE(generateToPly(g, path));
    auto scene = loadRenderScene(path);
    ASSERT_TRUE(scene) << scene.message();
    RenderOptions o = smallRender(48, 40, 4);
    o.aovs = kAovDepth | kAovPrimId;
    const RenderImage first = renderEmbree(*scene, o);
    const RenderImage second = renderEmbree(*scene, o);
    o.threads = 1;
    const RenderImage single = renderEmbree(*scene, o);
    EXPECT_TRUE(sameBits(first.rgb, second.rgb));
    EXPECT_TRUE(sameBits(first.rgb, single.rgb));
    EXPECT_TRUE(sameBits(first.depth, single.depth));
    EXPECT_EQ(first.primId, single.primId);
    o.seed = 1;
    EXPECT_FALSE(sameBits(first.rgb, renderEmbree(*scene, o).rgb)) << "the seed must matter";
}

}  // namespace
}  // namespace vastray
