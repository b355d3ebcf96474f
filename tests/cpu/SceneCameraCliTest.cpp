// glTF cameras (issue "Real assets"): imported from camera nodes, kept in the package,
// listed by `vastray info`, picked by `render --camera NAME|INDEX`, the first one by default;
// a picked camera renders exactly what --eye/--target/--up/--fov with its values render.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <fstream>
#include <string>

#include "CommandRunner.h"
#include "TestScenes.h"

namespace vastray {
namespace {

using test::CommandResult;
using test::runVastray;

// Two quads' worth of triangles and three cameras: "Front" at (0, 0, 5) looking down -Z,
// "Side" at (5, 0.5, 0) turned 90 degrees about Y (looking down -X), and an orthographic one.
const char* kGltf = R"({"asset":{"version":"2.0"},
 "buffers":[{"byteLength":104,"uri":"data:application/octet-stream;base64,AACAvwAAgL8AAAAAAACAPwAAgL8AAAAAAACAPwAAgD8AAAAAAACAvwAAgD8AAAAAAACAvwAAgL8AAIC/AACAPwAAgL8AAIC/AAAAAAAAgD8AAIC/AAABAAIAAAACAAMABAAFAAYAAAA="}],
 "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":84},{"buffer":0,"byteOffset":84,"byteLength":18}],
 "accessors":[{"bufferView":0,"componentType":5126,"type":"VEC3","count":7,"min":[-1,-1,-1],"max":[1,1,0]},
              {"bufferView":1,"componentType":5123,"type":"SCALAR","count":9}],
 "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],
 "cameras":[{"name":"Front","type":"perspective","perspective":{"yfov":0.7,"znear":0.1}},
            {"name":"Side","type":"perspective","perspective":{"yfov":0.5,"znear":0.1}},
            {"type":"orthographic","orthographic":{"xmag":1,"ymag":1,"znear":0.1,"zfar":10}}],
 "nodes":[{"mesh":0},{"camera":1,"translation":[5,0.5,0],"rotation":[0,0.70710678,0,0.70710678]},
          {"camera":0,"translation":[0,0,5]},{"camera":2}],
 "scenes":[{"nodes":[0,1,2,3]}],"scene":0})";

class SceneCameraCli : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        std::ofstream(test::tmpPath("cameras.gltf")) << kGltf;
        CommandResult i = runVastray("import " + test::tmpPath("cameras.gltf") + " -o " + package() + " --progress none");
        ASSERT_EQ(i.exitCode, 0) << i.output;
        importOutput() = i.output;
    }
    static std::string package() { return test::tmpPath("cameras.vast"); }
    static std::string& importOutput() {
        static std::string output;
        return output;
    }
    // --eye/--target/--up/--fov with the stored camera's floats (JSON numbers round-trip them).
    static std::string explicitFlags(const nlohmann::json& camera) {
        auto vec = [](const nlohmann::json& v) {
            char text[128];
            std::snprintf(text, sizeof text, "%.9g,%.9g,%.9g", v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
            return std::string(text);
        };
        char fov[32];
        std::snprintf(fov, sizeof fov, "%.9g", camera["fov_y_degrees"].get<double>());
        return " --eye " + vec(camera["eye"]) + " --target " + vec(camera["target"]) + " --up " + vec(camera["up"]) +
               " --fov " + fov;
    }
    static bool sameImage(const std::string& a, const std::string& b) {
        CommandResult d = runVastray("diff " + a + " " + b + " --json");
        const size_t brace = d.output.find('{');
        if (brace == std::string::npos) return false;
        const nlohmann::json j = nlohmann::json::parse(d.output.substr(brace), nullptr, false);
        return j.is_object() && j.contains("rmse") && j["rmse"].get<double>() == 0.0;
    }
};

TEST_F(SceneCameraCli, CamerasAreImportedInFileOrderAndListed) {
    EXPECT_NE(importOutput().find("1 cameras read but not used (orthographic"), std::string::npos) << importOutput();
    CommandResult info = runVastray("info " + package() + " --json");
    ASSERT_EQ(info.exitCode, 0) << info.output;
    const nlohmann::json cameras = nlohmann::json::parse(info.output)["cameras"];
    ASSERT_EQ(cameras.size(), 2u) << info.output;
    EXPECT_EQ(cameras[0]["name"], "Front");
    EXPECT_EQ(cameras[1]["name"], "Side");
    EXPECT_NEAR(cameras[0]["fov_y_degrees"].get<double>(), 0.7 * 180 / 3.14159265358979, 1e-4);
    EXPECT_NEAR(cameras[1]["eye"][1].get<double>(), 0.5, 1e-6);
    // Side looks down -X from (5, 0.5, 0): its target lies along -X (at the eye's distance from the origin).
    EXPECT_LT(cameras[1]["target"][0].get<double>(), 1.0);
    EXPECT_NEAR(cameras[1]["target"][1].get<double>(), 0.5, 1e-5);
    EXPECT_NEAR(cameras[1]["target"][2].get<double>(), 0.0, 1e-5);
    EXPECT_NEAR(cameras[1]["up"][1].get<double>(), 1.0, 1e-6);
}

