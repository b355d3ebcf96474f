// Volume bricks read from the package on demand (format 6, docs/PACKAGE_FORMAT.md "Volumes";
// docs/RENDERING.md "Volumes out of core"): a paged render reads only the bricks its rays ask
// for, and equals the in-core render bit for bit; a damaged brick fails the render naming the
// package, the volume and the brick, unless no ray reaches it; a version 5 package (its volume
// read whole) renders the same image.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>

#include "../StreamTestSupport.h"
#include "../VolumePackageForge.h"
#include "../VolumeTestSupport.h"
#include "TestTmp.h"
#include "vastray/streamer/PackageBuilder.h"

namespace vastray {
namespace {

constexpr float kVoxel = 0.25f;  // world units per voxel

std::string packagePath(const std::string& name) {
    return (test::testTmpDir("volume-bricks") / (name + ".vast")).string();
}

// A thin absorbing slab of 512 x 16 x 128 voxels (64 x 2 x 16 = 2,048 bricks, every one
// stored) at world [0, 128) x [0, 4) x [0, 32), and one small triangle far outside the view.
const std::string& thinSlab() {
    static const std::string path = [] {
        VolumeMaterial absorber;
        absorber.albedo = {0, 0, 0};
        absorber.densityScale = 0.5f;  // density 0.5 over 4 world units of depth: tau = 1
        Volume slab = test::makeVolume({0, 0, 0}, {511, 15, 127}, [](int32_t, int32_t, int32_t) { return 0.5f; },
                                       kVoxel, {0, 0, 0}, absorber);
        slab.name = "slab";
        std::vector<Volume> volumes;
        volumes.push_back(std::move(slab));
        return test::writeVolumePackage("volume-bricks", "thin-slab", test::farTriangle(300), std::move(volumes));
    }();
    return path;
}

// Looking straight down onto a patch of about 4 x 4 world units near the slab's x = 0 end: the
// rays cross 2 of the 64 brick columns along x.
RenderOptions lookingDown(const std::shared_ptr<const std::vector<Volume>>& volumes) {
    RenderOptions o;
    o.width = o.height = 16;
    o.samplesPerPixel = 4;
    o.maxDepth = 2;
    o.frameScene = false;
    o.camera.eye = {4.0f, 40.0f, 4.0f};
    o.camera.target = {4.0f, 0.0f, 4.0f};
    o.camera.up = {0, 0, 1};
    o.camera.fovYDegrees = 6.0f;
    o.volumes = volumes;
    return o;
}

std::shared_ptr<const std::vector<Volume>> openVolumes(const PackageReader& reader) {
    auto volumes = reader.openVolumes();
    EXPECT_TRUE(volumes) << volumes.message();
    return volumes ? *volumes : nullptr;
}

// A render through an open reader (renderVulkan opens its own, which a truncated file fails).
Result<RenderImage> renderOpen(const PackageReader& reader, const RenderOptions& o, uint64_t budget,
                               StreamingStats* stats) {
    stats->memoryBudgetBytes = budget;
    return renderStreaming(
        reader, o, StreamingOptions{},
        [&](const PackageInfo& info, const ChunkAttributes& a) {
            return gpu::createVulkanChunkBackend(test::sharedVulkanDevice(), info, a, budget, gpu::kWaveShareOutOfCore, {},
                                                 gpu::volumeReserveBytes(info, budget));
        },
        nullptr, stats);
}

// The budget that pages the slab's bricks through a pool of about a fifth of them.
uint64_t pagedBudget(const PackageInfo& info) { return gpu::volumeBytes(info) / 2; }

// The stored brick holding voxel ijk of the slab.
uint32_t brickAt(const Volume& v, int32_t i, int32_t j, int32_t k) {
    const int32_t b = int32_t(kVolumeBrickSize);
    const uint64_t cx = uint64_t((i - v.origin[0]) / b), cy = uint64_t((j - v.origin[1]) / b),
                   cz = uint64_t((k - v.origin[2]) / b);
    return v.brickOf[cx + v.brickCells[0] * (cy + v.brickCells[1] * cz)];
}

TEST(VolumeBrickRead, PagedRenderReadsOnlyTheBricksItsRaysReach) {
    auto reader = PackageReader::open(thinSlab());
    ASSERT_TRUE(reader) << reader.message();
    const PackageInfo& info = (*reader)->info();
    ASSERT_GE(info.formatVersion, 6u);  // brick by brick from version 6
    const RenderOptions o = lookingDown(openVolumes(**reader));
    ASSERT_TRUE(o.volumes);
    const Volume& slab = (*o.volumes)[0];
    ASSERT_TRUE(slab.voxels.empty()) << "the bricks stay in the package";
    const uint64_t bricks = slab.brickCount();
    ASSERT_EQ(bricks, 2048u);

    StreamingStats inCoreStats;
    auto inCore = renderOpen(**reader, o, 256ull << 20, &inCoreStats);
    ASSERT_TRUE(inCore) << inCore.message();
    EXPECT_EQ(inCoreStats.volumeBrickSlots, 0u);
    EXPECT_EQ(inCoreStats.volumeBricksRead, bricks) << "in core, every brick is read once";

    const uint64_t budget = pagedBudget(info);
    StreamingStats stats;
    auto paged = renderOpen(**reader, o, budget, &stats);
    ASSERT_TRUE(paged) << paged.message();
    std::printf("paged: %llu slots, %llu loads, %llu of %llu bricks read, peak device %llu of %llu bytes\n",
                (unsigned long long)stats.volumeBrickSlots, (unsigned long long)stats.volumeBrickLoads,
                (unsigned long long)stats.volumeBricksRead, (unsigned long long)bricks,
                (unsigned long long)stats.peakDeviceBytes, (unsigned long long)budget);
    EXPECT_GT(stats.volumeBrickSlots, 0u);
    EXPECT_LT(stats.volumeBrickSlots, bricks / 2) << "the bricks are paged";
    EXPECT_GT(stats.volumeBricksRead, 0u);
    // The rays cross 2 of 64 brick columns along x; their light rays go further, and a step
    // whose waited bricks do not fit loads a region (at most a pool's worth of bricks).
    EXPECT_LE(stats.volumeBricksRead, 2 * stats.volumeBrickSlots) << "bricks no ray reaches were read";
    EXPECT_LT(stats.volumeBricksRead, bricks / 2) << "bricks no ray reaches were read";
    EXPECT_LE(stats.volumeBricksRead, stats.volumeBrickLoads);
    EXPECT_LE(stats.peakDeviceBytes, budget);
    // The slab is in the picture (a clear sky would make any brick policy look equal).
    float darkest = 1e30f, brightest = 0.0f;
    for (size_t p = 0; p < paged->alpha.size(); ++p)
        darkest = std::min(darkest, paged->rgb[3 * p]), brightest = std::max(brightest, paged->rgb[3 * p]);
    EXPECT_LT(darkest, brightest);
    EXPECT_EQ(std::memcmp(paged->rgb.data(), inCore->rgb.data(), inCore->rgb.size() * 4), 0);
    EXPECT_EQ(std::memcmp(paged->alpha.data(), inCore->alpha.data(), inCore->alpha.size() * 4), 0);
}

// Camera rays only (max depth 0: no light or bounce rays) through the slab: the paged render reads
// no brick outside the cells those rays can touch, counted here from the view alone: the box the
// view's pyramid cuts out of the slab's depth, grown by one cell (a walk's trilinear reads touch
// the cells after the one it samples; rounding reaches one back). The bricks the rays ask for
// ahead lie along them, in the same box. Loading a region per step read ten times as many.
TEST(VolumeBrickRead, CameraRaysReadOnlyTheBricksOfTheCellsTheyCross) {
    auto reader = PackageReader::open(thinSlab());
    ASSERT_TRUE(reader) << reader.message();
    RenderOptions o = lookingDown(openVolumes(**reader));
    ASSERT_TRUE(o.volumes);
    o.maxDepth = 0;
    const Volume& slab = (*o.volumes)[0];
    // The slab spans world y in [0, 4); the view looks straight down from eye.y, square, so the
    // pyramid's half-width at the slab's bottom is eye.y tan(fov / 2) on x and on z.
    const float half = o.camera.eye[1] * std::tan(0.5f * o.camera.fovYDegrees * 3.14159265f / 180.0f);
    // Voxel i lies at world i kVoxel; brick cell c holds voxels origin + 8c to origin + 8c + 7.
    auto cellRange = [&](float centre, int a) {
        auto cell = [&](float world) {
            return int64_t(std::floor((world / kVoxel - float(slab.origin[a])) / float(kVolumeBrickSize)));
        };
        return std::pair{std::max<int64_t>(cell(centre - half) - 1, 0), cell(centre + half) + 1};
    };
    const auto [x0, x1] = cellRange(o.camera.eye[0], 0);
    const auto [z0, z1] = cellRange(o.camera.eye[2], 2);
    uint64_t reachable = 0;
    for (int64_t z = z0; z <= std::min<int64_t>(z1, slab.brickCells[2] - 1); ++z)
        for (int64_t y = 0; y < slab.brickCells[1]; ++y)
            for (int64_t x = x0; x <= std::min<int64_t>(x1, slab.brickCells[0] - 1); ++x)
                reachable += slab.brickOf[uint64_t(x + slab.brickCells[0] * (y + slab.brickCells[1] * z))] != kNoBrick;
    ASSERT_GT(reachable, 0u);
    ASSERT_LT(reachable, slab.brickCount() / 20) << "the view is not narrow";

    StreamingStats inCoreStats;
    auto inCore = renderOpen(**reader, o, 256ull << 20, &inCoreStats);
    ASSERT_TRUE(inCore) << inCore.message();
    StreamingStats stats;
    const uint64_t budget = pagedBudget((*reader)->info());
    auto paged = renderOpen(**reader, o, budget, &stats);
    ASSERT_TRUE(paged) << paged.message();
    std::printf("camera rays: %llu bricks read, %llu reachable, %llu slots\n", (unsigned long long)stats.volumeBricksRead,
                (unsigned long long)reachable, (unsigned long long)stats.volumeBrickSlots);
    EXPECT_GT(stats.volumeBrickSlots, reachable) << "the pool could hold a region wider than the view";
    EXPECT_GT(stats.volumeBricksRead, 0u);
    EXPECT_LE(stats.volumeBricksRead, reachable) << "bricks no ray reaches were read";
    EXPECT_LE(stats.peakDeviceBytes, budget);
    EXPECT_EQ(std::memcmp(paged->rgb.data(), inCore->rgb.data(), inCore->rgb.size() * 4), 0);
    EXPECT_EQ(std::memcmp(paged->alpha.data(), inCore->alpha.data(), inCore->alpha.size() * 4), 0);
}

// Damaged bricks, each in a copy of the slab's package: the paged render that reaches one fails
// naming it; a flipped byte in a brick no ray reaches costs nothing (it is never read).
TEST(VolumeBrickRead, DamagedBricksFailTheRenderByNameUnlessNoRayReachesThem) {
    auto clean = PackageReader::open(thinSlab());
    ASSERT_TRUE(clean) << clean.message();
    const PackageInfo info = (*clean)->info();
    const PackageVolume& p = info.volumes[0];
    const auto volumes = openVolumes(**clean);
    ASSERT_TRUE(volumes);
    const uint32_t reached = brickAt((*volumes)[0], 16, 8, 16), unreached = brickAt((*volumes)[0], 500, 8, 120);
    ASSERT_NE(reached, kNoBrick);
    ASSERT_NE(unreached, kNoBrick);
    StreamingStats cleanStats;
    auto expected = renderOpen(**clean, lookingDown(volumes), pagedBudget(info), &cleanStats);
    ASSERT_TRUE(expected) << expected.message();

    const std::vector<uint8_t> original = test::fileBytes(thinSlab());
    auto render = [&](const std::vector<uint8_t>& bytes, StreamingStats* stats) -> Result<RenderImage> {
        const std::string path = packagePath("damaged");
        test::writeBytes(path, bytes);
        auto reader = PackageReader::open(path);
        if (!reader) return reader.status();
        auto opened = (*reader)->openVolumes();
        if (!opened) return opened.status();
        return renderOpen(**reader, lookingDown(*opened), pagedBudget(info), stats);
    };
    auto flipped = [&](uint32_t brick) {
        std::vector<uint8_t> bytes = original;
        bytes[test::brickOffset(p, brick) + 100] ^= 0x40;
        return bytes;
    };
    const std::string name = "volume 0 'slab': brick " + std::to_string(reached);

    StreamingStats stats;
    auto unharmed = render(flipped(unreached), &stats);
    ASSERT_TRUE(unharmed) << unharmed.message();
    EXPECT_EQ(std::memcmp(unharmed->rgb.data(), expected->rgb.data(), expected->rgb.size() * 4), 0);

    auto refused = render(flipped(reached), &stats);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.message().find("damaged.vast: " + name + ": checksum mismatch"), std::string::npos)
        << refused.message();

