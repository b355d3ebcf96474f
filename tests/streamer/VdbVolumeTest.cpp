// readVdbVolume on .vdb files written here with OpenVDB: voxels, active tiles, grid choice and
// transform land where OpenVDB put them; hostile files are refused naming the file and the cause.
#include <gtest/gtest.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <random>
#include <string>

#include "TestTmp.h"
#include "vastray/core/Blackbody.h"
#include "vastray/streamer/VolumeImport.h"

namespace vastray::test {
namespace {

using openvdb::Coord;
using openvdb::CoordBBox;
using openvdb::FloatGrid;

std::string vdbPath(const std::string& name) { return (testTmpDir("vdb") / name).string(); }

std::string writeVdb(const std::string& name, const openvdb::GridPtrVec& grids,
                     uint32_t compression = openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK) {
    openvdb::initialize();
    const std::string path = vdbPath(name);
    openvdb::io::File file(path);
    file.setCompression(compression);
    file.write(grids);
    file.close();
    return path;
}

FloatGrid::Ptr densityGrid(float background = 0.0f) {
    openvdb::initialize();
    FloatGrid::Ptr grid = FloatGrid::create(background);
    grid->setName("density");
    return grid;
}

// One voxel of `value` at c, in a grid alone in file `name`.
std::string oneVoxelFile(const std::string& name, Coord c, float value) {
    FloatGrid::Ptr grid = densityGrid();
    grid->tree().setValue(c, value);
    return writeVdb(name, {grid});
}

::testing::AssertionResult refusedWith(const Result<Volume>& r, std::initializer_list<std::string> parts) {
    if (r.isOk()) return ::testing::AssertionFailure() << "accepted";
    for (const std::string& part : parts)
        if (r.message().find(part) == std::string::npos)
            return ::testing::AssertionFailure()
                   << "message \"" << r.message() << "\" lacks \"" << part << "\"";
    return ::testing::AssertionSuccess();
}

Result<Volume> read(const std::string& path, const std::string& grid = "") {
    return readVdbVolume(path, grid, {});
}

// A 20^3 box of density 2.5 from voxel (8, -5, 10) to (27, 14, 29) under a scaled, sheared and
// translated map. The brick grid must cover [lo - 1, hi + 1]: x from 0 (cell 0 holds no voxel,
// only interpolation's reach) to 31, y from -8 to 15, z from 8 to 31.
TEST(VdbVolume, DenseBoxLandsOnTheBrickGridWithItsTransform) {
    FloatGrid::Ptr grid = densityGrid();
    grid->denseFill(CoordBBox(Coord(8, -5, 10), Coord(27, 14, 29)), 2.5f, /*active=*/true);
    // Row vectors: world = (i, j, k, 1) * m, so world.y = 0.1 i + 0.25 j - 2.
    const openvdb::math::Mat4d m(0.5, 0.1, 0.0, 0.0,   //
                                 0.0, 0.25, 0.0, 0.0,  //
                                 0.0, 0.0, 2.0, 0.0,   //
                                 10.0, -2.0, 3.0, 1.0);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(m));
    VolumeMaterial material;
    material.densityScale = 4.0f;
    material.anisotropy = 0.3f;
    auto r = readVdbVolume(writeVdb("box.vdb", {grid}), "", material);
    ASSERT_TRUE(r.isOk()) << r.message();
    const Volume& v = *r;
    EXPECT_EQ(v.name, "density");
    EXPECT_EQ(v.material.densityScale, 4.0f);
    EXPECT_EQ(v.material.anisotropy, 0.3f);
    EXPECT_EQ(v.origin, (std::array<int32_t, 3>{0, -8, 8}));
    EXPECT_EQ(v.brickCells, (std::array<uint32_t, 3>{4, 3, 3}));
    // Cells with x index 1..3 hold voxels (27 bricks, numbered in cell order); x index 0 none.
    ASSERT_EQ(v.brickCount(), 27u);
    ASSERT_EQ(v.brickOf.size(), 36u);
    for (uint32_t c = 0; c < 36; ++c) {
        const uint32_t x = c % 4, yz = c / 4;
        EXPECT_EQ(v.brickOf[c], x == 0 ? kNoBrick : yz * 3 + (x - 1)) << "cell " << c;
    }
    // Every cell's majorant is 2.5: cell x = 0 reaches into x = 1 through interpolation.
    for (float majorant : v.majorant) EXPECT_EQ(majorant, 2.5f);
    EXPECT_EQ(volumeVoxel(v, 8, -5, 10), 2.5f);
    EXPECT_EQ(volumeVoxel(v, 27, 14, 29), 2.5f);
    EXPECT_EQ(volumeVoxel(v, 17, 0, 20), 2.5f);
    EXPECT_EQ(volumeVoxel(v, 7, 0, 20), 0.0f);
    EXPECT_EQ(volumeVoxel(v, 28, 0, 20), 0.0f);
    EXPECT_EQ(volumeVoxel(v, 17, 15, 20), 0.0f);
    EXPECT_EQ(volumeVoxel(v, 17, 0, 9), 0.0f);
    double sum = 0;
    for (float x : v.voxels) sum += x;
    EXPECT_EQ(sum, 8000 * 2.5);
    EXPECT_EQ(v.indexToWorld, (std::array<float, 12>{0.5f, 0, 0, 10, 0.1f, 0.25f, 0, -2, 0, 0, 2, 3}));
    // Against OpenVDB's own map at a few voxels (float entries: 1e-5 relative).
    for (Coord c : {Coord(8, -5, 10), Coord(27, 14, 29), Coord(-3, 7, 100)}) {
        const openvdb::Vec3d w = grid->transform().indexToWorld(c);
        const auto& a = v.indexToWorld;
        for (int r = 0; r < 3; ++r)
            EXPECT_NEAR(a[4 * r] * c.x() + a[4 * r + 1] * c.y() + a[4 * r + 2] * c.z() + a[4 * r + 3], w[r],
                        1e-5 * (1 + std::fabs(w[r])));
    }
    // The brick grid's box [0, 32] x [-8, 16] x [8, 32] in the world: x 0.5 i + 10, y 0.1 i +
    // 0.25 j - 2 (extremes at the box's corners), z 2 k + 3.
    EXPECT_NEAR(v.worldBounds.lo.x, 10.0f, 1e-4f);
    EXPECT_NEAR(v.worldBounds.hi.x, 26.0f, 1e-4f);
    EXPECT_NEAR(v.worldBounds.lo.y, -4.0f, 1e-4f);
    EXPECT_NEAR(v.worldBounds.hi.y, 5.2f, 1e-4f);
    EXPECT_NEAR(v.worldBounds.lo.z, 19.0f, 1e-4f);
    EXPECT_NEAR(v.worldBounds.hi.z, 67.0f, 1e-4f);
    EXPECT_EQ(checkVolume(v), "");
}

// fill() of aligned boxes makes tiles, not leaves: a 64^3 box becomes 8^3-voxel tiles one level
// above the leaves, a 128^3 box one tile two levels up. Both must land voxel for voxel.
TEST(VdbVolume, ActiveTilesFillTheirRegions) {
    FloatGrid::Ptr grid = densityGrid();
    grid->fill(CoordBBox(Coord(0, 0, 0), Coord(63, 63, 63)), 3.0f, true);
    grid->fill(CoordBBox(Coord(-128, 0, 0), Coord(-1, 127, 127)), 0.5f, true);
    grid->tree().setValue(Coord(200, 5, 5), 1.0f);
    ASSERT_EQ(grid->tree().leafCount(), 1u);  // the single voxel's; the rest are tiles
    uint64_t tiles = 0;
    for (auto it = grid->tree().cbeginValueOn(); it; ++it) tiles += it.isTileValue();
    ASSERT_EQ(tiles, 512u + 1u);
    auto r = read(writeVdb("tiles.vdb", {grid}));
    ASSERT_TRUE(r.isOk()) << r.message();
    const Volume& v = *r;
    EXPECT_EQ(v.origin, (std::array<int32_t, 3>{-136, -8, -8}));
    EXPECT_EQ(v.brickCells, (std::array<uint32_t, 3>{43, 18, 18}));
    EXPECT_EQ(v.brickCount(), 512u + 4096u + 1u);
    EXPECT_EQ(volumeVoxel(v, 0, 0, 0), 3.0f);
    EXPECT_EQ(volumeVoxel(v, 63, 63, 63), 3.0f);
    EXPECT_EQ(volumeVoxel(v, 31, 40, 7), 3.0f);
    EXPECT_EQ(volumeVoxel(v, 64, 0, 0), 0.0f);
    EXPECT_EQ(volumeVoxel(v, 0, 64, 0), 0.0f);
    EXPECT_EQ(volumeVoxel(v, -128, 0, 0), 0.5f);
    EXPECT_EQ(volumeVoxel(v, -1, 127, 127), 0.5f);
    EXPECT_EQ(volumeVoxel(v, -129, 0, 0), 0.0f);
    EXPECT_EQ(volumeVoxel(v, -64, 128, 0), 0.0f);
    EXPECT_EQ(volumeVoxel(v, 200, 5, 5), 1.0f);
    EXPECT_EQ(volumeVoxel(v, 200, 5, 6), 0.0f);
    double sum = 0;
    for (float x : v.voxels) sum += x;
    EXPECT_EQ(sum, 64.0 * 64 * 64 * 3 + 128.0 * 128 * 128 * 0.5 + 1);
}

TEST(VdbVolume, GridsAreChosenByNameOrTheFirstFloatOne) {
    FloatGrid::Ptr temperature = FloatGrid::create(0.0f);
    temperature->setName("temperature");
    temperature->tree().setValue(Coord(1, 1, 1), 7.0f);
    openvdb::Vec3SGrid::Ptr vel = openvdb::Vec3SGrid::create();
    vel->setName("vel");
    vel->tree().setValue(Coord(1, 1, 1), openvdb::Vec3s(1, 2, 3));
    FloatGrid::Ptr density = densityGrid();
    density->tree().setValue(Coord(1, 1, 1), 2.0f);
    const std::string path = writeVdb("several.vdb", {temperature, vel, density});

    auto named = read(path, "density");
    ASSERT_TRUE(named.isOk()) << named.message();
    EXPECT_EQ(named->name, "density");
    EXPECT_EQ(volumeVoxel(*named, 1, 1, 1), 2.0f);
    auto first = read(path);
    ASSERT_TRUE(first.isOk()) << first.message();
    EXPECT_EQ(first->name, "temperature");
    EXPECT_EQ(volumeVoxel(*first, 1, 1, 1), 7.0f);

    EXPECT_TRUE(refusedWith(read(path, "vel"),
                            {"several.vdb: grid 'vel' is of type vec3s; vastray reads float grids"}));
    EXPECT_TRUE(
        refusedWith(read(path, "temp"),
                    {"several.vdb: no grid named 'temp' (grids: temperature, vel (vec3s), density)"}));
    EXPECT_TRUE(refusedWith(read(writeVdb("velonly.vdb", {vel})),
                            {"velonly.vdb: no float grid (grids: vel (vec3s))"}));
}

// Two grids sharing one tree are written once: the second as an instance of the first, which
// reading it must fetch (under its own transform).
TEST(VdbVolume, InstancedGridReadsItsParentsVoxels) {
    FloatGrid::Ptr density = densityGrid();
    density->tree().setValue(Coord(2, 3, 4), 6.0f);
    FloatGrid::Ptr copy = density->copy();  // shares the tree
    copy->setName("copy");
    copy->setTransform(openvdb::math::Transform::createLinearTransform(2.0));
    auto r = read(writeVdb("instance.vdb", {density, copy}), "copy");
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(r->name, "copy");
    EXPECT_EQ(volumeVoxel(*r, 2, 3, 4), 6.0f);
    EXPECT_EQ(r->brickCount(), 1u);
    EXPECT_EQ(r->indexToWorld, (std::array<float, 12>{2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0}));
}

// A file written to a stream has no grid offsets: its grids are read in order.
TEST(VdbVolume, StreamWrittenFileIsRead) {
    FloatGrid::Ptr grid = densityGrid();
    grid->tree().setValue(Coord(-3, 4, 5), 1.5f);
    const std::string path = vdbPath("stream.vdb");
    {
        std::ofstream out(path, std::ios::binary);
        openvdb::io::Stream(out).write({grid});
    }
    auto r = read(path);
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(volumeVoxel(*r, -3, 4, 5), 1.5f);
    EXPECT_EQ(r->brickCount(), 1u);
}

// An emission grid ("temperature") beside the density: its values land in the density's bricks
// (a value where the density has no brick is dropped, an inactive one counts as 0); another
// transform, a bad value and a missing grid are refused by name.
TEST(VdbVolume, EmissionGridLandsInTheDensitysBricks) {
    FloatGrid::Ptr density = densityGrid();
    density->denseFill(CoordBBox(Coord(0, 0, 0), Coord(9, 3, 3)), 1.0f, /*active=*/true);
    density->setTransform(openvdb::math::Transform::createLinearTransform(0.5));
    FloatGrid::Ptr temperature = FloatGrid::create(0.0f);
    temperature->setName("temperature");
    temperature->setTransform(openvdb::math::Transform::createLinearTransform(0.5));
    temperature->tree().setValue(Coord(2, 1, 1), 3.0f);
    temperature->tree().setValue(Coord(9, 3, 3), 4.0f);
    temperature->tree().setValue(Coord(100, 0, 0), 5.0f);  // no density brick there: dropped
    temperature->tree().setValueOff(Coord(3, 1, 1), 7.0f);  // inactive: 0
    VolumeMaterial material;
    material.emission = {1.0f, 0.5f, 0.25f};
    const std::string path = writeVdb("fire.vdb", {density, temperature});
    auto r = readVdbVolume(path, "density", material, "temperature");
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->emissionVoxels.size(), r->voxels.size());
    double sum = 0;
    for (float x : r->emissionVoxels) sum += x;
    EXPECT_EQ(sum, 7.0);
    // Voxel (2, 1, 1) is the world point (1, 0.5, 0.5): emission (3, 1.5, 0.75).
    const Vec3f e = volumeEmission(*r, {1.0f, 0.5f, 0.5f});
    EXPECT_NEAR(e.x, 3.0f, 1e-5);
    EXPECT_NEAR(e.y, 1.5f, 1e-5);
    EXPECT_NEAR(e.z, 0.75f, 1e-5);
    EXPECT_TRUE(readVdbVolume(path, "density", material)->emissionVoxels.empty());

