// `vastray import --volume` as a user drives it: a .vdb (the fBm cloud bench/volume_cloud.cpp
// writes with OpenVDB, over [-1, 1]^3) goes into a package above a floor; `info` lists it, both
// backends render it (and agree), and bad volume options are errors that name the option, the
// file or the grid.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "CommandRunner.h"
#include "TestTmp.h"

namespace {

using vastray::test::CommandResult;
using vastray::test::runVastray;

// The beauty RMSE `vastray diff` prints.
double beautyRmse(const std::string& a, const std::string& b) {
    CommandResult d = runVastray("diff " + a + " " + b + " --json");
    const size_t at = d.output.find("\"rmse\":");
    EXPECT_NE(at, std::string::npos) << d.output;
    return at == std::string::npos ? -1.0 : std::atof(d.output.c_str() + at + 7);
}

class VolumeCli : public ::testing::Test {
protected:
    // A file in this suite's scratch folder.
    static std::string tmp(const std::string& name) {
        const std::filesystem::path dir = vastray::test::testTmpDir("volume-cli");
        std::filesystem::create_directories(dir);
        return (dir / name).string();
    }
    static void SetUpTestSuite() {
        // One large floor triangle under the cloud (a package needs a mesh).
        std::ofstream(tmp("floor.ply")) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                           "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                           "end_header\n-3 -1.2 -3\n3 -1.2 -3\n0 -1.2 4\n3 0 2 1\n";
        CommandResult plain = runVastray("import " + tmp("floor.ply") + " -o " + tmp("plain.vast") + " --chunk-size 64KiB");
        ASSERT_EQ(plain.exitCode, 0) << plain.output;
        // 32^3 voxels of cloud over [-1, 1]^3 (and Mitsuba's .vol of it, unused here).
        CommandResult cloud = vastray::test::runShell(std::string(VASTRAY_VOLUME_CLOUD) + " 32 " + tmp("fog.vdb") + " " +
                                                      tmp("fog.vol"));
        ASSERT_EQ(cloud.exitCode, 0) << cloud.output;
    }
};

TEST_F(VolumeCli, ImportInfoAndRenderOnBothBackends) {
    CommandResult i = runVastray("import " + tmp("floor.ply") + " -o " + tmp("fog.vast") + " --chunk-size 64KiB --volume " +
                                 tmp("fog.vdb") + ":density --volume-density 4 --volume-albedo 0.9,0.8,0.7 --volume-anisotropy 0.3 "
                                 "--volume-emission density --volume-emission-scale 0.5,0.2,0.1");
    ASSERT_EQ(i.exitCode, 0) << i.output;
    EXPECT_NE(i.output.find("read volume 'density'"), std::string::npos) << i.output;
    EXPECT_NE(i.output.find("with emission"), std::string::npos) << i.output;
    CommandResult info = runVastray("info " + tmp("fog.vast") + " --json");
    ASSERT_EQ(info.exitCode, 0) << info.output;
    for (const char* key : {"\"volumes\"", "\"name\": \"density\"", "\"anisotropy\"", "\"brick_cells\"", "\"emission\": ["})
        EXPECT_NE(info.output.find(key), std::string::npos) << key << " in " << info.output;
    CommandResult verify = runVastray("info " + tmp("fog.vast") + " --verify");
    EXPECT_EQ(verify.exitCode, 0) << verify.output;
    EXPECT_NE(verify.output.find("volume 0"), std::string::npos) << verify.output;
    EXPECT_NE(verify.output.find("chunks and 1 volumes intact"), std::string::npos) << verify.output;

    const std::string common = " --resolution 40x30 --spp 8 --max-depth 4 --eye 0,1,5 --target 0,0,0";
    for (const char* backend : {"vulkan", "embree"}) {
        CommandResult r = runVastray("render " + tmp("fog.vast") + " -o " + tmp(std::string(backend) + ".exr") + common +
                                     " --backend " + backend);
        ASSERT_EQ(r.exitCode, 0) << backend << ": " << r.output;
    }
    CommandResult clear = runVastray("render " + tmp("plain.vast") + " -o " + tmp("clear.exr") + common);
    ASSERT_EQ(clear.exitCode, 0) << clear.output;
    const double agree = beautyRmse(tmp("vulkan.exr"), tmp("embree.exr"));
    const double fogged = beautyRmse(tmp("vulkan.exr"), tmp("clear.exr"));
    std::printf("device vs Embree RMSE %.4g; with and without the fog %.4g\n", agree, fogged);
    EXPECT_GE(agree, 0.0);
    EXPECT_LT(agree * 10, fogged);
}

// --volume-codec: the package stores NanoVDB Fp16 or Fp8 leaves (info says so, and the device
// bytes shrink to about a half and a quarter of the float leaves'), and both backends render it.
TEST_F(VolumeCli, ImportsQuantizedBricks) {
    auto deviceBytes = [&](const std::string& package) -> uint64_t {
        CommandResult info = runVastray("info " + package + " --json");
        EXPECT_EQ(info.exitCode, 0) << info.output;
        const size_t at = info.output.find("\"device_bytes\": ");
        return at == std::string::npos ? 0 : std::stoull(info.output.substr(at + 16));
    };
    CommandResult plain = runVastray("import " + tmp("floor.ply") + " -o " + tmp("float.vast") + " --chunk-size 64KiB --volume " +
                                     tmp("fog.vdb"));
    ASSERT_EQ(plain.exitCode, 0) << plain.output;
    const uint64_t floatBytes = deviceBytes(tmp("float.vast"));
    ASSERT_GT(floatBytes, 0u);
    for (const char* codec : {"fp16", "fp8"}) {
        const std::string package = tmp(std::string(codec) + ".vast");
        CommandResult i = runVastray("import " + tmp("floor.ply") + " -o " + package + " --chunk-size 64KiB --volume " +
                                     tmp("fog.vdb") + " --volume-codec " + codec);
        ASSERT_EQ(i.exitCode, 0) << i.output;
        CommandResult info = runVastray("info " + package + " --json");
        EXPECT_NE(info.output.find(std::string("\"codec\": \"") + codec + "\""), std::string::npos) << info.output;
        CommandResult text = runVastray("info " + package);
        EXPECT_NE(text.output.find(std::string("NanoVDB ") + codec + " leaves"), std::string::npos) << text.output;
        EXPECT_LT(double(deviceBytes(package)), floatBytes * (codec == std::string("fp16") ? 0.55 : 0.32)) << codec;
        for (const char* backend : {"vulkan", "embree"}) {
            CommandResult r = runVastray("render " + package + " -o " + tmp(std::string(codec) + backend +
                                         ".exr") + " --resolution 16x12 --spp 2 --backend " + backend);
            EXPECT_EQ(r.exitCode, 0) << codec << " " << backend << ": " << r.output;
        }
    }
}

// A temperature grid (here the density, 0 to 1 K: valid, if cold) is stored with its flag.
TEST_F(VolumeCli, ImportsATemperatureGrid) {
    CommandResult i = runVastray("import " + tmp("floor.ply") + " -o " + tmp("hot.vast") +
                                 " --chunk-size 64KiB --volume " + tmp("fog.vdb") +
                                 " --volume-temperature density --volume-emission-scale 1e6");
    ASSERT_EQ(i.exitCode, 0) << i.output;
    EXPECT_NE(i.output.find("with temperature"), std::string::npos) << i.output;
    CommandResult info = runVastray("info " + tmp("hot.vast") + " --json");
    ASSERT_EQ(info.exitCode, 0) << info.output;
    EXPECT_NE(info.output.find("\"temperature\": true"), std::string::npos) << info.output;
}

TEST_F(VolumeCli, BadVolumeOptionsAreNamed) {
    const std::string base = "import " + tmp("floor.ply") + " -o " + tmp("bad.vast") + " --volume ";
    struct Case {
        std::string arguments, words;
    };
    for (const Case& c : std::initializer_list<Case>{
             {tmp("missing.vdb"), "missing.vdb"},
             {tmp("fog.vdb") + ":smoke", "smoke"},
             {tmp("floor.ply"), "expected FILE.vdb or FILE.vdb:GRID"},
             {tmp("fog.vdb") + " --volume-albedo 0.5 --volume-albedo 0.6", "--volume-albedo is given 2 times for 1 volumes"},
             {tmp("fog.vdb") + " --volume-albedo 0.5,2,0.5", "--volume-albedo '0.5,2,0.5'"},
             {tmp("fog.vdb") + " --volume-anisotropy 1", "--volume-anisotropy"},
             {tmp("fog.vdb") + " --volume-density -1", "--volume-density"},
             {tmp("fog.vdb") + " --volume-emission heat", "no grid named 'heat'"},
             {tmp("fog.vdb") + " --volume-emission density --volume-emission-scale -2", "--volume-emission-scale '-2'"},
             {tmp("fog.vdb") + " --volume-emission density --volume-temperature density",
              "--volume-emission 'density' and --volume-temperature 'density'"},
             {tmp("fog.vdb") + " --volume-temperature heat", "no grid named 'heat'"},
             {tmp("fog.vdb") + " --volume-codec fp4", "--volume-codec 'fp4' is not a brick codec (expected float, fp16 or fp8)"},
             {tmp("fog.vdb") + " --volume-codec fp8 --volume-codec fp16", "--volume-codec is given 2 times for 1 volumes"}}) {
        CommandResult r = runVastray(base + c.arguments);
        EXPECT_NE(r.exitCode, 0) << c.arguments;
        EXPECT_NE(r.output.find(c.words), std::string::npos) << c.arguments << ": " << r.output;
        EXPECT_FALSE(std::filesystem::exists(tmp("bad.vast"))) << c.arguments;
    }
}

}  // namespace