    // Forged with the checksums recomputed: a NaN voxel, then a voxel above the largest density
    // the brick index records (the majorants were computed from it).
    auto withVoxel = [&](float value) {
        return test::forgeVolumeData(original, p, [&](std::vector<uint8_t>& b) {
            std::memcpy(b.data() + test::voxelOffset(p, reached, 9), &value, 4);
        });
    };
    refused = render(withVoxel(std::nanf("")), &stats);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.message().find(name + " voxel 9 has density nan"), std::string::npos) << refused.message();
    // A leaf header other than the one a writer writes (NanoVDB's flags byte, 15).
    refused = render(test::forgeVolumeData(original, p, [&](std::vector<uint8_t>& b) { b[test::brickOffset(p, reached) + 15] = 7; }),
                     &stats);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.message().find(name + " (a NanoVDB float leaf): its flags are 7, not 2"), std::string::npos)
        << refused.message();
    // The brick index itself is checked when the volumes open, before any brick is read.
    refused = render(test::forgeVolumeData(original, p,
                                           [&](std::vector<uint8_t>& b) {
                                               const float nan = std::nanf("");
                                               std::memcpy(b.data() + p.offset + 4 * p.volume.cellCount() +
                                                               16ull * unreached + 8,
                                                           &nan, 4);
                                           }),
                     &stats);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.message().find("volume 0 'slab': brick " + std::to_string(unreached) +
                                     ": largest density nan is not in [0, 1e18]"),
              std::string::npos)
        << refused.message();
    refused = render(withVoxel(0.75f), &stats);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.message().find(name + ": its largest density 0.750000 is not the one its brick index records "
                                            "(0.500000)"),
              std::string::npos)
        << refused.message();
}