    temperature->setTransform(openvdb::math::Transform::createLinearTransform(0.25));
    EXPECT_TRUE(refusedWith(readVdbVolume(writeVdb("moved.vdb", {density, temperature}), "density", material, "temperature"),
                            {"moved.vdb", "emission grid 'temperature'", "not the density grid 'density'"}));
    temperature->setTransform(openvdb::math::Transform::createLinearTransform(0.5));
    temperature->tree().setValue(Coord(5, 2, 2), -1.0f);
    EXPECT_TRUE(refusedWith(readVdbVolume(writeVdb("cold.vdb", {density, temperature}), "density", material, "temperature"),
                            {"cold.vdb", "emission grid 'temperature'", "voxel (5, 2, 2)", "-1"}));
    EXPECT_TRUE(refusedWith(readVdbVolume(path, "density", material, "heat"), {"fire.vdb", "no grid named 'heat'"}));
}

// A temperature grid (material.temperature): kelvin in the same bricks, glowing as the
// blackbody table's colour times the emission scale; a voxel past 1e5 K is refused by file, grid
// and voxel.
TEST(VdbVolume, TemperatureGridGlowsAsABlackbody) {
    FloatGrid::Ptr density = densityGrid();
    density->denseFill(CoordBBox(Coord(0, 0, 0), Coord(9, 3, 3)), 1.0f, /*active=*/true);
    FloatGrid::Ptr temperature = FloatGrid::create(0.0f);
    temperature->setName("temperature");
    temperature->tree().setValue(Coord(2, 1, 1), 3000.0f);
    VolumeMaterial material;
    material.emission = {2.0f, 1.0f, 0.5f};
    material.temperature = true;
    auto r = readVdbVolume(writeVdb("flame.vdb", {density, temperature}), "density", material, "temperature");
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_TRUE(r->material.temperature);
    const Vec3f b = blackbodyRadiance(blackbodyTable().data(), 3000.0f);
    const Vec3f e = volumeEmission(*r, {2.0f, 1.0f, 1.0f});
    EXPECT_GT(b.x, b.z);  // 3000 K is orange
    EXPECT_NEAR(e.x, 2.0f * b.x, 1e-6f * b.x);
    EXPECT_NEAR(e.y, 1.0f * b.y, 1e-6f * b.y);
    EXPECT_NEAR(e.z, 0.5f * b.z, 1e-6f * b.z);
    temperature->tree().setValue(Coord(5, 2, 2), 2e5f);
    EXPECT_TRUE(refusedWith(readVdbVolume(writeVdb("sun.vdb", {density, temperature}), "density", material, "temperature"),
                            {"sun.vdb", "temperature grid 'temperature'", "voxel (5, 2, 2)", "temperature", "K"}));
    // The same value is a valid radiance.
    material.temperature = false;
    EXPECT_TRUE(readVdbVolume(writeVdb("sun.vdb", {density, temperature}), "density", material, "temperature").isOk());

    // Read in a child process (as the service reads uploads), the flag comes back through the pipe.
    VolumeSource source;
    source.grid = "density";
    source.emissionGrid = "temperature";
    source.material = material;
    source.material.temperature = true;
    temperature->tree().setValue(Coord(5, 2, 2), 0.0f);
    source.path = writeVdb("flame.vdb", {density, temperature});
    VolumeReadOptions child;
    child.childProcess = true;
    auto read = readVolumes({source}, child);
    ASSERT_TRUE(read.isOk()) << read.message();
    EXPECT_TRUE((*read)[0].material.temperature);
    // The bricks came back through a temporary file, read when asked for.
    EXPECT_TRUE((*read)[0].voxels.empty() && (*read)[0].bricks.source);
    ASSERT_TRUE(readVolumeIntoMemory((*read)[0]).isOk());
    EXPECT_NEAR(volumeEmission((*read)[0], {2.0f, 1.0f, 1.0f}).x, 2.0f * b.x, 1e-6f * b.x);
}

