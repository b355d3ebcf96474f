// `vastray render --backend vulkan --tile` and `vastray assemble`: the streaming renderer's tiles
// join into the whole frame bit for bit, in core and out of core (where the device also cuts
// each region into tiles of its own), EXR with every AOV and PNG.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "CommandRunner.h"
#include "RegionTestSupport.h"
#include "TestTmp.h"

namespace vastray {
namespace {

std::string tmp(const std::string& name) { return (test::testTmpDir("region-stream") / name).string(); }

// A small terrain package of many chunks, made once per test process through the CLI itself.
const std::string& terrainPackage() {
    static const std::string path = [] {
        const std::string ply = tmp("terrain.ply"), vast = tmp("terrain.vast");
        EXPECT_EQ(test::runVastray("generate terrain --triangles 20000 --seed 4 -o " + ply).exitCode, 0);
        EXPECT_EQ(test::runVastray("import " + ply + " -o " + vast + " --chunk-size 64KiB --progress none").exitCode,
                  0);
        return vast;
    }();
    return path;
}

// 50x37 in 3x2 tiles: tiles of uneven sizes (16/17 wide, 18/19 high).
std::string vulkan(const std::string& extra) {
    return terrainPackage() + " --backend vulkan --resolution 50x37 --spp 3 --seed 2" + extra;
}

// Every AOV but `cost`, which counts the work done: each render pages its chunks in as its rays
// reach them (a fresh process starts with none resident), and a ray traces the cells that are
// resident when it walks, so the work depends on what a tile's rays ask for first.
TEST(RegionStreamCli, ExrTilesWithEveryAovAssembleToTheWholeFrameBitForBit) {
    test::expectTilesAssembleToTheWholeFrame(
        vulkan(" --memory-budget 8MiB --aovs depth,normal,albedo,primid,chunkid"), tmp("vulkan-exr-"), ".exr", 3, 2);
}

TEST(RegionStreamCli, PngTilesAssembleToTheWholeFrameBitForBit) {
    test::expectTilesAssembleToTheWholeFrame(vulkan(" --memory-budget 8MiB"), tmp("vulkan-png-"), ".png", 3, 2);
}

// 512 KiB holds 2 chunk slots of this 16-chunk package: chunks are paged in and out, yet every
// channel is the same. (Not `cost`: it counts the work done, and out of core a ray traces the
// cells that are resident when it walks, so that depends on the schedule, which differs between a
// tile and the frame.)
TEST(RegionStreamCli, OutOfCoreTilesAssembleToTheWholeFrameBitForBit) {
    test::expectTilesAssembleToTheWholeFrame(vulkan(" --memory-budget 512KiB --aovs depth,normal,albedo,primid,chunkid"),
                                             tmp("vulkan-tight-"), ".exr", 2, 3);
}

TEST(RegionStreamCli, MeshFileInputToo) {
    const std::string ply = tmp("terrain.ply");
    (void)terrainPackage();
    test::expectTilesAssembleToTheWholeFrame(ply + " --backend vulkan --resolution 21x13 --spp 2 --memory-budget 8MiB",
                                             tmp("vulkan-mesh-"), ".png", 2, 2);
}

}  // namespace
}  // namespace vastray