// A forged cell table where two cells name one brick (checksums recomputed) is refused when the
// volumes open, naming both cells and the brick.
TEST(VolumeBrickRead, TwoCellsNamingOneBrickAreRefusedWhenTheVolumesOpen) {
    auto clean = PackageReader::open(thinSlab());
    ASSERT_TRUE(clean) << clean.message();
    const PackageVolume& p = (*clean)->info().volumes[0];
    const auto volumes = openVolumes(**clean);
    ASSERT_TRUE(volumes);
    const std::vector<uint32_t>& brickOf = (*volumes)[0].brickOf;
    std::vector<uint64_t> cells;  // the first two cells that hold a brick
    for (uint64_t c = 0; c < brickOf.size() && cells.size() < 2; ++c)
        if (brickOf[c] != kNoBrick) cells.push_back(c);
    ASSERT_EQ(cells.size(), 2u);
    const std::string path = packagePath("shared-brick");
    test::writeBytes(path, test::forgeVolumeData(test::fileBytes(thinSlab()), p, [&](std::vector<uint8_t>& b) {
        std::memcpy(b.data() + p.offset + 4 * cells[1], &brickOf[cells[0]], 4);  // the second names the first's brick
    }));
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    auto refused = (*reader)->openVolumes();
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.message().find("shared-brick.vast: volume 0 'slab': cells " + std::to_string(cells[0]) + " and " +
                                     std::to_string(cells[1]) + " both name brick " + std::to_string(brickOf[cells[0]]) +
                                     " (a brick belongs to one cell)"),
              std::string::npos)
        << refused.message();
}

