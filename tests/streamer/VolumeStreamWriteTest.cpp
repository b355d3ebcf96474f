// Volumes written to a package brick by brick: a volume opened with openVdbVolume (its voxels
// left in the .vdb), or in a child process (its bricks spooled to a temporary file), gives the
// same package bytes as the volume read whole into memory, and its
// data section is the layout docs/PACKAGE_FORMAT.md "Volumes" gives (cell table, brick index,
// bricks), computed here from the voxels; a brick that cannot be read fails the write and leaves
// no file behind.
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <string>

#include "../VolumePackageForge.h"
#include "../VolumeTestSupport.h"
#include "TestTmp.h"
#include "vastray/core/Checksum.h"
#include "vastray/core/VolumeLeaf.h"
#include "vastray/streamer/VolumeImport.h"

namespace vastray::test {
namespace {

using openvdb::Coord;
using openvdb::CoordBBox;
using openvdb::FloatGrid;

constexpr const char* kFolder = "volume-stream";

std::string streamVdbPath(const std::string& name) {
    std::filesystem::create_directories(testTmpDir(kFolder));
    return (testTmpDir(kFolder) / name).string();
}

uint32_t hash(int32_t i, int32_t j, int32_t k) {
    uint32_t h = uint32_t(i) * 73856093u ^ uint32_t(j) * 19349663u ^ uint32_t(k) * 83492791u;
    h ^= h >> 16, h *= 0x7feb352du, h ^= h >> 15;
    return h;
}

// A density grid with every kind of brick: 9 x 5 x 5 cells of leaves of hashed values (one voxel
// in 8 inactive, one in 16 zero), a 64^3 region of active tiles (512 bricks) and a lone voxel far
// off; and an emission grid "heat" over part of the leaves, one tile, and a voxel where the
// density has no brick (dropped). 738 bricks: several of the writer's batches (128 bricks).
std::string gridsFile() {
    openvdb::initialize();
    FloatGrid::Ptr density = FloatGrid::create(0.0f), heat = FloatGrid::create(0.0f);
    density->setName("density");
    heat->setName("heat");
    for (auto* grid : {density.get(), heat.get()})
        grid->setTransform(openvdb::math::Transform::createLinearTransform(0.125));
    // No ValueAccessor: a tree that has registered one iterates its accessor registry when it is
    // filled or destroyed, and that is undefined behaviour inside TBB's hash map (UBSan: a
    // misaligned downcast in concurrent_hash_map.h), not ours to fix; the tree's own setValue
    // does without.
    FloatGrid::TreeType& d = density->tree();
    FloatGrid::TreeType& e = heat->tree();
    for (int32_t k = 1; k < 40; ++k)
        for (int32_t j = 1; j < 40; ++j)
            for (int32_t i = 1; i < 72; ++i) {
                const uint32_t h = hash(i, j, k);
                if (h % 8 == 0) continue;
                d.setValue(Coord(i, j, k), h % 16 == 1 ? 0.0f : float(h >> 8) / float(1 << 23));
                if (i < 30 && h % 3 == 0) e.setValue(Coord(i, j, k), 100.0f + float(h % 1000) / 10.0f);
            }
    density->fill(CoordBBox(Coord(128, 0, 0), Coord(191, 63, 63)), 0.75f, true);
    heat->fill(CoordBBox(Coord(128, 0, 0), Coord(135, 7, 7)), 40.0f, true);
    d.setValue(Coord(-300, 5, 7), 3.0f);
    e.setValue(Coord(-600, 5, 7), 9.0f);
    const std::string path = streamVdbPath("grids.vdb");
    openvdb::io::File file(path);
    file.write({density, heat});
    file.close();
    return path;
}

// A version 14 volume data section from the voxels, as docs/PACKAGE_FORMAT.md lays it out: each
// brick a NanoVDB float leaf (core/VolumeLeaf.h; its layout is checked in VolumeLeafTest).
std::vector<uint8_t> expectedVolumeData(const Volume& v) {
    std::vector<uint8_t> out(v.brickOf.size() * 4);
    std::memcpy(out.data(), v.brickOf.data(), out.size());
    const bool emission = !v.emissionVoxels.empty();
    const size_t leafBytes = volumeLeafBytes(VolumeCodec::Float), brickBytes = leafBytes * (emission ? 2 : 1);
    const std::vector<std::array<int32_t, 3>> origins = volumeBrickOrigins(v);
    std::vector<uint8_t> bricks;
    for (uint64_t b = 0; b < v.brickCount(); ++b) {
        std::vector<uint8_t> brick(brickBytes);
        std::vector<float> density(v.voxels.begin() + b * kVolumeBrickVoxels, v.voxels.begin() + (b + 1) * kVolumeBrickVoxels);
        encodeVolumeLeaf(VolumeCodec::Float, origins[b], density.data(), brick.data());
        if (emission) {
            std::vector<float> glow(v.emissionVoxels.begin() + b * kVolumeBrickVoxels,
                                    v.emissionVoxels.begin() + (b + 1) * kVolumeBrickVoxels);
            encodeVolumeLeaf(VolumeCodec::Float, origins[b], glow.data(), brick.data() + leafBytes);
        }
        const uint64_t sum = checksum64(brick.data(), brick.size());
        const float largest = *std::max_element(density.begin(), density.end());
        const uint32_t reserved = 0;
        for (auto [p, n] : {std::pair<const void*, size_t>{&sum, 8}, {&largest, 4}, {&reserved, 4}})
            out.insert(out.end(), static_cast<const uint8_t*>(p), static_cast<const uint8_t*>(p) + n);
        bricks.insert(bricks.end(), brick.begin(), brick.end());
    }
    out.insert(out.end(), bricks.begin(), bricks.end());
    return out;
}

std::string packagePath(const std::string& name) { return (testTmpDir(kFolder) / (name + ".vast")).string(); }

TEST(VolumeStreamWrite, StreamedBricksGiveTheBytesOfTheWholeVolume) {
    const std::string vdb = gridsFile();
    VolumeMaterial material;
    material.emission = {1.0f, 0.5f, 0.25f};
    for (const std::string emission : {"", "heat"}) {
        SCOPED_TRACE("emission grid '" + emission + "'");
        auto whole = readVdbVolume(vdb, "density", material, emission);
        auto streamed = openVdbVolume(vdb, "density", material, emission);
        ASSERT_TRUE(whole) << whole.message();
        ASSERT_TRUE(streamed) << streamed.message();
        ASSERT_EQ(whole->brickCount(), 738u);
        EXPECT_TRUE(streamed->voxels.empty() && streamed->emissionVoxels.empty() && streamed->bricks.source);
        EXPECT_EQ(streamed->brickCount(), whole->brickCount());
        EXPECT_EQ(streamed->hasEmission(), !emission.empty());
        EXPECT_EQ(streamed->brickOf, whole->brickOf);
        EXPECT_EQ(streamed->majorant, whole->majorant);
        if (!emission.empty()) {  // the tile's 40 and the leaves' values landed; the far voxel's 9 did not
            const auto& glow = whole->emissionVoxels;
            EXPECT_EQ(std::count(glow.begin(), glow.end(), 40.0f), 512);
            EXPECT_GT(std::count_if(glow.begin(), glow.end(), [](float x) { return x >= 100.0f; }), 1000);
            EXPECT_EQ(std::count(glow.begin(), glow.end(), 9.0f), 0);
        }
        const std::string name = emission.empty() ? "plain" : "glowing";
        const std::string a = writeVolumePackage(kFolder, name + "-whole", farTriangle(300), {*whole});
        const std::string b = writeVolumePackage(kFolder, name + "-streamed", farTriangle(300), {*streamed});
        const std::vector<uint8_t> bytes = fileBytes(b);
        EXPECT_TRUE(fileBytes(a) == bytes) << "the streamed package's bytes differ from the whole volume's";
        // The service's path: a child process opens the volume and spools its bricks to a file.
        VolumeSource source{vdb, "density", emission, material, {}, {}};
        VolumeReadOptions child;
        child.childProcess = true;
        auto spooled = readVolumes({source}, child);
        ASSERT_TRUE(spooled) << spooled.message();
        EXPECT_TRUE((*spooled)[0].voxels.empty() && (*spooled)[0].bricks.source);
        const std::string c = writeVolumePackage(kFolder, name + "-spooled", farTriangle(300), {(*spooled)[0]});
        EXPECT_TRUE(fileBytes(c) == bytes) << "the child process's package differs from the whole volume's";

        auto reader = PackageReader::open(b);
        ASSERT_TRUE(reader) << reader.message();
        const PackageVolume& p = (*reader)->info().volumes.at(0);
        const std::vector<uint8_t> expected = expectedVolumeData(*whole);
        ASSERT_EQ(p.size, expected.size());
        ASSERT_LE(p.offset + p.size, bytes.size());
        EXPECT_TRUE(std::equal(expected.begin(), expected.end(), bytes.begin() + int64_t(p.offset)));
        EXPECT_EQ(p.checksum, checksum64(expected.data(), whole->brickOf.size() * 4 + 16 * whole->brickCount()));
        auto back = (*reader)->readVolumes();
        ASSERT_TRUE(back) << back.message();
        EXPECT_TRUE((**back)[0].voxels == whole->voxels);
        EXPECT_TRUE((**back)[0].emissionVoxels == whole->emissionVoxels);
    }
}

// Serves a volume's bricks from memory and fails at one of them, as a .vdb cut or changed under
// an opened volume does.
class FailingBricks final : public VolumeBrickSource {
public:
    FailingBricks(Volume whole, uint32_t failAt) : whole_(std::move(whole)), failAt_(failAt) {}
    Status readBrick(uint32_t, uint32_t brick, float* density, float* emission, uint8_t*) const override {
        if (brick == failAt_) return Status::error("slab.vdb: brick " + std::to_string(brick) + " is unreadable");
        ++served;
        return readVolumeBrick(whole_, brick, density, emission);
    }
    mutable uint32_t served = 0;

private:
    Volume whole_;
    uint32_t failAt_;
};

TEST(VolumeStreamWrite, BrickFailingHalfWayLeavesNoPackage) {
    Volume slab = makeVolume({0, 0, 0}, {255, 15, 63}, [](int32_t i, int32_t, int32_t) { return 0.01f * float(i % 7); });
    ASSERT_EQ(slab.brickCount(), 32u * 2 * 8);
    Volume streamed = slab;
    auto source = std::make_shared<FailingBricks>(slab, 300);
    streamed.bricks = {source, 0, slab.brickCount(), false};
    streamed.voxels.clear();
    const std::string path = packagePath("failed");
    std::filesystem::remove(path);
    PackageBuildOptions options;
    options.progress = Progress::Mode::None;
    options.volumes = {streamed};
    auto report = buildPackage(farTriangle(300), path, options);
    ASSERT_FALSE(report);
    EXPECT_NE(report.message().find("slab.vdb: brick 300 is unreadable"), std::string::npos) << report.message();
    EXPECT_EQ(source->served, 300u);  // bricks 0 to 299, in order, then the failure
    EXPECT_FALSE(std::filesystem::exists(path));
    EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
}

// A .vdb cut short after its volume was opened (its grids scanned): the brick whose leaf lies past
// the cut fails the write, naming the file, and no package is left.
TEST(VolumeStreamWrite, VdbCutAfterOpeningFailsTheWriteByName) {
    const std::string vdb = streamVdbPath("cut-later.vdb");
    std::filesystem::copy_file(gridsFile(), vdb, std::filesystem::copy_options::overwrite_existing);
    auto streamed = openVdbVolume(vdb, "density", {});
    ASSERT_TRUE(streamed) << streamed.message();
    std::filesystem::resize_file(vdb, std::filesystem::file_size(vdb) / 3);
    const std::string path = packagePath("cut-later");
    std::filesystem::remove(path);
    PackageBuildOptions options;
    options.progress = Progress::Mode::None;
    options.volumes = {*streamed};
    auto report = buildPackage(farTriangle(300), path, options);
    ASSERT_FALSE(report);
    EXPECT_NE(report.message().find("cut-later.vdb: ends before the data it describes"), std::string::npos)
        << report.message();
    EXPECT_FALSE(std::filesystem::exists(path));
    EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
}

}  // namespace
}  // namespace vastray::test