// The voxels are read leaf by leaf from the file (VdbGridVoxels.h), decoding each leaf as
// OpenVDB does: under every compression, and from half floats, each active voxel equals what
// OpenVDB's own reader gives, and an inactive one inside a leaf is 0.
TEST(VdbVolume, EveryCompressionAndHalfFloatsGiveOpenVdbsVoxels) {
    FloatGrid::Ptr grid = densityGrid();
    std::mt19937 random(11);
    std::uniform_real_distribution<float> value(0.0f, 4.0f);
    for (int32_t k = -9; k < 20; ++k)
        for (int32_t j = 0; j < 17; ++j)
            for (int32_t i = 3; i < 30; ++i) {
                if (random() % 5 == 0) grid->tree().setValueOff(Coord(i, j, k), 7.0f);  // inactive: 0
                else grid->tree().setValue(Coord(i, j, k), value(random));
            }
    for (bool half : {false, true}) {
        grid->setSaveFloatAsHalf(half);
        for (uint32_t compression : {uint32_t(openvdb::io::COMPRESS_NONE), uint32_t(openvdb::io::COMPRESS_ACTIVE_MASK),
                                     uint32_t(openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK),
                                     uint32_t(openvdb::io::COMPRESS_BLOSC)}) {
            SCOPED_TRACE("half " + std::to_string(half) + ", compression " + std::to_string(compression));
            const std::string path = writeVdb("codec.vdb", {grid}, compression);
            openvdb::io::File file(path);
            file.open();
            const FloatGrid::Ptr reference = openvdb::gridPtrCast<FloatGrid>(file.readGrid("density"));
            file.close();
            auto r = read(path);
            ASSERT_TRUE(r.isOk()) << r.message();
            uint64_t active = 0;
            for (int32_t k = -9; k < 20; ++k)
                for (int32_t j = 0; j < 17; ++j)
                    for (int32_t i = 3; i < 30; ++i) {
                        float expected = 0.0f;
                        active += reference->tree().probeValue(Coord(i, j, k), expected);
                        if (!reference->tree().isValueOn(Coord(i, j, k))) expected = 0.0f;
                        ASSERT_EQ(volumeVoxel(*r, i, j, k), expected) << i << " " << j << " " << k;
                    }
            EXPECT_GT(active, 10000u);
        }
    }
}

