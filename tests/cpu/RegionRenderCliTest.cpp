// `vastray render --region / --tile` and `vastray assemble` on the Embree backend: tiles join
// into the whole frame bit for bit; bad regions and bad tile sets are errors that name the
// option or the file; `--progress openjd` speaks OpenJD's protocol on stdout.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "CommandRunner.h"
#include "RegionTestSupport.h"
#include "TestScenes.h"

namespace vastray {
namespace {

using test::CommandResult;
using test::runVastray;


class RegionCli : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        CommandResult g = runVastray("generate terrain --triangles 5000 --seed 5 -o " + scene());
        ASSERT_EQ(g.exitCode, 0) << g.output;
    }
    static std::string scene() { return test::tmpPath("region-terrain.ply"); }
    // 50x37 does not divide by 3 or 2: the tiles are of uneven sizes (16/17 wide, 18/19 high).
    static std::string embree(const std::string& extra = "") {
        return scene() + " --backend embree --resolution 50x37 --spp 3 --seed 9" + extra;
    }
    // A tile of the 50x37 frame rendered with `flags` (--region or --tile ...), EXR with AOVs.
    static std::string renderTile(const std::string& name, const std::string& flags,
                                  const std::string& extra = " --aovs depth,primid") {
        const std::string out = test::tmpPath(name);
        CommandResult r = runVastray("render " + embree(extra) + " -o " + out + " --progress none " + flags);
        EXPECT_EQ(r.exitCode, 0) << flags << "\n" << r.output;
        return out;
    }
};

TEST_F(RegionCli, ExrTilesWithAovsAssembleToTheWholeFrameBitForBit) {
    test::expectTilesAssembleToTheWholeFrame(embree(" --aovs depth,normal,albedo,primid"),
                                             test::tmpPath("embree-exr-"), ".exr", 3, 2);
}

TEST_F(RegionCli, PngTilesAssembleToTheWholeFrameBitForBit) {
    test::expectTilesAssembleToTheWholeFrame(embree(), test::tmpPath("embree-png-"), ".png", 3, 2);
}

TEST_F(RegionCli, OneColumnAndOnePixelTilesToo) {
    test::expectTilesAssembleToTheWholeFrame(scene() + " --backend embree --resolution 7x5 --spp 2",
                                             test::tmpPath("embree-fine-"), ".exr", 7, 1);
    test::expectTilesAssembleToTheWholeFrame(scene() + " --backend embree --resolution 3x2 --spp 2",
                                             test::tmpPath("embree-pixels-"), ".png", 3, 2);
}

TEST_F(RegionCli, ARegionImageHasTheRegionsSizeAndRecordsItsPlace) {
    for (const char* ext : {".exr", ".png"}) {
        const std::string out = renderTile(std::string("place") + ext, "--region 16,18,33,37", "");
        auto image = readStoredImage(out);
        ASSERT_TRUE(bool(image)) << image.message();
        EXPECT_EQ(image->width, 17u) << ext;
        EXPECT_EQ(image->height, 19u) << ext;
        EXPECT_EQ(image->originX, 16u) << ext;
        EXPECT_EQ(image->originY, 18u) << ext;
        EXPECT_EQ(image->frameWidth, 50u) << ext;
        EXPECT_EQ(image->frameHeight, 37u) << ext;
    }
    // --tile 4 of 3x2 is the same rectangle (columns 0,16,33,50; rows 0,18,37).
    test::expectSameStoredImage(renderTile("tile4.exr", "--tile 4 --tiles 3,2"),
                                renderTile("region4.exr", "--region 16,18,33,37"));
}

TEST_F(RegionCli, BadRegionsAreClearErrorsNamingTheOptionAndTheLimit) {
    const std::vector<std::pair<std::string, std::string>> cases{
        {"--region 0,0,51,10", "--region 0,0,51,10: X1 51 is beyond the image width 50"},
        {"--region 0,0,10,38", "--region 0,0,10,38: Y1 38 is beyond the image height 37"},
        {"--region 5,0,5,10", "--region 5,0,5,10: empty"},
        {"--region 9,3,2,10", "--region 9,3,2,10: empty"},
        {"--region 1,2,3", "--region '1,2,3': expected X0,Y0,X1,Y1"},
        {"--region 0,0,-4,10", "--region '0,0,-4,10': expected X0,Y0,X1,Y1"},
        {"--region 0,0,10,10,4", "expected X0,Y0,X1,Y1"},
        {"--tile 6 --tiles 3,2", "--tile 6 is outside [0, 5]"},
        {"--tile -2 --tiles 3,2", "--tile -2 is outside [0, 5]"},
        {"--tile 1", "--tile needs --tiles NX,NY"},
        {"--tiles 3,2", "--tiles needs --tile I"},
        {"--tile 0 --tiles 0,2", "--tiles 0,2: NX must be in [1, 50]"},
        {"--tile 0 --tiles 3,38", "NY in [1, 37]"},
        {"--tile 0 --tiles 3", "--tiles '3': expected NX,NY"},
        {"--region 0,0,4,4 --tile 0 --tiles 2,2", "--region and --tile/--tiles exclude each other"},
    };
    const std::string out = test::tmpPath("never-region.exr");
    for (const auto& [flags, message] : cases) {
        std::filesystem::remove(out);
        CommandResult r = runVastray("render " + embree() + " -o " + out + " " + flags);
        EXPECT_EQ(r.exitCode, 2) << flags << "\n" << r.output;
        EXPECT_NE(r.output.find(message), std::string::npos) << flags << "\n" << r.output;
        EXPECT_FALSE(std::filesystem::exists(out)) << flags;
    }
}

