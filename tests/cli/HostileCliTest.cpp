// Issue 16: flags and paths a hostile or careless user gives `vastray`. Each is refused with
// the allowed range or the reason, before any work, and nothing hangs.
#include "CommandRunner.h"
#include "TestTmp.h"
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace {

using vastray::test::CommandResult;

class HostileCli : public ::testing::Test {
protected:
    // `timeout`: a regression that blocks (a FIFO) fails the test instead of stalling the suite.
    static CommandResult run(const std::string& arguments) {
        return vastray::test::runShell("timeout 60 " + std::string(VASTRAY_BINARY) + " " + arguments);
    }
    // A file in this suite's scratch folder.
    static std::string tmp(const std::string& name) {
        const std::filesystem::path dir = vastray::test::testTmpDir("cli-hostile");
        std::filesystem::create_directories(dir);
        return (dir / name).string();
    }
    static void SetUpTestSuite() {
        std::ofstream(tmp("tri.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        CommandResult i = run("import " + tmp("tri.obj") + " -o " + tmp("tri.vast") + " --progress none");
        ASSERT_EQ(i.exitCode, 0) << i.output;
    }
    static void expectRefused(const CommandResult& r, int exitCode, const std::string& message) {
        EXPECT_EQ(r.exitCode, exitCode) << r.output;
        EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
    }
};

TEST_F(HostileCli, ImportThreadsBeyondTheRangeAreRefused) {
    expectRefused(run("import " + tmp("tri.obj") + " -o " + tmp("t.vast") + " --threads 99999"), 2,
                  "--threads 99999 is outside [0, 4096]");
}

TEST_F(HostileCli, NegativeGpuDeviceIsRefusedWithTheRange) {
    expectRefused(run("render " + tmp("tri.vast") + " -o " + tmp("g.png") + " --gpu-device -5"), 2,
                  "--gpu-device -5: expected -1 (first discrete GPU) or a device index in [0, 255]");
}

// Was reported as "camera up is parallel to the view direction".
TEST_F(HostileCli, TinyFieldOfViewIsNamed) {
    expectRefused(run("render " + tmp("tri.vast") + " -o " + tmp("f.png") + " --fov 1e-30"), 2,
                  "--fov 1e-30 is outside [0.001, 180) degrees");
    expectRefused(run("render " + tmp("tri.vast") + " -o " + tmp("f.png") + " --fov 180"), 2,
                  "--fov 180 is outside [0.001, 180) degrees");
}

// Found out only after the whole render or import.
TEST_F(HostileCli, UnwritableOutputIsRefusedBeforeTheWork) {
    expectRefused(run("render " + tmp("tri.vast") + " -o " + tmp("tri.obj") + "/image.png --backend embree"), 2,
                  "image.png: folder '" + tmp("tri.obj") + "' does not exist");
    std::filesystem::create_directories(tmp("folder.png"));
    expectRefused(run("render " + tmp("tri.vast") + " -o " + tmp("folder.png") + " --backend embree"), 2,
                  "folder.png: exists and is not a regular file");
    expectRefused(run("render " + tmp("tri.vast") + " -o " + tmp("ok.png") + " --backend embree --stats-json " +
                      tmp("missing") + "/stats.json"),
                  2, "--stats-json");
    expectRefused(run("import " + tmp("tri.obj") + " -o " + tmp("nowhere") + "/tri.vast"), 2,
                  "tri.vast: folder '" + tmp("nowhere") + "' does not exist");
}

// A FIFO with no writer blocked `import` and `render` for ever.
TEST_F(HostileCli, FifoInputsAreRefusedByKind) {
    for (const char* name : {"fifo.obj", "fifo.vast"}) {
        std::filesystem::remove(tmp(name));
        ASSERT_EQ(::mkfifo(tmp(name).c_str(), 0600), 0);
    }
    expectRefused(run("import " + tmp("fifo.obj") + " -o " + tmp("fifo-out.vast")), 1,
                  "fifo.obj: is a FIFO; only regular files are read");
    expectRefused(run("render " + tmp("fifo.obj") + " -o " + tmp("fifo.png") + " --backend embree"), 1,
                  "fifo.obj: is a FIFO");
    expectRefused(run("info " + tmp("fifo.vast")), 1, "fifo.vast: is not a regular file");
}

// The documented maximum aborted with an uncaught std::bad_alloc. Under an address-space
// limit of 3 GiB the estimate (8 GiB: image and the writer's copy) refuses it by name.
TEST_F(HostileCli, RenderTooLargeForHostMemoryIsRefusedWithTheNeed) {
    const CommandResult r = vastray::test::runShell("ulimit -v 3145728; timeout 60 " + std::string(VASTRAY_BINARY) +
                                                    " render " + tmp("tri.vast") + " -o " + tmp("huge.exr") +
                                                    " --backend embree --resolution 16384x16384");
    expectRefused(r, 1, "a 16384x16384 render needs 8.0 GiB of host memory (image 4.0 GiB + writer 4.0 GiB)");
    EXPECT_NE(r.output.find("is available"), std::string::npos) << r.output;
}

}  // namespace

namespace {

// A material name longer than the package's 64-byte field, of 3-byte characters: the package
// keeps 21 whole ones (63 bytes), and `info --json` prints valid JSON (a split character made
// nlohmann::json throw, and the process abort).
TEST_F(HostileCli, LongMaterialNameIsCutToWholeCharacters) {
    std::string euro;
    for (int i = 0; i < 30; ++i) euro += "\xE2\x82\xAC";
    std::ofstream(tmp("euro.mtl")) << "newmtl " << euro << "\nKd 0.5 0.5 0.5\n";
    std::ofstream(tmp("euro.obj")) << "mtllib euro.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl " << euro << "\nf 1 2 3\n";
    CommandResult i = run("import " + tmp("euro.obj") + " -o " + tmp("euro.vast") + " --progress none");
    ASSERT_EQ(i.exitCode, 0) << i.output;
    CommandResult info = run("info " + tmp("euro.vast") + " --json");
    ASSERT_EQ(info.exitCode, 0) << info.output;
    EXPECT_NE(info.output.find("\"" + euro.substr(0, 63) + "\""), std::string::npos) << info.output;
}

}  // namespace