// The file loses its last bytes after the package opened (it was checked whole then): the brick
// that is no longer there fails the render by name.
TEST(VolumeBrickRead, TruncatedPackageFailsTheRenderNamingTheBrick) {
    const std::string path = packagePath("truncated");
    std::filesystem::copy_file(thinSlab(), path, std::filesystem::copy_options::overwrite_existing);
    auto reader = PackageReader::open(path);
    ASSERT_TRUE(reader) << reader.message();
    const PackageVolume& p = (*reader)->info().volumes[0];
    const auto volumes = openVolumes(**reader);
    ASSERT_TRUE(volumes);
    std::filesystem::resize_file(path, test::brickOffset(p, 0) + 100);
    StreamingStats stats;
    auto refused = renderOpen(**reader, lookingDown(volumes), pagedBudget((*reader)->info()), &stats);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.message().find("truncated.vast: volume 0 'slab': brick "), std::string::npos) << refused.message();
    EXPECT_NE(refused.message().find("cannot read its 2144 bytes"), std::string::npos) << refused.message();
}

// A version 5 package (the slab's data whole under one checksum) still opens and renders, paged,
// the same image: its volume is read whole when it opens, so no brick is read during the render.
TEST(VolumeBrickRead, VersionFivePackageRendersTheSame) {
    auto current = PackageReader::open(thinSlab());
    ASSERT_TRUE(current) << current.message();
    const PackageInfo info = (*current)->info();
    StreamingStats stats;
    auto expected = renderOpen(**current, lookingDown(openVolumes(**current)), pagedBudget(info), &stats);
    ASSERT_TRUE(expected) << expected.message();

    const std::string path = packagePath("version5");
    test::writeBytes(path, test::asVersion5(test::fileBytes(thinSlab()), info.volumes[0]));
    auto old = PackageReader::open(path);
    ASSERT_TRUE(old) << old.message();
    EXPECT_EQ((*old)->info().formatVersion, 5u);
    EXPECT_TRUE((*old)->verify().empty());
    const auto volumes = openVolumes(**old);
    ASSERT_TRUE(volumes);
    EXPECT_EQ((*volumes)[0].voxels.size(), info.volumes[0].brickCount * kVolumeBrickVoxels);
    EXPECT_EQ((*volumes)[0].majorant, (*openVolumes(**current))[0].majorant);
    StreamingStats oldStats;
    auto image = renderOpen(**old, lookingDown(volumes), pagedBudget(info), &oldStats);
    ASSERT_TRUE(image) << image.message();
    EXPECT_GT(oldStats.volumeBrickSlots, 0u);
    EXPECT_EQ(oldStats.volumeBricksRead, 0u);
    EXPECT_EQ(std::memcmp(image->rgb.data(), expected->rgb.data(), expected->rgb.size() * 4), 0);
}

// The Embree reference tracks volumes in host memory: it takes them read whole (readVolumes,
// the same image as the device's within noise elsewhere) and refuses them left in the package.
TEST(VolumeBrickRead, EmbreeNeedsTheVoxelsInMemory) {
    auto reader = PackageReader::open(thinSlab());
    ASSERT_TRUE(reader) << reader.message();
    RenderOptions o = lookingDown(openVolumes(**reader));
    o.width = o.height = 4;
    auto refused = test::renderEmbree(thinSlab(), o);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.message().find("volume 'slab': the Embree renderer needs its voxels in memory"), std::string::npos)
        << refused.message();
    o.volumes = (*reader)->readVolumes().value();
    auto image = test::renderEmbree(thinSlab(), o);
    EXPECT_TRUE(image) << image.message();
}

}  // namespace
}  // namespace vastray
