// glTF KHR_lights_punctual through the command line: `import` keeps a file's lights, `info`
// lists them (text and JSON), `render` lights the scene with them on either backend and
// `--no-lights` leaves them out.
#include "CliTestSupport.h"
#include "CommandRunner.h"
#include "LitFloorGltf.h"
#include "TestTmp.h"
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace {

using vastray::test::CommandResult;
using vastray::test::runVastray;
using vastray::test::slurp;

// The floor under a point light and a spot light.
const std::string kLitFloor = vastray::test::litFloorGltf(
    R"({"name":"Bulb","type":"point","intensity":3},{"name":"Spot","type":"spot","intensity":8,"spot":{"outerConeAngle":0.4}})",
    R"({"extensions":{"KHR_lights_punctual":{"light":0}},"translation":[0.5,1,0]},)"
    R"({"extensions":{"KHR_lights_punctual":{"light":1}},"translation":[-1,2,0],"rotation":[-0.70710678,0,0,0.70710678]})");

class LightsCli : public ::testing::Test {
protected:
    // A file in this suite's scratch folder.
    static std::string tmp(const std::string& name) {
        const std::filesystem::path dir = vastray::test::testTmpDir("cli-lights");
        std::filesystem::create_directories(dir);
        return (dir / name).string();
    }
    static void SetUpTestSuite() {
        std::ofstream(tmp("floor.gltf")) << kLitFloor;
        CommandResult i = runVastray("import " + tmp("floor.gltf") + " -o " + tmp("floor.vast"));
        ASSERT_EQ(i.exitCode, 0) << i.output;
    }
};

TEST_F(LightsCli, InfoListsTheLights) {
    CommandResult text = runVastray("info " + tmp("floor.vast"));
    ASSERT_EQ(text.exitCode, 0) << text.output;
    EXPECT_NE(text.output.find("'Bulb': point, colour (1, 1, 1), intensity 3 cd, at (0.5, 1, 0)"), std::string::npos)
        << text.output;
    EXPECT_NE(text.output.find("'Spot': spot"), std::string::npos) << text.output;
    CommandResult json = runVastray("info " + tmp("floor.vast") + " --json");
    ASSERT_EQ(json.exitCode, 0) << json.output;
    EXPECT_NE(json.output.find("\"lights\""), std::string::npos) << json.output;
    EXPECT_NE(json.output.find("\"outer_cone_angle\""), std::string::npos) << json.output;
}

// The sun off: with --no-lights the floor shows the sky's light alone, without it the lights'
// too; on both backends.
TEST_F(LightsCli, RenderUsesTheLightsUnlessTold) {
    for (const char* backend : {"embree", "vulkan"}) {
        const std::string lit = tmp(std::string("lit-") + backend + ".pfm"), dark = tmp(std::string("dark-") + backend + ".pfm");
        const std::string common = " --backend " + std::string(backend) +
                                   " --resolution 24x16 --spp 1 --no-sun --eye 0,4,3 --target 0,0,0";
        CommandResult a = runVastray("render " + tmp("floor.vast") + " -o " + lit + common);
        ASSERT_EQ(a.exitCode, 0) << a.output;
        CommandResult b = runVastray("render " + tmp("floor.vast") + " -o " + dark + common + " --no-lights");
        ASSERT_EQ(b.exitCode, 0) << b.output;
        EXPECT_NE(slurp(lit), slurp(dark)) << backend << ": the lights change nothing";
    }
    CommandResult help = runVastray("render --help");
    EXPECT_NE(help.output.find("--no-lights"), std::string::npos);
}

}  // namespace
