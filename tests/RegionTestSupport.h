#pragma once
// Region renders and `vastray assemble` through the CLI, for the Embree (cpu_tests) and Vulkan
// (stream_tests) backends alike: a frame rendered as tiles and assembled must equal the frame
// rendered whole, every stored bit of every channel.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "CommandRunner.h"
#include "vastray/core/ImageFile.h"

namespace vastray::test {

// Every stored byte of every channel, and the channel list and frame, are equal.
inline void expectSameStoredImage(const std::string& a, const std::string& b) {
    auto x = readStoredImage(a), y = readStoredImage(b);
    ASSERT_TRUE(bool(x)) << x.message();
    ASSERT_TRUE(bool(y)) << y.message();
    EXPECT_EQ(x->width, y->width);
    EXPECT_EQ(x->height, y->height);
    EXPECT_EQ(x->originX, y->originX);
    EXPECT_EQ(x->originY, y->originY);
    EXPECT_EQ(x->frameWidth, y->frameWidth);
    EXPECT_EQ(x->frameHeight, y->frameHeight);
    EXPECT_EQ(x->channels, y->channels);
    EXPECT_TRUE(x->types == y->types);
    ASSERT_EQ(x->pixels.size(), y->pixels.size());
    size_t differing = 0;
    for (size_t i = 0; i < x->pixels.size(); ++i) differing += x->pixels[i] != y->pixels[i];
    EXPECT_EQ(differing, 0u) << a << " and " << b << " differ in " << differing << " of " << x->pixels.size()
                             << " bytes";
}

// Renders `renderArgs` (input, options; no -o) whole and as an nx x ny grid of --tile renders
// into `dir` (a file name prefix), assembles the tiles and compares. `ext` is ".exr" or ".png".
inline void expectTilesAssembleToTheWholeFrame(const std::string& renderArgs, const std::string& prefix,
                                               const std::string& ext, int nx, int ny) {
    const std::string whole = prefix + "whole" + ext;
    CommandResult w = runVastray("render " + renderArgs + " -o " + whole + " --progress none");
    ASSERT_EQ(w.exitCode, 0) << w.output;
    std::string tiles;
    for (int i = 0; i < nx * ny; ++i) {
        const std::string tile = prefix + "tile" + std::to_string(i) + ext;
        CommandResult t = runVastray("render " + renderArgs + " -o " + tile + " --progress none --tile " +
                                     std::to_string(i) + " --tiles " + std::to_string(nx) + "," + std::to_string(ny));
        ASSERT_EQ(t.exitCode, 0) << t.output;
        tiles += " " + tile;
    }
    const std::string assembled = prefix + "assembled" + ext;
    CommandResult a = runVastray("assemble" + tiles + " -o " + assembled);
    ASSERT_EQ(a.exitCode, 0) << a.output;
    expectSameStoredImage(assembled, whole);
}

}  // namespace vastray::test
