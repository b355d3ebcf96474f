// Volumes (issue "Volumes"): density grids stored in the package beside the mesh and traced by
// the path integrator on the device and in the Embree reference. Checked against Beer-Lambert
// (an absorbing slab in front of the ground), the two backends against each other, a streamed
// render against the in-core one, the package round trip and the device bytes against the budget.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>

#include "../VolumePackageForge.h"
#include "../VolumeTestSupport.h"
#include "StreamTestSupport.h"
#include "vastray/core/Checksum.h"
#include "vastray/core/EnvironmentMap.h"
#include "vastray/core/Sampling.h"
#include "TestTmp.h"
#include "vastray/streamer/Generate.h"
#include "vastray/streamer/PackageBuilder.h"

namespace vastray {
namespace {

std::string writePackage(const std::string& name, TriangleMesh mesh, std::vector<Volume> volumes) {
    return test::writeVolumePackage("volumes", name, std::move(mesh), std::move(volumes));
}

std::shared_ptr<const std::vector<Volume>> volumesOf(const std::string& path) {
    auto reader = PackageReader::open(path);
    EXPECT_TRUE(reader) << reader.message();
    auto volumes = (*reader)->readVolumes();
    EXPECT_TRUE(volumes) << volumes.message();
    return *volumes;
}

// A package of a generated city of `triangles` triangles and one volume over it, which `make`
// builds from the city's bounds.
std::string cityUnder(const std::string& name, uint32_t triangles, uint32_t seed,
                      const std::function<Volume(const Aabb&)>& make) {
    auto mesh = generateMesh({GeneratorKind::City, triangles, seed});
    EXPECT_TRUE(mesh) << mesh.message();
    Volume v = make(mesh->bounds());
    return writePackage(name, std::move(mesh).value(), {std::move(v)});
}

// A 20k-triangle city with a fog bank of rising density over part of it.
const std::string& foggyCity() {
    static const std::string path = cityUnder("foggy-city", 20000, 1, [](const Aabb& b) {
        const Vec3f e = b.extent();
        VolumeMaterial fog;
        fog.albedo = {0.9f, 0.85f, 0.8f};
        fog.anisotropy = 0.4f;
        // 48 x 16 x 48 voxels over the middle of the city, densest at the bottom.
        const float voxel = e.x / 64.0f;
        fog.densityScale = 2.0f / (16.0f * voxel);
        return test::makeVolume({0, 0, 0}, {47, 15, 47},
                                [](int32_t i, int32_t j, int32_t k) {
                                    return (1.0f - float(j) / 16.0f) * (0.5f + 0.5f * float((i / 8 + k / 8) % 2));
                                },
                                voxel, b.lo + Vec3f{e.x / 8, 0, e.z / 8}, fog);
    });
    return path;
}

TEST(VolumeRender, PackageKeepsTheVolume) {
    const std::string& path = foggyCity();
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    const PackageInfo& info = (*reader)->info();
    EXPECT_GE(info.formatVersion, 6u);  // volumes came with version 4, brick by brick with 6
    ASSERT_EQ(info.volumes.size(), 1u);
    EXPECT_EQ(info.volumes[0].volume.name, "test");
    EXPECT_EQ(info.volumes[0].volume.material.anisotropy, 0.4f);
    auto volumes = (*reader)->readVolumes();
    ASSERT_TRUE(volumes) << volumes.message();
    const Volume& v = (**volumes)[0];
    EXPECT_EQ(volumeVoxel(v, 12, 4, 0), (1.0f - 4.0f / 16.0f) * 1.0f);
    EXPECT_EQ(volumeVoxel(v, 0, 0, 0), 0.5f);
    EXPECT_EQ(volumeVoxel(v, 48, 0, 0), 0.0f);
    EXPECT_EQ(v.majorant.size(), v.cellCount());
    EXPECT_TRUE((*reader)->verify().empty());
    EXPECT_GE(gpu::volumeBytes(info), v.voxels.size() * 4);

    // A flipped byte in the last brick: its own checksum names it (the table still reads).
    const std::string damaged = path + ".damaged.vast";
    std::filesystem::copy_file(path, damaged, std::filesystem::copy_options::overwrite_existing);
    {
        std::fstream f(damaged, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(std::streamoff(info.volumes[0].offset + info.volumes[0].size - 5));
        f.put(char(0x7F));
    }
    auto reopened = PackageReader::open(damaged);
    ASSERT_TRUE(reopened) << reopened.message();  // the records are sound; the data is read later
    ASSERT_TRUE((*reopened)->openVolumes());
    auto bad = (*reopened)->readVolumes();
    ASSERT_FALSE(bad);
    const std::string last = "brick " + std::to_string(info.volumes[0].brickCount - 1) + ": checksum mismatch";
    EXPECT_NE(bad.message().find("volume 0 'test': " + last), std::string::npos) << bad.message();
    EXPECT_EQ((*reopened)->verify().size(), 1u);

    // Forged with every checksum recomputed: a brick index past the bricks, then a NaN voxel,
    // then an albedo above 1 in the record. Each is refused by name.
    const std::vector<uint8_t> original = test::fileBytes(path);
    const PackageVolume& p = info.volumes[0];
    uint64_t recordAt = 0;
    std::memcpy(&recordAt, original.data() + 256 - 24, 8);
    auto forge = [&](const std::function<void(std::vector<uint8_t>&)>& change) {
        const std::string forged = path + ".forged.vast";
        test::writeBytes(forged, test::forgeVolumeData(original, p, change));
        return forged;
    };
    auto firstStored = [&] {  // the brick table entry of the first cell with a brick
        for (uint64_t c = 0; c < v.brickOf.size(); ++c)
            if (v.brickOf[c] != kNoBrick) return c;
        return uint64_t(0);
    }();
    const std::string badIndex = forge([&](std::vector<uint8_t>& b) {
        const uint32_t past = p.brickCount;
        std::memcpy(b.data() + p.offset + 4 * firstStored, &past, 4);
    });
    auto opened = PackageReader::open(badIndex);
    ASSERT_TRUE(opened) << opened.message();
    auto refused = (*opened)->openVolumes();  // the table is checked before any brick is read
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.message().find("volume 0 'test': cell " + std::to_string(firstStored) + " names brick " +
                                     std::to_string(p.brickCount)),
              std::string::npos)
        << refused.message();
    const std::string nanVoxel = forge([&](std::vector<uint8_t>& b) {
        const float nan = std::nanf("");
        std::memcpy(b.data() + test::voxelOffset(p, 0, 9), &nan, 4);
    });
    opened = PackageReader::open(nanVoxel);
    ASSERT_TRUE(opened) << opened.message();
    refused = (*opened)->readVolumes();
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.message().find("volume 0 'test': brick 0 voxel 9 has density nan"), std::string::npos)
        << refused.message();
    const std::string badAlbedo = forge([&](std::vector<uint8_t>& b) {
        const float two = 2.0f;
        std::memcpy(b.data() + recordAt + 140 + 4, &two, 4);
    });
    opened = PackageReader::open(badAlbedo);
    ASSERT_FALSE(opened);
    EXPECT_NE(opened.message().find("volume 0 'test': the albedo 2.000000 is not in [0, 1]"), std::string::npos)
        << opened.message();
}

// Looking straight down through a horizontal slab that only absorbs (albedo 0) onto the sky's
// ground colour: every pixel is ground x exp(-tau), on both backends.
TEST(VolumeRender, AbsorbingSlabFollowsBeerLambert) {
    TriangleMesh mesh = test::farTriangle(100);
    VolumeMaterial absorber;
    absorber.albedo = {0, 0, 0};
    absorber.densityScale = 1.0f;  // 4 voxels of 0.25 along the ray: tau = 1
    Volume slab = test::makeVolume({0, 0, 0}, {63, 3, 63}, [](int32_t, int32_t, int32_t) { return 1.0f; }, 0.25f,
                                   {-8, 0, -8}, absorber);
    const std::string path = writePackage("slab", std::move(mesh), {std::move(slab)});
    RenderOptions o;
    o.width = o.height = 24;
    o.samplesPerPixel = 64;
    o.frameScene = false;
    o.camera.eye = {0.01f, 5, 0.02f};
    o.camera.target = {0.01f, -5, 0.02f};
    o.camera.up = {0, 0, 1};
    o.camera.fovYDegrees = 1.0f;
    o.volumes = volumesOf(path);
    const double expected = double(o.environment.ground[0]) * std::exp(-1.0);
    for (const char* backend : {"vulkan", "embree"}) {
        auto image = std::string(backend) == "vulkan" ? test::renderVulkan(path, o, 256ull << 20) : test::renderEmbree(path, o);
        ASSERT_TRUE(image) << backend << ": " << image.message();
        double sum = 0;
        for (size_t p = 0; p < image->alpha.size(); ++p) sum += image->rgb[3 * p];
        const double mean = sum / double(image->alpha.size());
        // Each sample passes (ground) or not (0): a binomial mean over every sample of the image.
        const double samples = double(image->alpha.size()) * o.samplesPerPixel;
        const double sigma = o.environment.ground[0] * std::sqrt(std::exp(-1.0) * (1 - std::exp(-1.0)) / samples);
        std::printf("%s: mean %.5f, expected %.5f (+-%.5f)\n", backend, mean, expected, sigma);
        EXPECT_NEAR(mean, expected, 4 * sigma) << backend;
    }
}

// A slab that absorbs and glows (albedo 0, an emission grid of 1 times 2) over a black world,
// seen from above: each pixel is the integral of sigma(s) Le(s) e^-tau(s) along the ray (below
// 2 (1 - e^-1): the emission ramps down with the density at the faces), computed by quadrature of the slab's trilinear density and emission; both
// backends, and the package keeps the emission grid.
TEST(VolumeRender, GlowingSlabMatchesTheQuadrature) {
    TriangleMesh mesh = test::farTriangle(100);
    VolumeMaterial glow;
    glow.albedo = {0, 0, 0};
    glow.emission = {2, 2, 2};
    Volume slab = test::makeVolume({0, 0, 0}, {63, 3, 63}, [](int32_t, int32_t, int32_t) { return 1.0f; }, 0.25f,
                                   {-8, 0, -8}, glow);
    slab.emissionVoxels = slab.voxels;
    const Volume reference = slab;
    const std::string path = writePackage("glowing-slab", std::move(mesh), {std::move(slab)});
    RenderOptions o = test::glowingSlabView();
    o.volumes = volumesOf(path);
    ASSERT_EQ(o.volumes->at(0).emissionVoxels.size(), reference.voxels.size());
    EXPECT_EQ(std::memcmp(o.volumes->at(0).emissionVoxels.data(), reference.voxels.data(), reference.voxels.size() * 4), 0);
    double integral = 0, tau = 0;
    const int steps = 20000;
    const double dy = 2.0 / steps;  // from y = 1.5 down to -0.5
    for (int i = 0; i < steps; ++i) {
        const Vec3f p{0.01f, float(1.5 - (i + 0.5) * dy), 0.02f};
        const Vec3f index{(p.x + 8) / 0.25f, p.y / 0.25f, (p.z + 8) / 0.25f};
        const double sigma = volumeDensity(reference, index);
        integral += sigma * volumeEmission(reference, p).x * std::exp(-(tau + 0.5 * sigma * dy)) * dy;
        tau += sigma * dy;
    }
    std::printf("quadrature %.5f (2 (1 - e^-tau) = %.5f, tau %.4f)\n", integral, 2 * (1 - std::exp(-tau)), tau);
    for (const char* backend : {"vulkan", "embree"}) {
        auto image = std::string(backend) == "vulkan" ? test::renderVulkan(path, o, 256ull << 20) : test::renderEmbree(path, o);
        ASSERT_TRUE(image) << backend << ": " << image.message();
        const auto [mean, standardError] = test::pixelMean(*image);
        std::printf("%s: mean %.5f, standard error %.5f\n", backend, mean, standardError);
        EXPECT_LT(standardError, 0.01 * integral);
        EXPECT_NEAR(mean, integral, 4 * standardError + 1e-3 * integral) << backend;
    }
}

// One scattering event (maxDepth 1) along a narrow view from `eye` to `target` over a black
// world, the sun of irradiance 2 towards `sun`: what the single-scattering tests render.
RenderOptions singleScatteringView(const std::string& path, Vec3f eye, Vec3f target, Vec3f sun) {
    RenderOptions o;
    o.width = o.height = 16;
    o.samplesPerPixel = 256;
    o.maxDepth = 1;
    o.frameScene = false;
    o.camera.eye = eye;
    o.camera.target = target;
    o.camera.fovYDegrees = 0.1f;
    o.environment.zenith = o.environment.horizon = o.environment.ground = {0, 0, 0};
    o.environment.sunDirection = sun;
    o.environment.sunIrradiance = {2, 2, 2};
    o.volumes = volumesOf(path);
    return o;
}

// Both backends' pixel mean within 4 standard errors (and `slack` of it) of `expected`, each
// standard error below 1 % of it.
void expectSingleScattering(const std::string& path, const RenderOptions& o, double expected, double slack,
                            const char* what) {
    for (const char* backend : {"vulkan", "embree"}) {
        auto image = std::string(backend) == "vulkan" ? test::renderVulkan(path, o, 256ull << 20) : test::renderEmbree(path, o);
        ASSERT_TRUE(image) << backend << ": " << image.message();
        const auto [mean, standardError] = test::pixelMean(*image);
        std::printf("%s: mean %.6f, %s %.6f, standard error %.6f\n", backend, mean, what, expected, standardError);
        EXPECT_LT(standardError, 0.01 * expected);
        EXPECT_NEAR(mean, expected, 4 * standardError + slack * expected) << backend;
    }
}

// Single scattering of the sun in a homogeneous box, seen along a ray through its middle with
// the sun across it (one scattering event: --max-depth 1, a black sky): the pixel is
// E x albedo x phase(90 degrees) x the integral over the ray of sigma(s) e^-tau_camera(s)
// e^-tau_sun(s), computed here by quadrature of the box's trilinear density, on both backends.
TEST(VolumeRender, SingleScatteringMatchesTheQuadrature) {
    TriangleMesh mesh = test::farTriangle(-100);  // out of the light's way too
    VolumeMaterial m;
    m.albedo = {0.8f, 0.8f, 0.8f};
    m.densityScale = 1.0f;
    m.anisotropy = 0.5f;
    const float voxel = 1.0f / 32.0f;
    Volume box = test::makeVolume({0, 0, 0}, {63, 63, 63}, [](int32_t, int32_t, int32_t) { return 1.0f; }, voxel, {0, 0, 0}, m);
    const Volume reference = box;
    const std::string path = writePackage("single-scattering", std::move(mesh), {std::move(box)});
    const RenderOptions o = singleScatteringView(path, {-3, 1, 1}, {0, 1, 1}, {0, 1, 0});
    // The quadrature: density along the ray (x from -1 to 3 at y = z = 1) and up to the sun.
    auto sigma = [&](float x, float y, float z) { return volumeDensity(reference, {x / voxel, y / voxel, z / voxel}); };
    const int steps = 4000, sunSteps = 1000;
    const double dx = 4.0 / steps, dy = 2.0 / sunSteps;
    double integral = 0, tauCamera = 0;
    for (int i = 0; i < steps; ++i) {
        const float x = float(-1.0 + (i + 0.5) * dx);
        const double s = sigma(x, 1, 1);
        if (s > 0) {
            double tauSun = 0;
            for (int j = 0; j < sunSteps; ++j) tauSun += sigma(x, float(1.0 + (j + 0.5) * dy), 1) * dy;
            // The camera's transmittance to the middle of this step.
            integral += s * std::exp(-(tauCamera + 0.5 * s * dx)) * std::exp(-tauSun) * dx;
        }
        tauCamera += s * dx;
    }
    const double g = 0.5, phase = (1 - g * g) / (4 * kPi * std::pow(1 + g * g, 1.5));
    expectSingleScattering(path, o, 2.0 * 0.8 * phase * integral, 1e-3, "quadrature");
}

// Single scattering in a homogeneous sphere against its analytic value: a ray through the
// sphere's centre with the sun behind the camera (one scattering event, a black sky). At depth t
// into the sphere the camera's and the sun's paths are both t long and the light turns back
// (phase at cos -1), so the pixel is E x albedo x phase(-1) x the integral from 0 to 2R of
// sigma e^(-2 sigma t) dt = E x albedo x phase(-1) x (1 - e^(-4 sigma R)) / 2. The sphere is
// voxels of density 1 within 31.5 voxels of its centre: along the ray the trilinear ramp at each
// face is centred on R, so its chord integrates to 2R; on both backends.
TEST(VolumeRender, SingleScatteringInASphereMatchesTheAnalyticValue) {
    TriangleMesh mesh = test::farTriangle(-100);
    VolumeMaterial m;
    m.albedo = {0.8f, 0.8f, 0.8f};
    m.densityScale = 1.5f;
    m.anisotropy = 0.5f;
    const float voxel = 1.0f / 32.0f, radius = 31.5f * voxel;
    Volume sphere = test::makeVolume(
        {-32, -32, -32}, {32, 32, 32},
        [](int32_t i, int32_t j, int32_t k) { return i * i + j * j + k * k < 31.5f * 31.5f ? 1.0f : 0.0f; }, voxel,
        {0, 0, 0}, m);
    const std::string path = writePackage("single-scattering-sphere", std::move(mesh), {std::move(sphere)});
    // The sun behind the camera: the light travels along +x.
    const RenderOptions o = singleScatteringView(path, {-3, 0, 0}, {0, 0, 0}, {-1, 0, 0});
    const double sigma = 1.5, g = 0.5;
    const double phase = (1 - g * g) / (4 * kPi * std::pow(1 + g * g + 2 * g, 1.5));  // cos = -1
    expectSingleScattering(path, o, 2.0 * 0.8 * phase * (1 - std::exp(-4 * sigma * radius)) / 2, 2e-3, "analytic");
}

RenderOptions foggyRender(uint32_t spp) {
    RenderOptions o;
    o.width = 48, o.height = 36;
    o.samplesPerPixel = spp;
    o.maxDepth = 4;
    o.volumes = volumesOf(foggyCity());
    return o;
}

TEST(VolumeRender, DeviceAgreesWithEmbreeAndStreamsTheSame) {
    const std::string& path = foggyCity();
    const RenderOptions o = foggyRender(8);
    auto reference = test::renderEmbree(path, o);
    ASSERT_TRUE(reference) << reference.message();
    StreamingStats stats;
    auto device = test::renderVulkan(path, o, 256ull << 20, &stats);
    ASSERT_TRUE(device) << device.message();
    EXPECT_GT(stats.chunksTotal, 4u);
    const double rmse = test::relativeRmse(device->rgb, reference->rgb);
    std::printf("device vs Embree beauty relative RMSE %.2e\n", rmse);
    EXPECT_LE(rmse, 5e-3);
    // The fog is in the picture: without it the image is another.
    RenderOptions clear = o;
    clear.volumes.reset();
    auto unfogged = test::renderVulkan(path, clear, 256ull << 20);
    ASSERT_TRUE(unfogged) << unfogged.message();
    const double difference = test::relativeRmse(unfogged->rgb, device->rgb);
    std::printf("with and without the fog: relative RMSE %.2e\n", difference);
    EXPECT_GT(difference, 0.03);

    // Out of core (two chunk slots): the same image bit for bit; the volume's bytes are kept.
    test::expectTwoSlotRenderEquals(path, o, gpu::volumeBytes(PackageReader::open(path).value()->info()), *device,
                                    stats.chunksTotal);
}

// A 2,000-triangle town under a cloud of 128 x 64 x 128 voxels (2,048 bricks, every one stored),
// the bricks stored as NanoVDB leaves of `codec`.
std::string cloudedTownOf(VolumeCodec codec) {
    return cityUnder(std::string("clouded-town-") + volumeCodecName(codec), 2000, 3, [codec](const Aabb& b) {
        VolumeMaterial cloud;
        cloud.albedo = {0.95f, 0.95f, 0.9f};
        cloud.anisotropy = 0.3f;
        const float voxel = b.extent().x / 128.0f;
        cloud.densityScale = 3.0f / (64.0f * voxel);  // an optical depth of ~1.5 from top to bottom
        Volume v = test::makeVolume({0, 0, 0}, {127, 63, 127},
                                [](int32_t i, int32_t j, int32_t k) {
                                    return 0.2f + 0.4f * (1.0f + std::sin(0.21f * float(i)) * std::cos(0.17f * float(k))) *
                                                      (1.0f - float(j) / 80.0f);
                                },
                                voxel, b.lo, cloud);
        v.codec = codec;  // the package writer quantizes
        return v;
    });
}
const std::string& cloudedTown() {
    static const std::string path = cloudedTownOf(VolumeCodec::Float);
    return path;
}

// The clouded town at width x height, spp, depth, its volumes opened as `vastray render` opens
// them: brick tables now, each brick read when a render needs it.
RenderOptions cloudedTownView(const std::string& path, uint32_t width, uint32_t height, uint32_t spp, uint32_t depth) {
    RenderOptions o;
    o.width = width, o.height = height;
    o.samplesPerPixel = spp;
    o.maxDepth = depth;
    o.volumes = PackageReader::open(path).value()->openVolumes().value();
    return o;
}

// Bricks paged through a pool about a quarter of their size (--memory-budget at two fifths of the
// volume's bytes keeps half of it for the volume, its tables and park records, and the volume takes
// what the wave and the mesh leave): the image equals the in-core one bit for bit, the bricks are
// loaded (some more than once) and the device bytes stay within the budget.
TEST(VolumeRender, PagedBricksRenderTheSameBitForBit) {
    const std::string& path = cloudedTown();
    const RenderOptions o = cloudedTownView(path, 32, 24, 4, 3);
    ASSERT_EQ(o.volumes->size(), 1u);
    const uint64_t bricks = (*o.volumes)[0].brickCount();
    ASSERT_EQ(bricks, 2048u);
    StreamingStats inCoreStats;
    auto inCore = test::renderVulkan(path, o, 256ull << 20, &inCoreStats);
    ASSERT_TRUE(inCore) << inCore.message();
    EXPECT_EQ(inCoreStats.volumeBrickSlots, 0u);
    EXPECT_EQ(inCoreStats.volumeBrickLoads, 0u);
    EXPECT_EQ(inCoreStats.volumeBricksRead, bricks);

    const PackageInfo info = PackageReader::open(path).value()->info();
    const uint64_t budget = gpu::volumeBytes(info) * 2 / 5;
    EXPECT_LT(gpu::volumeReserveBytes(info, budget), gpu::volumeBytes(info));
    StreamingStats stats;
    auto paged = test::renderVulkan(path, o, budget, &stats);
    ASSERT_TRUE(paged) << paged.message();
    std::printf("paged: %llu brick slots for %llu bricks, %llu loads, %llu submits, peak device %llu of %llu bytes\n",
                (unsigned long long)stats.volumeBrickSlots, (unsigned long long)bricks,
                (unsigned long long)stats.volumeBrickLoads, (unsigned long long)stats.submits,
                (unsigned long long)stats.peakDeviceBytes, (unsigned long long)budget);
    EXPECT_GT(stats.volumeBrickSlots, 0u);
    EXPECT_LE(stats.volumeBrickSlots * 4, bricks + 64) << "the bricks are 4x the pool or more";
    EXPECT_GT(stats.volumeBrickLoads, stats.volumeBrickSlots) << "slots were reused";
    // The host cache holds every brick of this cloud: each is read from the package at most once.
    EXPECT_GT(stats.volumeBricksRead, 0u);
    EXPECT_LE(stats.volumeBricksRead, bricks);
    EXPECT_LE(stats.peakDeviceBytes, budget);
    EXPECT_EQ(std::memcmp(paged->rgb.data(), inCore->rgb.data(), inCore->rgb.size() * 4), 0);
    EXPECT_EQ(std::memcmp(paged->alpha.data(), inCore->alpha.data(), inCore->alpha.size() * 4), 0);
}

// The clouded town with its bricks stored as NanoVDB's quantized Fp16 and Fp8 leaves: the package
// and the device hold about a half and a quarter of the float leaves' bytes; paged through a pool
// the image equals the in-core one bit for bit;
// the Embree reference, which reads the voxels the leaves decode to (NanoVDB's C++ access), agrees
// with the device as closely as with float bricks; and the quantized cloud differs from the float
// one by no more than its quantization.
TEST(VolumeRender, QuantizedBricksPageTheSameAndAgreeWithEmbree) {
    const std::string& floatPath = cloudedTown();
    const RenderOptions floatView = cloudedTownView(floatPath, 32, 24, 4, 3);
    auto floatImage = test::renderVulkan(floatPath, floatView, 256ull << 20);
    ASSERT_TRUE(floatImage) << floatImage.message();
    const uint64_t floatBytes = gpu::volumeBytes(PackageReader::open(floatPath).value()->info());
    for (const VolumeCodec codec : {VolumeCodec::Fp16, VolumeCodec::Fp8}) {
        SCOPED_TRACE(volumeCodecName(codec));
        const std::string path = cloudedTownOf(codec);
        const PackageInfo info = PackageReader::open(path).value()->info();
        ASSERT_EQ(info.volumes.size(), 1u);
        EXPECT_EQ(info.volumes[0].volume.codec, codec);
        const uint64_t bytes = gpu::volumeBytes(info);
        EXPECT_LT(bytes, floatBytes * (codec == VolumeCodec::Fp16 ? 0.55 : 0.3));
        const RenderOptions o = cloudedTownView(path, 32, 24, 4, 3);
        EXPECT_EQ((*o.volumes)[0].codec, codec);
        StreamingStats inCoreStats;
        auto inCore = test::renderVulkan(path, o, 256ull << 20, &inCoreStats);
        ASSERT_TRUE(inCore) << inCore.message();
        EXPECT_EQ(inCoreStats.volumeBrickSlots, 0u);
        // Two fifths of the float cloud's bytes (Fp16), three tenths (Fp8): below the quantized
        // cloud's bytes besides the wave's and the mesh's, above the scene's minimum.
        const uint64_t budget = floatBytes * (codec == VolumeCodec::Fp16 ? 4 : 3) / 10;
        StreamingStats stats;
        auto paged = test::renderVulkan(path, o, budget, &stats);
        ASSERT_TRUE(paged) << paged.message();
        EXPECT_GT(stats.volumeBrickSlots, 0u);
        EXPECT_GT(stats.volumeBrickLoads, stats.volumeBrickSlots) << "slots were reused";
        EXPECT_LE(stats.peakDeviceBytes, budget);
        EXPECT_EQ(std::memcmp(paged->rgb.data(), inCore->rgb.data(), inCore->rgb.size() * 4), 0);

        RenderOptions reference = o;
        reference.volumes = PackageReader::open(path).value()->readVolumes().value();
        auto embree = test::renderEmbree(path, reference);
        ASSERT_TRUE(embree) << embree.message();
        const double rmse = test::relativeRmse(inCore->rgb, embree->rgb);
        const double quantized = test::relativeRmse(inCore->rgb, floatImage->rgb);
        std::printf("%s: device vs Embree relative RMSE %.2e, against the float cloud %.2e; paged: %llu slots, %llu loads\n",
                    volumeCodecName(codec), rmse, quantized, (unsigned long long)stats.volumeBrickSlots,
                    (unsigned long long)stats.volumeBrickLoads);
        EXPECT_LE(rmse, 5e-3);
        EXPECT_GT(quantized, 0.0) << "the quantized cloud is another cloud";
        EXPECT_LE(quantized, codec == VolumeCodec::Fp16 ? 2e-3 : 3e-2);
    }
}

// A kept-open scene (as the service keeps one) whose volumes are paged, rendered under a small
// environment map and then a larger one: the volumes took what the small map left of the
// reserve, and give it back before the larger map is allocated, so the device's peak stays within
// the budget on both renders (it passed the budget by about the maps' difference before).
TEST(VolumeRender, ALargerMapOfAKeptOpenSceneStaysWithinTheBudget) {
    const std::string& path = cloudedTown();
    RenderOptions o = cloudedTownView(path, 16, 12, 2, 1);
    const std::shared_ptr<const EnvironmentMap> small = test::constantEnvironmentMap("small", 8, 4, 1, 1, 1),
                                                large = test::constantEnvironmentMap("large", 256, 128, 1, 1, 1);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    const PackageInfo info = (*reader)->info();
    const uint64_t budget = gpu::volumeBytes(info);  // the volume's share of it, a half, pages the bricks
    RenderOptions withLarge = o;
    withLarge.environment.map = large;
    const uint64_t reserved = gpu::environmentBytes(withLarge.environment) + gpu::volumeReserveBytes(info, budget);
    auto scene = StreamingScene::open(**reader, requiredAttributes(info, o), StreamingOptions{},
                                      [&](const PackageInfo& i, const ChunkAttributes& a) {
                                          return gpu::createVulkanChunkBackend(test::sharedVulkanDevice(), i, a, budget,
                                                                               gpu::kWaveShareOutOfCore, {}, reserved);
                                      });
    ASSERT_TRUE(scene) << scene.message();
    StreamingStats first, second;
    o.environment.map = small;
    auto underSmall = (*scene)->render(o, nullptr, &first);
    ASSERT_TRUE(underSmall) << underSmall.message();
    auto underLarge = (*scene)->render(withLarge, nullptr, &second);
    ASSERT_TRUE(underLarge) << underLarge.message();
    std::printf("peak device bytes: %llu under the small map, %llu under the large one, of %llu; %llu brick slots\n",
                (unsigned long long)first.peakDeviceBytes, (unsigned long long)second.peakDeviceBytes,
                (unsigned long long)budget, (unsigned long long)second.volumeBrickSlots);
    EXPECT_GT(first.volumeBrickSlots, second.volumeBrickSlots) << "the larger map leaves fewer slots";
    EXPECT_GT(second.volumeBrickSlots, 0u);
    EXPECT_LE(first.peakDeviceBytes, budget);
    EXPECT_LE(second.peakDeviceBytes, budget);
}

// The bytes of the budget that the wave and the chunk slots leave (the wave grows by doubling, the
// plan counts whole allocation granules) go to the brick pool besides the volume's share: at half
// the volume's bytes the pool's voxels alone outweigh that share, and the device bytes stay within
// the budget.
TEST(VolumeRender, PagedVolumesTakeWhatTheWaveAndTheMeshLeave) {
    const std::string& path = cloudedTown();
    const RenderOptions o = cloudedTownView(path, 16, 12, 2, 1);
    const PackageInfo info = PackageReader::open(path).value()->info();
    const uint64_t budget = gpu::volumeBytes(info) / 2, share = gpu::volumeReserveBytes(info, budget);
    ASSERT_LT(share, gpu::volumeBytes(info));
    StreamingStats stats;
    auto paged = test::renderVulkan(path, o, budget, &stats);
    ASSERT_TRUE(paged) << paged.message();
    std::printf("%llu brick slots (%llu bytes of voxels) for a share of %llu bytes; peak device %llu of %llu\n",
                (unsigned long long)stats.volumeBrickSlots,
                (unsigned long long)(stats.volumeBrickSlots * 4ull * kVolumeBrickVoxels), (unsigned long long)share,
                (unsigned long long)stats.peakDeviceBytes, (unsigned long long)budget);
    EXPECT_GT(stats.volumeBrickSlots * 4ull * kVolumeBrickVoxels, share)
        << "the pool holds no more than the volume's share: the budget's spare bytes are unused";
    EXPECT_LE(stats.peakDeviceBytes, budget);
}

// A backend that kept no bytes for the volumes refuses to render them, naming them.
TEST(VolumeRender, VolumesOutsideTheReserveAreRefused) {
    const std::string& path = foggyCity();
    const RenderOptions o = foggyRender(1);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    auto refused = renderStreaming(**reader, o, StreamingOptions{}, [&](const PackageInfo& info, const ChunkAttributes& a) {
        return gpu::createVulkanChunkBackend(test::sharedVulkanDevice(), info, a, 256ull << 20);
    });
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.message().find("the volumes need"), std::string::npos) << refused.message();
}

}  // namespace
}  // namespace vastray
