// `vastray render` and `vastray diff` as a user drives them: exit codes, messages, files.
#include "CommandRunner.h"
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "TestScenes.h"
#include "vastray/core/ImageFile.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {
namespace {

using vastray::test::CommandResult;
using vastray::test::runVastray;


double jsonNumber(const std::string& json, const std::string& key) {
    const size_t at = json.find("\"" + key + "\":");
    return at == std::string::npos ? NAN : std::stod(json.substr(at + key.size() + 3));
}

class RenderCli : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        CommandResult g =
            runVastray("generate terrain --triangles 20000 --seed 3 -o " + test::tmpPath("terrain.ply"));
        ASSERT_EQ(g.exitCode, 0) << g.output;
        CommandResult i = runVastray("import " + test::tmpPath("terrain.ply") + " -o " +
                                     test::tmpPath("terrain.vast") + " --chunk-size 64KiB --progress none");
        ASSERT_EQ(i.exitCode, 0) << i.output;
    }
    static std::string terrain() { return test::tmpPath("terrain.ply"); }
};

TEST_F(RenderCli, BadInputIsAClearErrorBeforeAnyWork) {
    const std::vector<std::pair<std::string, std::string>> cases{
        {"--resolution 0x64", "--resolution"},
        {"--resolution 64x-3", "--resolution"},
        {"--resolution 100000x64", "--resolution"},
        {"--resolution 64", "--resolution"},
        {"--spp 0", "--spp"},
        {"--spp -4", "--spp"},
        {"--spp 10000000", "--spp"},
        {"--eye nan,0,0 --target 0,0,0", "--eye"},
        {"--eye 1,2,3 --target 1,2,3", "eye equals target"},
        {"--eye 1,2,3", "--eye and --target"},
        {"--aovs depth,colour", "unknown AOV 'colour'"},
        {"--integrator whitted", "unknown integrator 'whitted'"},
        {"--texture-lod blurry", "--texture-lod 'blurry' is not one of cone, finest"},
        {"--backend optix", "--backend 'optix': expected vulkan or embree"},
        {"--backend embree --aovs primid,chunkid", "need --backend vulkan"},
        {"--memory-budget 12XB", "--memory-budget"},
        {"--host-cache -1", "--host-cache"},
        {"--fov 0", "fov"},
        {"--max-depth 5000", "--max-depth"},
    };
    const std::string out = test::tmpPath("never.exr");
    for (const auto& [flags, message] : cases) {
        std::filesystem::remove(out);
        CommandResult r = runVastray("render " + terrain() + " -o " + out + " " + flags);
        EXPECT_EQ(r.exitCode, 2) << flags << "\n" << r.output;
        EXPECT_NE(r.output.find(message), std::string::npos) << flags << "\n" << r.output;
        EXPECT_FALSE(std::filesystem::exists(out)) << flags;
    }
    CommandResult png =
        runVastray("render " + terrain() + " -o " + test::tmpPath("never.png") + " --aovs depth");
    EXPECT_EQ(png.exitCode, 2) << png.output;
}

// OpenImageIO lives in a module loaded on the first image read or write
// (core/src/image/ImageModule.h): a command that touches no image does not load it, and a render
// whose module cannot be loaded stops before rendering, saying where it looked.
TEST_F(RenderCli, OpenImageIoIsLoadedOnlyToReadOrWriteImages) {
    const std::string binary = VASTRAY_BINARY, package = test::tmpPath("terrain.vast");
    CommandResult info = vastray::test::runShell("LD_DEBUG=libs " + binary + " info " + package);
    ASSERT_EQ(info.exitCode, 0) << info.output;
    EXPECT_NE(info.output.find("libembree3"), std::string::npos) << "LD_DEBUG=libs printed no library names";
    EXPECT_EQ(info.output.find("libOpenImageIO"), std::string::npos) << info.output;
    const std::string png = test::tmpPath("module.png");
    CommandResult render = vastray::test::runShell("LD_DEBUG=libs " + binary + " render --backend embree " +
                                                   terrain() + " -o " + png + " --resolution 16x16 --progress none");
    ASSERT_EQ(render.exitCode, 0) << render.output;
    EXPECT_NE(render.output.find("libOpenImageIO"), std::string::npos);
    EXPECT_TRUE(std::filesystem::exists(png));

    const std::string missing = "VASTRAY_IMAGE_MODULE=" + test::tmpPath("no-such-module.so") + " " + binary;
    const std::string never = test::tmpPath("never-written.png");
    CommandResult broken = vastray::test::runShell(missing + " render --backend embree " + terrain() + " -o " +
                                                   never + " --resolution 16x16 --stats --progress none");
    EXPECT_NE(broken.exitCode, 0);
    for (const char* text : {"never-written.png: cannot write", "libvastray_oiio.so", "no-such-module.so",
                             "VASTRAY_IMAGE_MODULE"})
        EXPECT_NE(broken.output.find(text), std::string::npos) << text << "\n" << broken.output;
    EXPECT_EQ(broken.output.find("rays/s"), std::string::npos) << "it rendered first:\n" << broken.output;
    EXPECT_FALSE(std::filesystem::exists(never));
    CommandResult diff = vastray::test::runShell(missing + " diff " + png + " " + png);
    EXPECT_NE(diff.exitCode, 0);
    EXPECT_NE(diff.output.find("libvastray_oiio.so"), std::string::npos) << diff.output;
}