TEST(VdbVolume, NonFiniteAndNegativeValuesAreRefusedByIndex) {
    EXPECT_TRUE(refusedWith(read(oneVoxelFile("nan.vdb", Coord(1, 2, 3), std::nanf(""))),
                            {"nan.vdb: grid 'density': voxel (1, 2, 3) has density nan"}));
    EXPECT_TRUE(
        refusedWith(read(oneVoxelFile("inf.vdb", Coord(0, -7, 9), std::numeric_limits<float>::infinity())),
                    {"inf.vdb: grid 'density': voxel (0, -7, 9) has density inf"}));
    EXPECT_TRUE(refusedWith(read(oneVoxelFile("negative.vdb", Coord(4, 5, 6), -1.0f)),
                            {"negative.vdb: grid 'density': voxel (4, 5, 6) has density -1"}));
    EXPECT_TRUE(refusedWith(read(oneVoxelFile("huge.vdb", Coord(4, 5, 6), 1e30f)),
                            {"huge.vdb: grid 'density': voxel (4, 5, 6) has density 1e+30", "[0, 1e+18]"}));
    FloatGrid::Ptr grid = densityGrid();
    grid->fill(CoordBBox(Coord(0, 0, 0), Coord(127, 127, 127)), -2.0f, true);
    EXPECT_TRUE(
        refusedWith(read(writeVdb("negtile.vdb", {grid})),
                    {"negtile.vdb: grid 'density': tile (0, 0, 0) to (127, 127, 127) has density -2"}));
}