TEST_F(RegionCli, AssembleRefusesOverlapsGapsAndMismatchesNamingTheFile) {
    const std::string left = renderTile("left.exr", "--region 0,0,25,37");
    const std::string right = renderTile("right.exr", "--region 25,0,50,37");
    const std::string wide = renderTile("wide.exr", "--region 20,0,50,37");
    const std::string top = renderTile("top.exr", "--region 25,0,50,30");
    const std::string noAovs = renderTile("noaovs.exr", "--region 25,0,50,37", "");
    const std::string out = test::tmpPath("assembled-bad.exr");
    const auto refuses = [&](const std::string& tiles, const std::string& message) {
        std::filesystem::remove(out);
        CommandResult r = runVastray("assemble " + tiles + " -o " + out);
        EXPECT_EQ(r.exitCode, 1) << tiles << "\n" << r.output;
        EXPECT_NE(r.output.find(message), std::string::npos) << tiles << "\n" << r.output;
        EXPECT_FALSE(std::filesystem::exists(out)) << tiles;
    };
    refuses(left + " " + wide,
            wide + " (pixels 20,0,50,37) overlaps " + left + " (pixels 0,0,25,37) at pixels 20,0,25,37");
    refuses(left + " " + left, "overlaps " + left);
    refuses(left + " " + top,
            "the tiles do not cover the 50x37 frame: pixels 25,30,50,37 (X1, Y1 exclusive) are in no tile");
    refuses(left, "pixels 25,0,50,37 (X1, Y1 exclusive) are in no tile");
    refuses(left + " " + noAovs, noAovs + ": channels R,G,B,A differ from " + left + "'s R,G,B,A,Z,primid");
    // Another --resolution: another frame.
    const std::string other = test::tmpPath("other-frame.exr");
    ASSERT_EQ(runVastray("render " + scene() + " --backend embree --resolution 50x40 --spp 1 --aovs depth,primid -o " + other +
                         " --region 25,0,50,37 --progress none").exitCode, 0);
    refuses(left + " " + other, other + ": full frame 50x40 differs from " + left + "'s 50x37");
    // Another camera (EXR worldToCamera / worldToNDC): tiles of another view.
    const std::string turned = renderTile("turned.exr", "--region 25,0,50,37 --fov 60");
    refuses(left + " " + turned, turned + ": its camera (EXR worldToCamera, worldToNDC) differs from " + left + "'s");
    // Not an image, and no file at all.
    const std::string junk = test::tmpPath("junk.exr");
    std::ofstream(junk) << "not an image";
    refuses(left + " " + junk, junk);
    refuses(left + " " + test::tmpPath("absent.exr"), test::tmpPath("absent.exr"));
    // Usage: formats must agree.
    CommandResult mixed =
        runVastray("assemble " + left + " " + right + " -o " + test::tmpPath("assembled.png"));
    EXPECT_EQ(mixed.exitCode, 2) << mixed.output;
    EXPECT_NE(mixed.output.find(left + ": tiles must have the output's format"), std::string::npos) << mixed.output;
    // And the good pair works.
    CommandResult good = runVastray("assemble " + right + " " + left + " -o " + out);
    EXPECT_EQ(good.exitCode, 0) << good.output;
}

// OpenJD reads an action's stdout (openjd-sessions merges stderr into it; the specification
// defines the messages on stdout): status, progress and failure lines must be there.
TEST_F(RegionCli, OpenJdProgressStatusAndFailLinesAreOnStdout) {
    const std::string out = test::tmpPath("openjd.png");
    const std::string binary = VASTRAY_BINARY;
    CommandResult r = test::runShell("(" + binary + " render " + embree() + " -o " + out +
                                     " --tile 1 --tiles 3,2 --progress openjd 2>/dev/null)");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("openjd_status: rendering pixels 16,0,33,18 of 50x37"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("openjd_progress: 100\n"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("openjd_status: wrote " + out), std::string::npos) << r.output;
    CommandResult bad = test::runShell("(" + binary + " render " + embree() + " -o " + out +
                                       " --region 0,0,99,5 --progress openjd 2>/dev/null)");
    EXPECT_EQ(bad.exitCode, 2) << bad.output;
    EXPECT_NE(bad.output.find("openjd_fail: --region 0,0,99,5: X1 99 is beyond the image width 50"), std::string::npos)
        << bad.output;
    // Other modes keep stdout free of progress.
    CommandResult quiet = test::runShell("(" + binary + " render " + embree() + " -o " + out +
                                         " --progress auto 2>/dev/null)");
    EXPECT_EQ(quiet.exitCode, 0) << quiet.output;
    EXPECT_EQ(quiet.output.find("openjd_"), std::string::npos) << quiet.output;
}

}  // namespace
}  // namespace vastray
