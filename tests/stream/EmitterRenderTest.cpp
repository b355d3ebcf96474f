// Issue 13 ("Real assets"): emissive triangles are lights that next-event estimation samples, on
// both backends (docs/RENDERING.md, "Emissive triangles"). Closed form: a Lambertian plane of
// albedo a under a square lamp of radiance L, half side s at height h, shows a L F below its
// centre, F the form factor of the square from a point below its centre (four corner-rectangle
// factors). Sampled and found by chance only, both backends agree with it; sampling lowers the
// noise; the device agrees with the Embree reference; a lamp seen from behind (single-sided) is
// dark; a streamed render equals the in-core one; an emissive map's triangles are sampled too;
// beside the sun and a punctual light, and in fog, sampling keeps the expectation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>

#include "../VolumePackageForge.h"
#include "../VolumeTestSupport.h"
#include "StreamTestSupport.h"
#include "TestTextures.h"
#include "TestTmp.h"
#include "shared/WavefrontTypes.h"
#include "vastray/core/ImageFile.h"
#include "vastray/streamer/PackageBuilder.h"

namespace vastray {
namespace {

constexpr double kPiDouble = 3.14159265358979323846;
constexpr float kAlbedo = 0.5f, kHeight = 1.0f, kHalfSide = 1.0f, kRadiance = 2.0f;
constexpr uint32_t kSide = 16;

// The form factor from a point to a parallel rectangle of sides x, y with a corner straight
// above it at height 1 (Howell's catalogue, C-11), in units of the height.
double cornerFactor(double x, double y) {
    const double a = std::sqrt(1 + x * x), b = std::sqrt(1 + y * y);
    return (x / a * std::atan(y / a) + y / b * std::atan(x / b)) / (2 * kPiDouble);
}
// Below the lamp at (x, 0, z), inside its shadow: the four rectangles it cuts the lamp into.
double radianceAt(double x, double z) {
    const double s = kHalfSide, h = kHeight;
    double f = 0;
    for (double dx : {s - x, s + x})
        for (double dz : {s - z, s + z}) f += cornerFactor(dx / h, dz / h);
    return kAlbedo * kRadiance * f;
}
double expectedRadiance() { return radianceAt(0, 0); }

std::string lampPackage(const std::string& name, TriangleMesh mesh, uint64_t chunkBytes = 64 << 10) {
    return test::meshPackage("emitters", name, std::move(mesh), chunkBytes);
}

// The plane y = 0 over [-20, 20]^2 in cells x cells squares (white, albedo kAlbedo), and the
// lamp: a square of half side kHalfSide at height kHeight, single-sided, facing down (or up),
// black but for its emission.
TriangleMesh lampOverPlane(bool facingDown, uint32_t cells = 1, bool doubleSided = false) {
    TriangleMesh mesh;
    for (uint32_t j = 0; j <= cells; ++j)
        for (uint32_t i = 0; i <= cells; ++i)
            mesh.positions.push_back({-20.0f + 40.0f * i / cells, 0, -20.0f + 40.0f * j / cells});
    for (uint32_t j = 0; j < cells; ++j)
        for (uint32_t i = 0; i < cells; ++i) {
            const uint32_t v = j * (cells + 1) + i;
            mesh.indices.insert(mesh.indices.end(), {v, v + cells + 1, v + 1, v + 1, v + cells + 1, v + cells + 2});
        }
    mesh.materialIds.assign(mesh.triangleCount(), 0);
    const auto base = uint32_t(mesh.positions.size());
    const float s = kHalfSide, h = kHeight;
    mesh.positions.insert(mesh.positions.end(), {{-s, h, -s}, {s, h, -s}, {s, h, s}, {-s, h, s}});
    if (facingDown)
        mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    else
        mesh.indices.insert(mesh.indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
    mesh.materialIds.insert(mesh.materialIds.end(), {1, 1});
    Material white{"white"}, lamp{"lamp"};
    white.baseColor = {kAlbedo, kAlbedo, kAlbedo, 1};
    lamp.baseColor = {0, 0, 0, 1};
    lamp.emissive = {kRadiance, kRadiance, kRadiance};
    lamp.doubleSided = doubleSided;
    mesh.materials = {white, lamp};
    return mesh;
}

// The plane's centre under the lamp, seen at a slant from below the lamp's height through a
// narrow field; sky and sun off; one scattering event (direct light only).
constexpr Vec3f kEye{0, 0.5f, 4};
constexpr float kFovDegrees = 1.0f;
RenderOptions slantView(const std::string& path, bool sampleEmitters, uint32_t spp) {
    RenderOptions o;
    o.width = o.height = kSide;
    o.samplesPerPixel = spp;
    o.maxDepth = 1;
    o.frameScene = false;
    o.camera = {kEye, {0, 0, 0}, {0, 1, 0}, kFovDegrees};
    o.environment.zenith = o.environment.horizon = o.environment.ground = {0, 0, 0};
    o.environment.sunIrradiance = {0, 0, 0};
    if (sampleEmitters) {
        auto reader = PackageReader::open(path);
        EXPECT_TRUE(reader) << reader.message();
        if (reader) applySceneEmitters((*reader)->info().emitters, (*reader)->info().materials, o);
        EXPECT_TRUE(o.emitters) << "the package keeps its emitters";
    }
    return o;
}

// The closed form averaged over the points the pixels' centres see (the view covers about 0.07
// x 0.56 of the plane, over which the radiance falls by 1 %; the jitter within a pixel changes
// the mean by far less than the noise). The image is symmetric: the average does not depend on
// which way rows and columns run.
double expectedMean() {
    const double half = std::tan(kFovDegrees * kPiDouble / 360);
    const double ex = kEye.x, ey = kEye.y, ez = kEye.z, length = std::sqrt(ey * ey + ez * ez);
    const double fy = -ey / length, fz = -ez / length;  // forward; right is +x; up is (0, fz, -fy) turned up
    const double uy = -fz, uz = fy;
    double sum = 0;
    for (uint32_t j = 0; j < kSide; ++j)
        for (uint32_t i = 0; i < kSide; ++i) {
            const double a = ((i + 0.5) / kSide * 2 - 1) * half, b = ((j + 0.5) / kSide * 2 - 1) * half;
            const double dx = a, dy = fy + b * uy, dz = fz + b * uz;
            const double t = -ey / dy;
            sum += radianceAt(ex + t * dx, ez + t * dz);
        }
    return sum / (kSide * kSide);
}

using test::Mean;
using test::pixelMean;

// Renders options(true) and options(false) (emitters sampled, and found by chance only) on the
// device and on the Embree reference: the two device images have one expectation (their means
// within 4 combined standard errors), and each follows the reference within `tolerance` relative
// RMSE (the same random numbers, the same steps). Returns the sampled device image's mean.
Mean expectSampledAsByChance(const std::string& path, const std::function<RenderOptions(bool)>& options,
                             double tolerance, const char* what) {
    auto sampled = test::renderVulkan(path, options(true), 256ull << 20);
    auto byChance = test::renderVulkan(path, options(false), 256ull << 20);
    auto reference = test::renderEmbree(path, options(true));
    auto referenceByChance = test::renderEmbree(path, options(false));
    if (!sampled || !byChance || !reference || !referenceByChance) {
        ADD_FAILURE() << sampled.message() << byChance.message() << reference.message() << referenceByChance.message();
        return {};
    }
    const Mean s = pixelMean(*sampled), c = pixelMean(*byChance);
    const double error = test::relativeRmse(sampled->rgb, reference->rgb);
    const double chanceError = test::relativeRmse(byChance->rgb, referenceByChance->rgb);
    std::printf("%s: sampled %.5f +- %.5f, by chance %.5f +- %.5f; device against Embree, relative RMSE %.2e "
                "sampled, %.2e by chance\n",
                what, s.mean, s.standardError, c.mean, c.standardError, error, chanceError);
    EXPECT_NEAR(s.mean, c.mean, 4 * std::hypot(s.standardError, c.standardError)) << what;
    EXPECT_LE(error, tolerance) << what;
    EXPECT_LE(chanceError, tolerance) << what;
    return s;
}

TEST(EmitterRender, LampOverAPlaneShowsTheFormFactorOnBothBackends) {
    const std::string path = lampPackage("lamp", lampOverPlane(true));
    {
        auto reader = PackageReader::open(path);
        ASSERT_TRUE(reader) << reader.message();
        ASSERT_EQ((*reader)->info().emitters.size(), 2u) << "the lamp's two triangles";
        EXPECT_EQ((*reader)->info().emitters[0].material, 1u);
    }
    const double expected = expectedMean();
    const RenderOptions sampled = slantView(path, true, 64), byChance = slantView(path, false, 64);
    auto embreeSampled = test::renderEmbree(path, sampled);
    auto embreeByChance = test::renderEmbree(path, byChance);
    auto deviceSampled = test::renderVulkan(path, sampled, 256ull << 20);
    auto deviceByChance = test::renderVulkan(path, byChance, 256ull << 20);
    ASSERT_TRUE(embreeSampled && embreeByChance) << embreeSampled.message() << embreeByChance.message();
    ASSERT_TRUE(deviceSampled && deviceByChance) << deviceSampled.message() << deviceByChance.message();
    const Mean es = pixelMean(*embreeSampled), ec = pixelMean(*embreeByChance);
    const Mean ds = pixelMean(*deviceSampled), dc = pixelMean(*deviceByChance);
    std::printf("lamp: expected %.5f; Embree sampled %.5f +- %.5f, by chance %.5f +- %.5f; device sampled %.5f +- "
                "%.5f, by chance %.5f +- %.5f\n",
                expected, es.mean, es.standardError, ec.mean, ec.standardError, ds.mean, ds.standardError, dc.mean,
                dc.standardError);
    // Within 4 standard errors.
    EXPECT_NEAR(expected / expectedRadiance(), 0.99, 0.01) << "the view sees the centre and a little around it";
    for (const Mean& m : {es, ec, ds, dc}) EXPECT_NEAR(m.mean, expected, 4 * m.standardError);
    EXPECT_LT(es.standardError, 0.5 * ec.standardError) << "sampling the lamp lowers the noise";
    EXPECT_LT(es.standardError, 0.01 * expected);
    // Same random numbers, same steps: the device follows the reference sample for sample.
    const double sampledError = test::relativeRmse(deviceSampled->rgb, embreeSampled->rgb);
    const double chanceError = test::relativeRmse(deviceByChance->rgb, embreeByChance->rgb);
    std::printf("lamp: device against Embree, relative RMSE %.2e sampled, %.2e by chance\n", sampledError, chanceError);
    EXPECT_LE(sampledError, 1e-3);
    EXPECT_LE(chanceError, 1e-3);
}

TEST(EmitterRender, GlossyPlaneUnderTheLampMatchesWithAndWithoutSampling) {
    TriangleMesh mesh = lampOverPlane(true);
    mesh.materials[0].metallic = 0.6f;
    mesh.materials[0].roughness = 0.35f;
    const std::string path = lampPackage("lamp-glossy", std::move(mesh));
    // The power heuristic between the lamp's density and the GGX lobe's: both estimators have one
    // expectation.
    expectSampledAsByChance(path, [&](bool sampled) { return slantView(path, sampled, 256); }, 1e-3, "glossy lamp");
}

TEST(EmitterRender, SingleSidedLampSeenFromBehindIsDark) {
    // Facing up: the plane sees its back. Neither next-event estimation nor a bounce finds light.
    const std::string path = lampPackage("lamp-up", lampOverPlane(false));
    for (bool sampling : {true, false}) {
        const RenderOptions o = slantView(path, sampling, 16);
        auto device = test::renderVulkan(path, o, 256ull << 20);
        auto reference = test::renderEmbree(path, o);
        ASSERT_TRUE(device && reference) << device.message() << reference.message();
        EXPECT_EQ(pixelMean(*device).mean, 0.0) << "sampling " << sampling;
        EXPECT_EQ(pixelMean(*reference).mean, 0.0) << "sampling " << sampling;
    }
    // Double-sided, the same lamp lights the plane as when it faces down.
    const std::string both = lampPackage("lamp-up-both", lampOverPlane(false, 1, true));
    auto lit = test::renderEmbree(both, slantView(both, true, 64));
    ASSERT_TRUE(lit) << lit.message();
    const Mean m = pixelMean(*lit);
    EXPECT_NEAR(m.mean, expectedMean(), 4 * m.standardError);
}

TEST(EmitterRender, StreamedEqualsInCoreWithSampledEmitters) {
    // A plane of 2 x 48^2 triangles in small chunks: two slots page them in and out.
    const std::string path = lampPackage("lamp-chunked", lampOverPlane(true, 48), 16 << 10);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    const uint64_t chunks = (*reader)->info().chunks.size();
    ASSERT_GT(chunks, 2u);
    RenderOptions o = slantView(path, true, 4);
    o.maxDepth = 3;
    o.camera = {{0, 3, 6}, {0, 0, 0}, {0, 1, 0}, 60.0f};
    o.width = o.height = 32;
    auto inCore = test::renderVulkan(path, o, 512ull << 20);
    ASSERT_TRUE(inCore) << inCore.message();
    test::expectTwoSlotRenderEquals(path, o, 0, *inCore, chunks);
}

// A kept-open scene's renders share its emitter table (the service makes it once per open scene):
// the device uploads it at the first render only; a new table, even of the same triangles, is
// uploaded again. Each render is the same image.
TEST(EmitterRender, AKeptOpenSceneUploadsItsEmitterTableOnce) {
    const std::string path = lampPackage("lamp-kept-open", lampOverPlane(true, 4));
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    const RenderOptions o = slantView(path, true, 2);
    ASSERT_TRUE(o.emitters);
    const uint64_t tableBytes = o.emitters->entries.size() * sizeof(gpu::WavefrontEmitter);
    auto scene = StreamingScene::open(**reader, requiredAttributes((*reader)->info(), o), StreamingOptions{},
                                      [&](const PackageInfo& info, const ChunkAttributes& a) {
                                          return gpu::createVulkanChunkBackend(test::sharedVulkanDevice(), info, a,
                                                                               256ull << 20);
                                      });
    ASSERT_TRUE(scene) << scene.message();
    StreamingStats first, second, renewed;
    auto a = (*scene)->render(o, nullptr, &first);
    auto b = (*scene)->render(o, nullptr, &second);
    RenderOptions fresh = o;
    fresh.emitters = sceneEmitterTable((*reader)->info().emitters, (*reader)->info().materials);
    auto c = (*scene)->render(fresh, nullptr, &renewed);
    ASSERT_TRUE(a && b && c) << a.message() << b.message() << c.message();
    EXPECT_EQ(second.hostToDeviceBytes + tableBytes, renewed.hostToDeviceBytes);
    EXPECT_GE(first.hostToDeviceBytes, renewed.hostToDeviceBytes);
    EXPECT_EQ(a->rgb, b->rgb);
    EXPECT_EQ(a->rgb, c->rgb);
}

// The sum and share of every light, sampled and by chance: the sun (half of next-event
// estimation's picks go to the lamp, the rest is divided between the point light and the sun),
// a point light and the lamp; several bounces.
TEST(EmitterRender, BesideTheSunAndAPointLightTheExpectationHolds) {
    TriangleMesh mesh = lampOverPlane(true);
    PunctualLight bulb{"bulb", LightType::Point, {1, 1, 1}, 3.0f};
    bulb.position = {0.5f, 0.6f, 1.5f};
    mesh.lights = {bulb};
    const std::string path = lampPackage("lamp-sun-bulb", std::move(mesh));
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    auto lit = [&](bool sampled) {
        RenderOptions o = slantView(path, sampled, 256);
        o.environment = Environment{};  // the default sky and sun
        o.maxDepth = 3;
        applySceneLights((*reader)->info().lights, (*reader)->info().bounds, o);
        return o;
    };
    const Mean s = expectSampledAsByChance(path, lit, 1e-3, "lamp, sun and bulb");
    EXPECT_GT(s.mean, expectedMean()) << "the sun and the bulb add to the lamp";
}

// Fog between the lamp and the plane: next-event estimation from points in the volume (the phase
// function against the lamp's density) and through it (ratio tracking), hits after a volume
// bounce weighted by the phase function's density.
TEST(EmitterRender, FogUnderTheLampScattersItsLightOnBothBackends) {
    VolumeMaterial fog;
    fog.albedo = {0.9f, 0.9f, 0.9f};
    fog.anisotropy = 0.4f;
    fog.densityScale = 0.8f;
    // Between the plane and the lamp, touching neither (tests/stream/VolumeFaceTest.cpp has a
    // surface on a volume's face).
    Volume slab = test::makeVolume({0, 0, 0}, {15, 3, 15},
                                   [](int32_t i, int32_t, int32_t k) { return 0.6f + 0.4f * float((i / 4 + k / 4) % 2); },
                                   0.125f, {-1, 0.25f, -1}, fog);
    const std::string path =
        test::writeVolumePackage("emitters", "lamp-fog", lampOverPlane(true), {std::move(slab)});
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    auto volumes = (*reader)->readVolumes();
    ASSERT_TRUE(volumes) << volumes.message();
    auto foggy = [&](bool sampled) {
        RenderOptions o = slantView(path, sampled, 64);
        o.camera = {{0, 0.5f, 3}, {0, 0.3f, 0}, {0, 1, 0}, 40.0f};
        o.maxDepth = 3;
        o.volumes = *volumes;
        return o;
    };
    EXPECT_GT(expectSampledAsByChance(path, foggy, 1e-4, "lamp in fog").mean, 0.01);
}

// An emissive map over the lamp (1024^2 of noise, sRGB, UVs across the square): its triangles are
// sampled, the drawn point reading the map at level 0 (docs/RENDERING.md "Emissive triangles").
// At level 0 for both strategies (--texture-lod finest), sampled and by chance have one
// expectation on both backends, and the device follows the reference; the map shows (the mean
// well below the unmapped lamp's); and through a texture pool of a quarter of the map's pages the
// sampled render equals the in-core one bit for bit (a drawn point on an absent page waits for it
// as a hit does).
TEST(EmitterRender, AnEmissiveMapIsSampledWhereItsTexelsShine) {
    TriangleMesh mesh = lampOverPlane(true);
    mesh.materials[1].textures.slots[uint32_t(TextureSlot::Emissive)].texture = 0;
    mesh.uvs.assign(mesh.positions.size(), {0.5f, 0.5f});
    const size_t lamp = mesh.positions.size() - 4;
    mesh.uvs[lamp] = {0, 0}, mesh.uvs[lamp + 1] = {1, 0}, mesh.uvs[lamp + 2] = {1, 1}, mesh.uvs[lamp + 3] = {0, 1};
    const Rgba8Image noise = test::noiseImage(1024, 1024, 5);
    const std::filesystem::path png = test::testTmpDir("emitters") / "glow.png";
    std::filesystem::create_directories(png.parent_path());
    ASSERT_TRUE(writeRgba8Png(png.string(), noise.width, noise.height, noise.texels));
    std::ifstream in(png, std::ios::binary);
    mesh.textures.push_back({"glow.png", ".png", {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()},
                             TextureWrap::Clamp, TextureWrap::Clamp, TextureEncoding::Srgb});
    const std::string path = lampPackage("lamp-mapped", std::move(mesh));
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    const PackageInfo info = (*reader)->info();
    ASSERT_EQ(info.emitters.size(), 2u) << "the mapped lamp's triangles are sampled";
    EXPECT_EQ(info.emitters[0].t1, (std::array<float, 2>{1, 0})) << "with their corners' UVs";
    auto view = [&](bool sampled) {
        RenderOptions o = slantView(path, sampled, 256);
        o.textureLod = TextureLodMode::Finest;
        return o;
    };
    const Mean mapped = expectSampledAsByChance(path, view, 1e-3, "mapped lamp");
    EXPECT_LT(mapped.mean, 0.6 * expectedMean()) << "the noise's texels are darker than the factor alone";
    EXPECT_GT(mapped.mean, 0.05 * expectedMean());
    // The map's pages four times the pool's: the sampled render waits for the pages its points read.
    const RenderOptions o = view(true);
    StreamingStats ample, tight;
    auto inCore = test::renderVulkan(path, o, 256ull << 20, &ample);
    const uint64_t budget = gpu::textureBytes(info);
    auto paged = test::renderVulkan(path, o, budget, &tight);
    ASSERT_TRUE(inCore && paged) << inCore.message() << paged.message();
    std::printf("mapped lamp paged: %llu page slots, %llu page loads\n", (unsigned long long)tight.texturePageSlots,
                (unsigned long long)tight.texturePageLoads);
    EXPECT_EQ(ample.texturePageSlots, 0u);
    EXPECT_GT(tight.texturePageSlots, 0u);
    EXPECT_GT(tight.texturePageLoads, tight.texturePageSlots) << "pages paged in more than once";
    EXPECT_EQ(std::memcmp(paged->rgb.data(), inCore->rgb.data(), inCore->rgb.size() * 4), 0);
}

}  // namespace
}  // namespace vastray