TEST(VdbVolume, NonzeroBackgroundIsRefused) {
    FloatGrid::Ptr grid = densityGrid(0.5f);
    grid->tree().setValue(Coord(0, 0, 0), 1.0f);
    EXPECT_TRUE(refusedWith(read(writeVdb("levelset.vdb", {grid})),
                            {"levelset.vdb: grid 'density': background 0.5 is not 0"}));
}

TEST(VdbVolume, EmptyGridIsRefused) {
    EXPECT_TRUE(refusedWith(read(writeVdb("empty-grid.vdb", {densityGrid()})),
                            {"empty-grid.vdb: grid 'density': has no active values"}));
}

// Two voxels 2^20 apart on each axis: 131074^3 cells, refused before anything is allocated.
TEST(VdbVolume, BrickGridAboveTheCellLimitIsRefused) {
    FloatGrid::Ptr grid = densityGrid();
    grid->tree().setValue(Coord(0, 0, 0), 1.0f);
    grid->tree().setValue(Coord(1 << 20, 1 << 20, 1 << 20), 1.0f);
    EXPECT_TRUE(refusedWith(
        read(writeVdb("far.vdb", {grid})),
        {"far.vdb: grid 'density': ", "131074 x 131074 x 131074 cells, more than the limit of 16777216"}));
}

