// Temperature grids (issue "Volumes"): a volume whose emission grid is a temperature in kelvin
// glows as a blackbody (core/Blackbody.h) on both backends; the package keeps the record's flag
// (bit 1) and refuses it without an emission grid.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "../VolumePackageForge.h"
#include "../VolumeTestSupport.h"
#include "StreamTestSupport.h"
#include "TestTmp.h"
#include "vastray/core/Blackbody.h"
#include "vastray/gpu/VulkanChunkBackend.h"
#include "vastray/streamer/PackageBuilder.h"

namespace vastray {
namespace {

constexpr float kKelvin = 3000.0f;

// A slab that absorbs and glows (albedo 0) over a black world: density 1 in voxels y 1..4 (0.25
// world units each, tau 1 across with the faces' trilinear ramps), and the temperature kKelvin in
// every voxel of its bricks (y 0..7), so the temperature is kKelvin wherever the density is not 0.
Volume temperatureSlab() {
    VolumeMaterial glow;
    glow.albedo = {0, 0, 0};
    glow.emission = {100, 80, 120};
    glow.temperature = true;
    Volume slab = test::makeVolume({0, 1, 0}, {63, 4, 63}, [](int32_t, int32_t, int32_t) { return 1.0f; }, 0.25f,
                                   {-8, 0, -8}, glow);
    slab.emissionVoxels.assign(slab.voxels.size(), kKelvin);
    return slab;
}

std::string writePackage(const std::string& name, std::vector<Volume> volumes) {
    return test::writeVolumePackage("temperature-volumes", name, test::farTriangle(100), std::move(volumes));
}

// Seen from above, each sample either collides in the slab (probability 1 - e^-tau), where the
// absorbed share glows with scale x blackbody(T), or leaves into the black world: the pixel's
// mean is (1 - e^-1) scale blackbody(T). blackbody(T) here is the direct integration (not the
// table, which is within 2e-4 of it at 3000 K). Both backends, each channel, within 4 standard
// errors (plus 1e-3 of the value for the table and the float arithmetic).
TEST(TemperatureVolume, GlowingSlabIsTheBlackbody) {
    const std::string path = writePackage("temperature-slab", {temperatureSlab()});
    RenderOptions o = test::glowingSlabView();
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    auto volumes = (*reader)->readVolumes();
    ASSERT_TRUE(volumes) << volumes.message();
    ASSERT_TRUE((*volumes)->at(0).material.temperature);
    o.volumes = *volumes;
    const auto blackbody = blackbodySrgb(kKelvin);
    const double scale[3] = {100, 80, 120};
    double means[2][3] = {};
    int b = 0;
    for (const char* backend : {"vulkan", "embree"}) {
        auto image = std::string(backend) == "vulkan" ? test::renderVulkan(path, o, 256ull << 20) : test::renderEmbree(path, o);
        ASSERT_TRUE(image) << backend << ": " << image.message();
        const size_t pixels = image->alpha.size();
        for (int c = 0; c < 3; ++c) {
            double sum = 0;
            for (size_t p = 0; p < pixels; ++p) sum += image->rgb[3 * p + c];
            const double expected = (1 - std::exp(-1.0)) * scale[c] * blackbody[c];
            const double mean = sum / double(pixels), samples = double(pixels) * o.samplesPerPixel;
            const double sigma = scale[c] * blackbody[c] * std::sqrt(std::exp(-1.0) * (1 - std::exp(-1.0)) / samples);
            std::printf("%s channel %d: mean %.5f, expected %.5f (+-%.5f)\n", backend, c, mean, expected, sigma);
            EXPECT_NEAR(mean, expected, 4 * sigma + 1e-3 * expected) << backend << " channel " << c;
            means[b][c] = mean;
        }
        ++b;
    }
    // 3000 K is orange: red over green over blue on both.
    EXPECT_GT(means[0][0] / scale[0], means[0][1] / scale[1]);
    EXPECT_GT(means[0][1] / scale[1], means[0][2] / scale[2]);
}

// The record's flags: bit 1 (a temperature) read back, by the whole reader and the brick by brick
// one; bit 1 without bit 0 and bits above 1 refused by name.
TEST(TemperatureVolume, PackageKeepsTheFlagAndRefusesItAlone) {
    const std::string path = writePackage("temperature-flag", {temperatureSlab()});
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    const PackageInfo& info = (*reader)->info();
    ASSERT_EQ(info.volumes.size(), 1u);
    EXPECT_TRUE(info.volumes[0].hasEmission);
    EXPECT_TRUE(info.volumes[0].volume.material.temperature);
    auto opened = (*reader)->openVolumes();
    ASSERT_TRUE(opened) << opened.message();
    EXPECT_TRUE((*opened)->at(0).material.temperature);
    EXPECT_TRUE((*opened)->at(0).hasEmission());

    const std::vector<uint8_t> original = test::fileBytes(path);
    uint64_t recordAt = 0;
    std::memcpy(&recordAt, original.data() + 256 - 24, 8);
    for (const uint32_t flags : {2u, 12u, 16u, 23u}) {
        const std::string forged = path + ".flags" + std::to_string(flags) + ".vast";
        test::writeBytes(forged, test::forgeVolumeData(original, info.volumes[0], [&](std::vector<uint8_t>& bytes) {
            std::memcpy(bytes.data() + recordAt + 160, &flags, 4);  // the record's flags word
        }));
        auto refused = PackageReader::open(forged);
        ASSERT_FALSE(refused) << flags;
        // Bits 2-3 are the codec (3: none); above them nothing is defined.
        const std::string words = flags == 2    ? "volume 0 'test': flags 2: a temperature grid without an emission grid"
                                  : flags == 12 ? "volume 0 'test': unknown brick codec 3"
                                                : "volume 0 'test': unknown flags " + std::to_string(flags & ~12u);
        EXPECT_NE(refused.message().find(words), std::string::npos) << refused.message();
    }
}

// A wide slab of 1,024 bricks whose temperatures vary from brick to brick, its bricks read from
// the package as a render opens them, paged through a pool of about a quarter of them (a budget of
// half the volume's bytes): the image equals the in-core one bit for bit (the table travels with
// the paged layout too), and the Embree reference agrees with the device's mean within 1 %.
TEST(TemperatureVolume, PagedTemperatureBricksRenderTheSame) {
    Volume slab = test::makeVolume({0, 1, 0}, {255, 4, 255}, [](int32_t, int32_t, int32_t) { return 1.0f; }, 0.25f,
                                   {-32, 0, -32}, temperatureSlab().material);
    slab.emissionVoxels.resize(slab.voxels.size());
    for (size_t i = 0; i < slab.emissionVoxels.size(); ++i)
        slab.emissionVoxels[i] = 1500.0f + 9.0f * float((i / kVolumeBrickVoxels) % 1000);
    const std::string path = writePackage("temperature-paged", {std::move(slab)});
    RenderOptions o;
    o.width = 32, o.height = 24;
    o.samplesPerPixel = 4;
    o.frameScene = false;
    o.camera.eye = {0, 40, 0.01f};
    o.camera.target = {0, 0, 0};
    o.camera.up = {0, 0, 1};
    o.camera.fovYDegrees = 70.0f;
    o.environment.zenith = o.environment.horizon = o.environment.ground = {0, 0, 0};
    o.environment.sunIrradiance = {0, 0, 0};
    o.volumes = PackageReader::open(path).value()->openVolumes().value();
    ASSERT_EQ((*o.volumes)[0].brickCount(), 1024u);
    auto inCore = test::renderVulkan(path, o, 256ull << 20);
    ASSERT_TRUE(inCore) << inCore.message();
    const PackageInfo info = PackageReader::open(path).value()->info();
    StreamingStats stats;
    auto paged = test::renderVulkan(path, o, gpu::volumeBytes(info) / 2, &stats);
    ASSERT_TRUE(paged) << paged.message();
    EXPECT_GT(stats.volumeBrickSlots, 0u);
    EXPECT_LT(stats.volumeBrickSlots, 1024u);
    EXPECT_EQ(std::memcmp(paged->rgb.data(), inCore->rgb.data(), inCore->rgb.size() * 4), 0);
    o.volumes = PackageReader::open(path).value()->readVolumes().value();
    auto reference = test::renderEmbree(path, o);
    ASSERT_TRUE(reference) << reference.message();
    double device = 0, embree = 0;
    for (size_t i = 0; i < inCore->rgb.size(); ++i) device += inCore->rgb[i], embree += reference->rgb[i];
    std::printf("device sum %.4f, embree sum %.4f, %llu brick slots\n", device, embree,
                (unsigned long long)stats.volumeBrickSlots);
    EXPECT_GT(device, 0.0);
    EXPECT_NEAR(device, embree, 0.01 * embree);
}

}  // namespace
}  // namespace vastray
