// deploy/openjd/vastray-render.yaml run end to end by openjd-cli (`openjd check`, `openjd run`;
// scripts/install-openjd.sh installs it): a terrain imported once, rendered as 3x2 tiles of a
// 50x37 frame (uneven tiles) on the Vulkan backend, assembled. The job's frame must equal the
// whole-frame render bit for bit, the tasks' OpenJD messages must reach the runtime, and a task
// that fails must fail the job with its openjd_fail message.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "CommandRunner.h"
#include "RegionTestSupport.h"
#include "TestTmp.h"

namespace vastray {
namespace {

std::string tmp(const std::string& name) { return (test::testTmpDir("openjd") / name).string(); }

test::CommandResult openjd(const std::string& arguments) {
    return test::runShell(std::string(VASTRAY_OPENJD) + " " + arguments);
}

// `openjd run` of the template with the job parameters `params` (-p KEY=VALUE ...).
test::CommandResult runJob(const std::string& params) {
    return openjd("run " + std::string(VASTRAY_OPENJD_TEMPLATE) + " -p Vastray=" + VASTRAY_BINARY + " " + params);
}

class OpenJdTemplate : public ::testing::Test {
protected:
    void SetUp() override {
        ASSERT_TRUE(std::filesystem::exists(VASTRAY_OPENJD))
            << VASTRAY_OPENJD << " is missing: run scripts/install-openjd.sh (scripts/install-deps.sh does)";
    }
};

TEST_F(OpenJdTemplate, PassesOpenJdCheck) {
    test::CommandResult r = openjd("check " + std::string(VASTRAY_OPENJD_TEMPLATE));
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("passes validation checks"), std::string::npos) << r.output;
}

TEST_F(OpenJdTemplate, JobFrameEqualsTheWholeFrameRender) {
    const std::string ply = tmp("terrain.ply"), work = tmp("job"), frame = tmp("job.exr");
    ASSERT_EQ(test::runVastray("generate terrain --triangles 5000 --seed 7 -o " + ply).exitCode, 0);
    std::filesystem::remove_all(work);
    test::CommandResult job =
        runJob("-p Scene=" + ply + " -p Output=" + frame + " -p WorkDir=" + work +
               " -p Backend=vulkan -p Resolution=50x37 -p Spp=2 -p Seed=3 -p TilesX=3 -p TilesY=2"
               " -p 'RenderArgs=--aovs depth,primid,chunkid --memory-budget 8MiB'");
    ASSERT_EQ(job.exitCode, 0) << job.output;
    EXPECT_NE(job.output.find("Session ended successfully"), std::string::npos) << job.output;
    EXPECT_NE(job.output.find("openjd_status: rendering pixels 33,18,50,37 of 50x37"), std::string::npos)
        << job.output;
    EXPECT_NE(job.output.find("openjd_progress: 100"), std::string::npos) << job.output;
    // The same frame rendered whole from the job's package, with the same options.
    const std::string whole = tmp("whole.exr");
    test::CommandResult w = test::runVastray("render " + work + "/scene.vast -o " + whole +
                                             " --backend vulkan --resolution 50x37 --spp 2 --seed 3"
                                             " --aovs depth,primid,chunkid --memory-budget 8MiB --progress none");
    ASSERT_EQ(w.exitCode, 0) << w.output;
    test::expectSameStoredImage(frame, whole);
}

// --tiles 3,1 over a 2x2 frame: every render task fails; so must the job, with vastray's message.
TEST_F(OpenJdTemplate, AFailingTaskFailsTheJobWithItsMessage) {
    const std::string ply = tmp("terrain-small.ply");
    ASSERT_EQ(test::runVastray("generate terrain --triangles 200 -o " + ply).exitCode, 0);
    test::CommandResult job = runJob("-p Scene=" + ply + " -p Output=" + tmp("bad.png") + " -p WorkDir=" +
                                     tmp("bad-job") + " -p Backend=embree -p Resolution=2x2 -p Spp=1 -p TilesX=3"
                                     " -p TilesY=1");
    EXPECT_NE(job.exitCode, 0) << job.output;
    EXPECT_NE(job.output.find("openjd_fail: --tiles 3,1: NX must be in [1, 2]"), std::string::npos) << job.output;
    EXPECT_FALSE(std::filesystem::exists(tmp("bad.png")));
}

}  // namespace
}  // namespace vastray