TEST(VdbVolume, IndicesNearTheInt32LimitsAreRefused) {
    const int32_t top = std::numeric_limits<int32_t>::max(), bottom = std::numeric_limits<int32_t>::min();
    EXPECT_TRUE(refusedWith(read(oneVoxelFile("top.vdb", Coord(top, 0, 0), 1.0f)),
                            {"top.vdb: grid 'density': ", "beyond the limit of +-16777216"}));
    EXPECT_TRUE(refusedWith(read(oneVoxelFile("bottom.vdb", Coord(0, bottom, 0), 1.0f)),
                            {"bottom.vdb: grid 'density': ", "beyond the limit of +-16777216"}));
    // Just inside: the covered range [lo - 1, hi + 1] reaches +-2^24 exactly.
    auto inside = read(oneVoxelFile("inside.vdb", Coord((1 << 24) - 1, 1 - (1 << 24), 0), 1.0f));
    ASSERT_TRUE(inside.isOk()) << inside.message();
    EXPECT_EQ(volumeVoxel(*inside, (1 << 24) - 1, 1 - (1 << 24), 0), 1.0f);
}

TEST(VdbVolume, FrustumTransformIsRefused) {
    FloatGrid::Ptr grid = densityGrid();
    grid->tree().setValue(Coord(1, 1, 1), 1.0f);
    grid->setTransform(openvdb::math::Transform::createFrustumTransform(
        openvdb::BBoxd(openvdb::Vec3d(0, 0, 0), openvdb::Vec3d(10, 10, 10)), 0.5, 2.0, 1.0));
    EXPECT_TRUE(
        refusedWith(read(writeVdb("frustum.vdb", {grid})),
                    {"frustum.vdb: grid 'density': its transform is a NonlinearFrustumMap, not linear"}));
}

