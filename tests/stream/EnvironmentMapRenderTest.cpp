// `--environment` (issue "Real assets"): a latitude-longitude map lights the path integrator,
// importance sampled with MIS, on the device and in the Embree reference alike. Checked against
// the closed form (a convex Lambertian sphere under a constant sky reflects albedo x sky), the
// two backends against each other, a streamed render against the in-core one, and the map's
// device bytes against the budget.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "StreamTestSupport.h"
#include "TestTmp.h"
#include "vastray/core/EnvironmentMap.h"
#include "vastray/core/PathShading.h"
#include "vastray/core/Sampling.h"
#include "vastray/streamer/Generate.h"
#include "vastray/streamer/PackageBuilder.h"

namespace vastray {
namespace {

// A generated mesh's package; `material` (when given) replaces every material (names kept).
std::string package(const std::string& name, GeneratorKind kind, uint64_t triangles,
                    const Material* material = nullptr) {
    return test::generatedMaterialPackage("environment", name, kind, triangles, material);
}

std::shared_ptr<const EnvironmentMap> constantMap(float r, float g, float b) {
    return test::constantEnvironmentMap("constant", 8, 4, r, g, b);
}

// A sky with a horizon, a dark ground and a small bright sun-like spot: the case importance
// sampling is for.
std::shared_ptr<const EnvironmentMap> skyMap() {
    const uint32_t w = 64, h = 32;
    std::vector<float> r(w * h), g(w * h), b(w * h);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            const uint32_t i = y * w + x;
            const float v = (y + 0.5f) / h;
            r[i] = y < h / 2 ? 0.3f + 0.5f * (1 - v) : 0.2f;
            g[i] = y < h / 2 ? 0.4f + 0.4f * (1 - v) : 0.18f;
            b[i] = y < h / 2 ? 0.8f : 0.15f;
            if (x >= 9 && x <= 11 && y >= 5 && y <= 7) r[i] = 200, g[i] = 180, b[i] = 150;
        }
    auto map = makeEnvironmentMap("sky", w, h, r, g, b);
    EXPECT_TRUE(map) << map.message();
    return *map;
}

// side x side pixels, 32 spp, depth 3, lit by a constant map of (r, g, b) alone.
RenderOptions constantSkyRender(uint32_t side, float r, float g, float b) {
    RenderOptions o;
    o.width = o.height = side;
    o.samplesPerPixel = 32;
    o.maxDepth = 3;
    o.environment.sunIrradiance = {0, 0, 0};
    o.environment.map = constantMap(r, g, b);
    return o;
}

// Under a constant sky L, every point of a convex Lambertian body of albedo a reflects a * L (its
// whole hemisphere sees the sky); the background is L.
TEST(EnvironmentMapRender, ConvexSphereUnderAConstantSkyReflectsAlbedoTimesSky) {
    const std::string path = package("sphere", GeneratorKind::Sphere, 20000);
    const RenderOptions o = constantSkyRender(48, 0.5f, 1.0f, 2.0f);
    const float sky[3] = {0.5f, 1.0f, 2.0f}, albedo = 0.8f;
    for (const char* backend : {"vulkan", "embree"}) {
        auto image = std::string(backend) == "vulkan" ? test::renderVulkan(path, o, 256ull << 20) : test::renderEmbree(path, o);
        ASSERT_TRUE(image) << backend << ": " << image.message();
        double sum[3] = {0, 0, 0}, squares[3] = {0, 0, 0};
        uint64_t hits = 0;
        for (size_t p = 0; p < image->alpha.size(); ++p) {
            if (image->alpha[p] == 0.0f) {
                for (int c = 0; c < 3; ++c) ASSERT_EQ(image->rgb[3 * p + c], sky[c]) << backend << " background pixel " << p;
                continue;
            }
            if (image->alpha[p] < 1.0f) continue;  // the silhouette: partly background
            ++hits;
            for (int c = 0; c < 3; ++c) sum[c] += image->rgb[3 * p + c], squares[c] += double(image->rgb[3 * p + c]) * image->rgb[3 * p + c];
        }
        ASSERT_GT(hits, 300u);
        for (int c = 0; c < 3; ++c) {
            // Every hit pixel has the same expectation: their spread gives the mean's standard error.
            const double mean = sum[c] / double(hits);
            const double standardError = std::sqrt(std::max(0.0, squares[c] / double(hits) - mean * mean) / double(hits));
            std::printf("%s: channel %d mean %.5f, expected %.5f, standard error %.5f\n", backend, c, mean,
                        double(albedo * sky[c]), standardError);
            EXPECT_LT(standardError, 0.005 * albedo * sky[c]);
            EXPECT_NEAR(mean, albedo * sky[c], 4 * standardError) << backend << " channel " << c;
        }
    }
}

// The white furnace with the metallic-roughness BSDF (core/Microfacet.h): a convex white sphere
// under a constant sky of 1 reflects 1 at every pixel, whatever its roughness and metalness (the
// lost multiple scattering and the dielectric's diffuse share are compensated; the BSDF alone is
// checked within 1 % by MicrofacetTest). Both backends, next-event estimation of the map with MIS.
TEST(EnvironmentMapRender, GlossyWhiteSpheresInAWhiteFurnaceVanish) {
    const RenderOptions o = constantSkyRender(40, 1.0f, 1.0f, 1.0f);
    for (const auto& [metallic, roughness] : {std::pair{1.0f, 0.3f}, std::pair{0.0f, 0.6f}, std::pair{1.0f, 1.0f}}) {
        Material white;
        white.baseColor = {1, 1, 1, 1};
        white.metallic = metallic, white.roughness = roughness, white.specular = 1.0f;
        const std::string path = package("furnace", GeneratorKind::Sphere, 20000, &white);
        for (const char* backend : {"vulkan", "embree"}) {
            auto image = std::string(backend) == "vulkan" ? test::renderVulkan(path, o, 256ull << 20)
                                                          : test::renderEmbree(path, o);
            ASSERT_TRUE(image) << backend << ": " << image.message();
            double sum = 0, squares = 0;
            uint64_t hits = 0;
            for (size_t p = 0; p < image->alpha.size(); ++p) {
                if (image->alpha[p] < 1.0f) continue;
                const double v = (double(image->rgb[3 * p]) + image->rgb[3 * p + 1] + image->rgb[3 * p + 2]) / 3.0;
                ++hits, sum += v, squares += v * v;
            }
            ASSERT_GT(hits, 200u);
            const double mean = sum / double(hits);
            const double standardError = std::sqrt(std::max(0.0, squares / double(hits) - mean * mean) / double(hits));
            std::printf("%s metallic %.1f roughness %.1f: mean %.5f, standard error %.5f\n", backend, metallic, roughness,
                        mean, standardError);
            EXPECT_NEAR(mean, 1.0, 0.01 + 4 * standardError) << backend << " metallic " << metallic << " roughness " << roughness;
        }
    }
}

const std::string& city();

// Glossy materials on both backends: the same BSDF steps give the same image (up to the device's
// float rounding), with the sky and sun and with a map and the sun; a metal is not the Lambertian
// image.
TEST(EnvironmentMapRender, GlossyDeviceAgreesWithEmbree) {
    Material gold;
    gold.baseColor = {1.0f, 0.76f, 0.33f, 1.0f};
    gold.metallic = 0.8f, gold.roughness = 0.35f, gold.specular = 1.0f;
    const std::string path = package("glossy-city", GeneratorKind::City, 20000, &gold);
    for (const bool withMap : {false, true}) {
        RenderOptions o;
        o.width = 48, o.height = 36;
        o.samplesPerPixel = 4;
        o.maxDepth = 3;
        if (withMap) o.environment.map = skyMap(), o.environment.mapRotationDegrees = 37.0f;
        auto reference = test::renderEmbree(path, o);
        ASSERT_TRUE(reference) << reference.message();
        auto device = test::renderVulkan(path, o, 256ull << 20);
        ASSERT_TRUE(device) << device.message();
        const double rmse = test::relativeRmse(device->rgb, reference->rgb);
        std::printf("%s: glossy device vs Embree relative RMSE %.2e\n", withMap ? "map and sun" : "sky and sun", rmse);
        EXPECT_LE(rmse, 1e-2);
        auto lambertian = test::renderVulkan(city(), o, 256ull << 20);
        ASSERT_TRUE(lambertian) << lambertian.message();
        EXPECT_GT(test::relativeRmse(lambertian->rgb, device->rgb), 0.1);
    }
}

// A 20k-triangle city in 64 KiB chunks (built once), and a small render of it.
const std::string& city() {
    static const std::string path = package("city", GeneratorKind::City, 20000);
    return path;
}
RenderOptions cityRender(uint32_t spp) {
    RenderOptions o;
    o.width = 48, o.height = 36;
    o.samplesPerPixel = spp;
    o.maxDepth = 3;
    return o;
}

TEST(EnvironmentMapRender, DeviceAgreesWithEmbreeAndStreamsTheSame) {
    const std::string& path = city();
    RenderOptions o = cityRender(4);
    o.aovs = kAovPrimId;
    o.environment.map = skyMap();  // and the default sun: next-event estimation picks one of the two
    o.environment.mapRotationDegrees = 37.0f;
    auto reference = test::renderEmbree(path, o);
    ASSERT_TRUE(reference) << reference.message();
    StreamingStats stats;
    auto device = test::renderVulkan(path, o, 256ull << 20, &stats);
    ASSERT_TRUE(device) << device.message();
    EXPECT_GT(stats.chunksTotal, 4u);
    const double rmse = test::relativeRmse(device->rgb, reference->rgb);
    std::printf("device vs Embree beauty relative RMSE %.2e\n", rmse);
    EXPECT_LE(rmse, 2e-3);
    // The map lights the picture: without it (the sky and sun) the image is another.
    RenderOptions plain = o;
    plain.environment.map.reset();
    auto unlit = test::renderVulkan(path, plain, 256ull << 20);
    ASSERT_TRUE(unlit) << unlit.message();
    EXPECT_GT(test::relativeRmse(unlit->rgb, device->rgb), 0.1);
    // Turning the map turns its sun-like spot: another image.
    RenderOptions unturned = o;
    unturned.environment.mapRotationDegrees = 0.0f;
    auto straight = test::renderVulkan(path, unturned, 256ull << 20);
    ASSERT_TRUE(straight) << straight.message();
    EXPECT_GT(test::relativeRmse(straight->rgb, device->rgb), 0.1);

    const uint64_t reserved = gpu::environmentBytes(o.environment);
    EXPECT_GE(reserved, o.environment.map->deviceBytes());
    test::expectTwoSlotRenderEquals(path, o, reserved, *device, stats.chunksTotal);
}

// A map of the analytic sky (core/PathShading.h's skyRadiance, which depends on the height of a
// direction only: 1,024 rows) lights a city as the sky does, although the map is sampled by next-
// event estimation with MIS and the sky only found by bounces: two estimators of one integral,
// occlusion included.
TEST(EnvironmentMapRender, AMapOfTheSkyLightsAsTheSkyDoes) {
    const std::string& path = city();
    RenderOptions o = cityRender(32);
    o.environment.sunIrradiance = {0, 0, 0};
    const uint32_t w = 4, h = 1024;
    std::vector<float> planes[3];
    for (auto& plane : planes) plane.resize(w * h);
    for (uint32_t y = 0; y < h; ++y) {
        const float theta = kPi * (y + 0.5f) / h;
        const Vec3f sky = skyRadiance(o.environment, {std::sin(theta), std::cos(theta), 0});
        for (uint32_t x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) planes[c][y * w + x] = sky[c];
    }
    auto map = makeEnvironmentMap("sky rows", w, h, planes[0], planes[1], planes[2]);
    ASSERT_TRUE(map) << map.message();
    auto bySky = test::renderVulkan(path, o, 256ull << 20);
    ASSERT_TRUE(bySky) << bySky.message();
    o.environment.map = *map;
    auto byMap = test::renderVulkan(path, o, 256ull << 20);
    ASSERT_TRUE(byMap) << byMap.message();
    double skySum = 0, mapSum = 0;
    for (size_t p = 0; p < byMap->alpha.size(); ++p) {
        if (byMap->alpha[p] == 0.0f) continue;  // the background: the sky itself
        for (int c = 0; c < 3; ++c) skySum += bySky->rgb[3 * p + c], mapSum += byMap->rgb[3 * p + c];
    }
    std::printf("lit by the sky %.2f, by its map %.2f\n", skySum, mapSum);
    EXPECT_NEAR(mapSum / skySum, 1.0, 0.01);
    EXPECT_GT(test::relativeRmse(byMap->rgb, bySky->rgb), 1e-3) << "the two estimators differ pixel by pixel";
}

TEST(EnvironmentMapRender, TheBudgetCountsTheMap) {
    const std::string& path = city();
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    RenderOptions o;
    o.environment.map = skyMap();
    const ChunkAttributes a = requiredAttributes((*reader)->info(), o);
    const uint64_t reserved = gpu::environmentBytes(o.environment);
    auto without = gpu::planPool((*reader)->info(), a, 1ull << 30);
    auto with = gpu::planPool((*reader)->info(), a, 1ull << 30, true, gpu::kWaveShareOutOfCore, 0, reserved);
    ASSERT_TRUE(without && with);
    EXPECT_EQ(with->minimumBytes, without->minimumBytes + reserved);
    EXPECT_EQ(with->reservedBytes, reserved);
    EXPECT_LE(with->totalBytes, 1ull << 30);
    auto refused = gpu::planPool((*reader)->info(), a, with->minimumBytes - 1, true, gpu::kWaveShareOutOfCore, 0, reserved);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.message().find("environment map"), std::string::npos) << refused.message();
    // A backend that kept nothing for the map refuses to render with one.
    auto scene = StreamingScene::open(**reader, a, StreamingOptions{}, [&](const PackageInfo& info, const ChunkAttributes& attributes) {
        return gpu::createVulkanChunkBackend(test::sharedVulkanDevice(), info, attributes, 256ull << 20);
    });
    ASSERT_TRUE(scene) << scene.message();
    auto unreserved = (*scene)->render(o);
    ASSERT_FALSE(unreserved);
    EXPECT_NE(unreserved.message().find("environment map needs"), std::string::npos) << unreserved.message();
}

}  // namespace
}  // namespace vastray