// A .pfm is written without the image module (where it cannot be loaded, e.g. a device bundle)
// and holds the same linear colours as the .exr of the same render, rows bottom to top.
TEST_F(RenderCli, PfmIsWrittenWithoutTheImageModule) {
    const std::string binary = VASTRAY_BINARY;
    const std::string missing = "VASTRAY_IMAGE_MODULE=" + test::tmpPath("no-such-module.so") + " " + binary;
    const std::string pfm = test::tmpPath("beauty.pfm"), exr = test::tmpPath("beauty.exr");
    const std::string flags = " --backend embree --resolution 24x16 --spp 2 --progress none";
    CommandResult render = vastray::test::runShell("LD_DEBUG=libs " + missing + " render " + terrain() + " -o " +
                                                   pfm + flags);
    ASSERT_EQ(render.exitCode, 0) << render.output;
    EXPECT_EQ(render.output.find("libOpenImageIO"), std::string::npos) << "the module was loaded";
    ASSERT_EQ(runVastray("render " + terrain() + " -o " + exr + flags).exitCode, 0);

    std::ifstream in(pfm, std::ios::binary);
    std::string magic;
    uint32_t width = 0, height = 0;
    float scale = 0;
    in >> magic >> width >> height >> scale;
    in.get();  // the one whitespace byte before the floats
    ASSERT_EQ(magic, "PF");
    ASSERT_EQ(width, 24u);
    ASSERT_EQ(height, 16u);
    EXPECT_EQ(scale, -1.0f);  // little-endian
    std::vector<float> floats(3ull * width * height);
    in.read(reinterpret_cast<char*>(floats.data()), std::streamsize(floats.size() * 4));
    ASSERT_EQ(uint64_t(in.gcount()), floats.size() * 4);
    EXPECT_EQ(in.peek(), std::char_traits<char>::eof()) << "bytes after the pixels";

    auto expected = readImageChannels(exr, {"R", "G", "B"});
    ASSERT_TRUE(expected.isOk()) << expected.message();
    double sum = 0;
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x)
            for (uint32_t c = 0; c < 3; ++c) {
                const float stored = floats[(uint64_t(height - 1 - y) * width + x) * 3 + c];
                ASSERT_EQ(stored, expected->planes[c][uint64_t(y) * width + x]) << x << "," << y << " channel " << c;
                sum += stored;
            }
    EXPECT_GT(sum, 0.0) << "a black image proves nothing";

    for (const char* extra : {" --aovs depth", " --region 0,0,8,8"}) {
        const std::string never = test::tmpPath("never.pfm");
        std::filesystem::remove(never);
        CommandResult refused = runVastray("render " + terrain() + " -o " + never + flags + extra);
        EXPECT_EQ(refused.exitCode, 2) << extra << "\n" << refused.output;
        EXPECT_NE(refused.output.find(".exr"), std::string::npos) << extra << "\n" << refused.output;
        EXPECT_FALSE(std::filesystem::exists(never)) << extra;
    }
}

TEST_F(RenderCli, HelpNamesBothBackendsAndTheBudget) {
    CommandResult r = runVastray("render --help");
    EXPECT_EQ(r.exitCode, 0);
    for (const char* text : {"vulkan (streaming path tracer on the GPU", "embree (CPU reference", "--memory-budget",
                             "--host-cache", "--gpu-device", "chunkid,cost", "--path-state"})
        EXPECT_NE(r.output.find(text), std::string::npos) << text << "\n" << r.output;
}