TEST_F(SceneCameraCli, PickedCameraRendersLikeItsExplicitValues) {
    const nlohmann::json cameras = nlohmann::json::parse(runVastray("info " + package() + " --json").output)["cameras"];
    const std::string flags = " --resolution 48x32 --spp 2 --progress none";
    for (const std::string backend : {"embree", "vulkan"}) {
        const std::string picked = test::tmpPath("picked-" + backend + ".png");
        const std::string byIndex = test::tmpPath("index-" + backend + ".png");
        const std::string explicitly = test::tmpPath("explicit-" + backend + ".png");
        const std::string byDefault = test::tmpPath("default-" + backend + ".png");
        const std::string front = test::tmpPath("front-" + backend + ".png");
        const std::string base = "render --backend " + backend + " " + package() + flags + " -o ";
        ASSERT_EQ(runVastray(base + picked + " --camera Side").exitCode, 0) << backend;
        ASSERT_EQ(runVastray(base + byIndex + " --camera 1").exitCode, 0) << backend;
        ASSERT_EQ(runVastray(base + explicitly + explicitFlags(cameras[1])).exitCode, 0) << backend;
        ASSERT_EQ(runVastray(base + byDefault).exitCode, 0) << backend;
        ASSERT_EQ(runVastray(base + front + explicitFlags(cameras[0])).exitCode, 0) << backend;
        EXPECT_TRUE(sameImage(picked, explicitly)) << backend;
        EXPECT_TRUE(sameImage(picked, byIndex)) << backend;
        EXPECT_TRUE(sameImage(byDefault, front)) << backend << ": the default is the first camera";
        EXPECT_FALSE(sameImage(picked, front)) << backend << ": the two cameras see different images";
    }
}

TEST_F(SceneCameraCli, BadChoicesAreNamedErrors) {
    const std::string base = "render --backend embree " + package() + " --resolution 16x16 --spp 1 --progress none -o " +
                             test::tmpPath("bad.png");
    CommandResult unknown = runVastray(base + " --camera Top");
    EXPECT_NE(unknown.exitCode, 0);
    EXPECT_NE(unknown.output.find("scene camera 'Top': no camera of that name or index; the scene has 0 'Front', 1 'Side'"),
              std::string::npos)
        << unknown.output;
    CommandResult both = runVastray(base + " --camera Front --eye 0,0,3 --target 0,0,0");
    EXPECT_NE(both.exitCode, 0);
    EXPECT_NE(both.output.find("--camera Front and --eye/--target exclude each other"), std::string::npos) << both.output;
    std::ofstream(test::tmpPath("no-camera.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    CommandResult none = runVastray("render --backend embree " + test::tmpPath("no-camera.obj") +
                                    " --resolution 16x16 --spp 1 --progress none --camera 0 -o " + test::tmpPath("none.png"));
    EXPECT_NE(none.exitCode, 0);
    EXPECT_NE(none.output.find("scene camera '0': the scene defines no cameras"), std::string::npos) << none.output;
}

// A camera name longer than a package keeps (64 bytes) still imports: it is cut at a character
// boundary, `import` says what it stored for what, and `render --camera` takes the stored name
// or the file's full one, both the same camera as its index.
TEST_F(SceneCameraCli, LongCameraNameIsCutReportedAndPickedByEitherName) {
    std::string longName = "Shot-12_";
    while (longName.size() < 100) longName += "\xC3\xA9";  // "é" is 2 bytes: 8 + 46 * 2 = 100
    ASSERT_EQ(longName.size(), 100u);
    const std::string stored = longName.substr(0, 64);
    std::string gltf = kGltf;
    gltf.replace(gltf.find("\"Front\""), 7, "\"" + longName + "\"");
    std::ofstream(test::tmpPath("long-camera.gltf")) << gltf;
    const std::string package = test::tmpPath("long-camera.vast");
    CommandResult i = runVastray("import " + test::tmpPath("long-camera.gltf") + " -o " + package + " --progress none");
    ASSERT_EQ(i.exitCode, 0) << i.output;
    EXPECT_NE(i.output.find("warning: " + test::tmpPath("long-camera.gltf") + ": camera 0 name '" + longName +
                            "' (100 bytes) is stored as '" + stored + "' (64 bytes; names are kept to 64)"),
              std::string::npos)
        << i.output;
    CommandResult info = runVastray("info " + package + " --json");
    ASSERT_EQ(info.exitCode, 0) << info.output;
    EXPECT_EQ(nlohmann::json::parse(info.output)["cameras"][0]["name"], stored);

    const std::string base = "render --backend embree " + package + " --resolution 24x16 --spp 1 --progress none -o ";
    const std::string byIndex = test::tmpPath("long-index.png"), byStored = test::tmpPath("long-stored.png"),
                      byFull = test::tmpPath("long-full.png");
    ASSERT_EQ(runVastray(base + byIndex + " --camera 0").exitCode, 0);
    CommandResult s = runVastray(base + byStored + " --camera '" + stored + "'");
    ASSERT_EQ(s.exitCode, 0) << s.output;
    CommandResult f = runVastray(base + byFull + " --camera '" + longName + "'");
    ASSERT_EQ(f.exitCode, 0) << f.output;
    EXPECT_TRUE(sameImage(byStored, byIndex));
    EXPECT_TRUE(sameImage(byFull, byIndex));
    CommandResult other =
        runVastray(base + test::tmpPath("long-other.png") + " --camera " + std::string(70, 'z'));
    EXPECT_NE(other.exitCode, 0);
    EXPECT_NE(other.output.find("no camera of that name or index; the scene has 0 '" + stored + "', 1 'Side'"),
              std::string::npos)
        << other.output;
}

}  // namespace
}  // namespace vastray