// Half of a valid file, compressed or not (io::File read the uncompressed half silently, the
// voxels past the cut as garbage), and a stream-written file cut short.
TEST(VdbVolume, TruncatedFilesAreRefused) {
    FloatGrid::Ptr grid = densityGrid();
    grid->denseFill(CoordBBox(Coord(0, 0, 0), Coord(39, 39, 39)), 1.0f, true);
    for (uint32_t compression : {uint32_t(openvdb::io::COMPRESS_NONE),
                                 uint32_t(openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK),
                                 uint32_t(openvdb::io::COMPRESS_BLOSC)}) {
        const std::string path = writeVdb("cut.vdb", {grid}, compression);
        ASSERT_TRUE(read(path).isOk());
        std::filesystem::resize_file(path, std::filesystem::file_size(path) / 2);
        EXPECT_TRUE(refusedWith(read(path), {"cut.vdb: grid 'density' claims bytes", "(truncated?)"}))
            << "compression " << compression;
    }
    const std::string path = vdbPath("cutstream.vdb");
    {
        std::ofstream out(path, std::ios::binary);
        openvdb::io::Stream(out).write({grid});
    }
    std::filesystem::resize_file(path, std::filesystem::file_size(path) / 2);
    EXPECT_TRUE(refusedWith(read(path), {"cutstream.vdb: "}));
}

TEST(VdbVolume, NotVdbFilesAreRefusedByName) {
    std::string garbage(4096, '\0');
    std::mt19937 random(7);
    for (char& c : garbage) c = char(random());
    const std::string garbagePath = vdbPath("garbage.vdb");
    std::ofstream(garbagePath, std::ios::binary).write(garbage.data(), std::streamsize(garbage.size()));
    EXPECT_TRUE(
        refusedWith(read(garbagePath), {"garbage.vdb: not a readable OpenVDB file", "not a VDB file"}));

    const std::string emptyPath = vdbPath("empty.vdb");
    std::ofstream(emptyPath, std::ios::binary).close();
    EXPECT_TRUE(refusedWith(read(emptyPath), {"empty.vdb: is empty (0 bytes)"}));

    const std::string shortPath = vdbPath("short.vdb");
    std::ofstream(shortPath, std::ios::binary).write(" BDV", 4);
    EXPECT_TRUE(refusedWith(read(shortPath), {"short.vdb: "}));

    EXPECT_TRUE(
        refusedWith(read(vdbPath("missing.vdb")), {"missing.vdb: cannot open: No such file or directory"}));
    EXPECT_TRUE(refusedWith(read(testTmpDir("vdb").string()), {"only regular files are read"}));
}

// A grid name whose length field claims 2^31 - 1 bytes: OpenVDB allocates (and fills) the string
// before it reads a byte of it, 2.1 GB for a file of a few hundred bytes. In the child process
// (the service's path) the allocation fails at once against the child's memory limit (1 GiB +
// 64 x the file's size) and the file is refused naming the limit.
TEST(VdbVolume, LengthFieldClaimingGigabytesFailsAgainstTheChildsMemoryLimit) {
    const std::string path = oneVoxelFile("claims.vdb", Coord(1, 2, 3), 0.5f);
    std::string bytes;
    {
        std::ifstream in(path, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    // The grid descriptor's unique name, the file's first "density": a uint32 length, then the name.
    const size_t name = bytes.find("density");
    ASSERT_NE(name, std::string::npos);
    ASSERT_GE(name, 4u);
    uint32_t length = 0;
    std::memcpy(&length, &bytes[name - 4], 4);
    ASSERT_EQ(length, 7u);
    length = 0x7fffffff;
    std::memcpy(&bytes[name - 4], &length, 4);
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));

    VolumeSource source;
    source.path = path;
    VolumeReadOptions child;
    child.childProcess = true;
    const auto start = std::chrono::steady_clock::now();
    auto r = readVolumes({source}, child);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ASSERT_FALSE(r.isOk());
    const std::string expected =
        "claims.vdb: OpenVDB ran out of its 1.0 GiB memory limit (1 GiB + 64 x the file's size) reading the file; "
        "refused";
    EXPECT_EQ(r.message().rfind(expected, 0), 0u) << r.message();
    EXPECT_LT(seconds, 5.0) << r.message();
}

// Sparse: the size check comes before OpenVDB reads a byte.
TEST(VdbVolume, FileAboveTheSizeLimitIsRefusedUnread) {
    const std::string path = vdbPath("big.vdb");
    std::ofstream(path, std::ios::binary).close();
    std::filesystem::resize_file(path, kMaxVdbFileBytes + 1);
    EXPECT_TRUE(refusedWith(read(path),
                            {"big.vdb: is 17179869185 bytes, above the limit of 17179869184 (16.0 GiB)"}));
    std::filesystem::remove(path);
}

}  // namespace
}  // namespace vastray::test