TEST_F(RenderCli, WritesAPngAndTheStatsJson) {
    const std::string png = test::tmpPath("terrain.png"), stats = test::tmpPath("stats.json");
    CommandResult r = runVastray("render --backend embree " + terrain() + " -o " + png +
                                 " --resolution 48x32 --spp 2 --stats --stats-json " + stats +
                                 " --progress openjd");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(std::filesystem::exists(png));
    EXPECT_NE(r.output.find("openjd_progress: 100"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("rays/s"), std::string::npos) << r.output;
    std::ifstream in(stats);
    std::stringstream json;
    json << in.rdbuf();
    EXPECT_NE(json.str().find("\"backend\": \"embree\""), std::string::npos) << json.str();
    for (const char* key : {"render_seconds", "rays", "rays_per_second", "triangles", "peak_host_bytes"})
        EXPECT_GT(jsonNumber(json.str(), key), 0.0) << key << "\n" << json.str();
}

TEST_F(RenderCli, TwoRendersAreIdenticalAndDiffSaysSo) {
    const std::string a = test::tmpPath("same-a.exr"), b = test::tmpPath("same-b.exr");
    const std::string flags = " --resolution 40x30 --spp 2 --aovs depth,primid --progress none";
    ASSERT_EQ(runVastray("render --backend embree " + terrain() + " -o " + a + flags).exitCode, 0);
    ASSERT_EQ(
        runVastray("render --backend embree " + terrain() + " -o " + b + flags + " --threads 1").exitCode, 0);
    CommandResult d = runVastray("diff " + a + " " + b + " --json");
    ASSERT_EQ(d.exitCode, 0) << d.output;
    EXPECT_EQ(jsonNumber(d.output, "rmse"), 0.0) << d.output;
    EXPECT_EQ(jsonNumber(d.output, "primid_agreement"), 1.0) << d.output;
}

TEST_F(RenderCli, MeshFileAndPackageGiveTheSamePrimIds) {
    const std::string a = test::tmpPath("mesh.exr"), b = test::tmpPath("package.exr");
    const std::string flags = " --resolution 64x64 --spp 1 --aovs depth,primid --progress none";
    ASSERT_EQ(runVastray("render --backend embree " + terrain() + " -o " + a + flags).exitCode, 0);
    CommandResult r =
        runVastray("render --backend embree " + test::tmpPath("terrain.vast") + " -o " + b + flags);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    CommandResult d = runVastray("diff " + b + " " + a + " --json");
    ASSERT_EQ(d.exitCode, 0) << d.output;
    // 20-bit quantization moves a vertex by at most half a step (~1e-6 of the scene size):
    // only a pixel-centre ray passing that close to an edge may pick the neighbouring
    // triangle, far fewer than 1% of the pixels; depth moves by about as little.
    EXPECT_GE(jsonNumber(d.output, "primid_agreement"), 0.99) << d.output;
    EXPECT_LT(jsonNumber(d.output, "depth_mean_relative_error"), 1e-4) << d.output;
}

TEST_F(RenderCli, PackageSceneKeepsEachTriangleOnce) {
    // A sphere: its triangles straddle the cells' planes wherever they lie (the terrain's regular
    // grid of vertices can fall exactly on them, with a power-of-two grid step, and share none).
    const std::string ply = test::tmpPath("keep-once-sphere.ply"), package = test::tmpPath("keep-once-sphere.vast");
    ASSERT_EQ(runVastray("generate sphere --triangles 20000 --seed 3 -o " + ply).exitCode, 0);
    ASSERT_EQ(
        runVastray("import " + ply + " -o " + package + " --chunk-size 64KiB --progress none").exitCode, 0);
    auto reader = PackageReader::open(package);
    ASSERT_TRUE(reader) << reader.message();
    ASSERT_GT((*reader)->info().duplicatedReferences(), 0u) << "the test needs triangles shared by cells";
    auto scene = renderSceneFromPackage(**reader);
    ASSERT_TRUE(scene) << scene.message();
    EXPECT_EQ(scene->mesh.triangleCount(), (*reader)->info().triangleCount);
}

TEST_F(RenderCli, DiffFailsOnDifferentSizesOrChannels) {
    const std::string small = test::tmpPath("small.exr"), big = test::tmpPath("big.exr"),
                      aov = test::tmpPath("aov.exr");
    ASSERT_EQ(
        runVastray("render --backend embree " + terrain() + " -o " + small + " --resolution 16x16 --spp 1 --progress none").exitCode,
        0);
    ASSERT_EQ(
        runVastray("render --backend embree " + terrain() + " -o " + big + " --resolution 16x17 --spp 1 --progress none").exitCode,
        0);
    ASSERT_EQ(
        runVastray("render --backend embree " + terrain() + " -o " + aov + " --resolution 16x16 --spp 1 --aovs depth --progress none")
                   .exitCode,
        0);
    CommandResult sizes = runVastray("diff " + small + " " + big);
    EXPECT_NE(sizes.exitCode, 0);
    EXPECT_NE(sizes.output.find("sizes differ"), std::string::npos) << sizes.output;
    CommandResult channels = runVastray("diff " + small + " " + aov);
    EXPECT_NE(channels.exitCode, 0);
    EXPECT_NE(channels.output.find("channels differ"), std::string::npos) << channels.output;
}

// A little-endian portable float map of w x h RGB texels (rows bottom to top) from f(x, y, c),
// y counted from the top; `header` replaces the size line when given.
void writePfm(const std::string& path, uint32_t w, uint32_t h, float (*f)(uint32_t, uint32_t, uint32_t),
              const std::string& header = "") {
    std::ofstream out(path, std::ios::binary);
    out << "PF\n" << (header.empty() ? std::to_string(w) + " " + std::to_string(h) : header) << "\n-1.0\n";
    for (uint32_t y = h; y-- > 0;)
        for (uint32_t x = 0; x < w; ++x)
            for (uint32_t c = 0; c < 3; ++c) {
                const float v = f(x, y, c);
                out.write(reinterpret_cast<const char*>(&v), 4);
            }
}

float skyTexel(uint32_t x, uint32_t y, uint32_t c) {
    if (x == 5 && y == 2) return 40.0f;
    return y < 4 ? 0.4f + 0.1f * float(c) : 0.2f;
}

// --environment FILE lights the render with the file's map (both backends); the scale multiplies
// it (a power of two exactly: the sampling does not depend on it); bad files and flags are
// named errors.
TEST_F(RenderCli, EnvironmentMapLightsTheRenderAndBadMapsAreNamed) {
    const std::string sky = test::tmpPath("sky.pfm");
    writePfm(sky, 16, 8, skyTexel);
    const std::string flags = " --resolution 24x16 --spp 4 --progress none --environment " + sky;
    std::vector<std::vector<float>> images;
    for (const std::string scale : {"1", "2", "0"}) {
        const std::string out = test::tmpPath("env-" + scale + ".exr");
        CommandResult r = runVastray("render " + terrain() + " -o " + out + " --backend embree --environment-scale " + scale + flags);
        ASSERT_EQ(r.exitCode, 0) << r.output;
        auto rgb = readImageChannels(out, {"R", "G", "B"});
        ASSERT_TRUE(rgb) << rgb.message();
        std::vector<float> all;
        for (const auto& plane : rgb->planes) all.insert(all.end(), plane.begin(), plane.end());
        images.push_back(all);
    }
    double energy = 0;
    for (size_t i = 0; i < images[0].size(); ++i) {
        ASSERT_EQ(images[1][i], 2.0f * images[0][i]) << i;
        ASSERT_EQ(images[2][i], 0.0f) << "the default sun is off with a map, and the map scaled to black: " << i;
        energy += images[0][i];
    }
    EXPECT_GT(energy, 0.0);
    // The Vulkan backend (the map's device bytes kept from the budget) renders it too.
    const std::string device = test::tmpPath("env-vulkan.exr");
    CommandResult vulkan = runVastray("render " + test::tmpPath("terrain.vast") + " -o " + device + flags);
    ASSERT_EQ(vulkan.exitCode, 0) << vulkan.output;

    const std::string nan = test::tmpPath("nan.pfm"), huge = test::tmpPath("huge.pfm"), text = test::tmpPath("text.exr");
    writePfm(nan, 4, 2, [](uint32_t x, uint32_t y, uint32_t c) { return x == 1 && y == 0 && c == 2 ? std::nanf("") : 1.0f; });
    writePfm(huge, 1, 1, skyTexel, "100000 100000");
    std::ofstream(text) << "not an image";
    const std::string out = test::tmpPath("never-env.exr");
    const std::vector<std::tuple<std::string, int, std::string>> cases{
        {"--environment " + nan, 1, "nan.pfm: texel (1, 0) channel B is nan"},
        {"--environment " + huge, 1, "huge.pfm: 100000x100000 pixels is more than the 67108864"},
        {"--environment " + text, 1, "text.exr"},
        {"--environment " + test::tmpPath("missing.hdr"), 2, "missing.hdr"},
        {"--environment-scale 2", 2, "--environment-scale needs --environment"},
        {"--environment-rotate 10", 2, "--environment-rotate needs --environment"},
        {"--environment " + sky + " --environment-rotate 400", 2, "--environment-rotate 400"},
        {"--environment " + sky + " --environment-rotate nan", 2, "--environment-rotate"},
        {"--environment " + sky + " --environment-scale -1", 2, "--environment-scale -1"},
        {"--environment " + sky + " --integrator ao", 2, "--integrator ao has no lights"},
    };
    for (const auto& [flag, code, message] : cases) {
        CommandResult r = runVastray("render " + terrain() + " -o " + out + " --backend embree --progress none " + flag);
        EXPECT_EQ(r.exitCode, code) << flag << "\n" << r.output;
        EXPECT_NE(r.output.find(message), std::string::npos) << flag << "\n" << r.output;
        EXPECT_FALSE(std::filesystem::exists(out)) << flag;
    }
}

}  // namespace
}  // namespace vastray
