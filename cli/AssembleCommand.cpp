// `vastray assemble TILE... -o OUT`: joins region renders (`render --region` / `--tile`) into
// the full frame, every channel copied as stored (no conversion), so the result equals the
// whole-frame render bit for bit.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "Commands.h"
#include "OutputPath.h"
#include "vastray/core/FilePath.h"
#include "vastray/core/ImageFile.h"
#include "vastray/core/RenderOptions.h"

namespace vastray::cli {
namespace {

struct AssembleArgs {
    std::vector<std::string> tiles;
    std::string output;
};


// "X0,Y0,X1,Y1" (X1, Y1 exclusive), as --region takes it.
std::string describe(const PixelBounds& b) {
    return std::to_string(b.x0) + "," + std::to_string(b.y0) + "," + std::to_string(b.x1) + "," + std::to_string(b.y1);
}

PixelBounds boundsOf(const StoredImage& image) {
    return {image.originX, image.originY, image.originX + image.width, image.originY + image.height};
}

std::string join(const std::vector<std::string>& names) {
    std::string text;
    for (const std::string& n : names) text += (text.empty() ? "" : ",") + n;
    return text;
}

Status checkUsage(const AssembleArgs& args) {
    const std::string ext = lowerExtension(args.output);
    if (ext != ".png" && ext != ".exr") return Status::error("-o " + args.output + ": output must be .png or .exr");
    for (const std::string& tile : args.tiles)
        if (lowerExtension(tile) != ext)
            return Status::error(tile + ": tiles must have the output's format (" + ext + ", as -o " + args.output +
                                 ")");
    return checkWritableOutput("-o", args.output);
}

// A tile agrees with the first in frame size, channels and their sample types.
Status checkMatches(const std::string& path, const StoredImage& tile, const std::string& firstPath,
                    const StoredImage& first) {
    if (tile.frameWidth != first.frameWidth || tile.frameHeight != first.frameHeight)
        return Status::error(path + ": full frame " + std::to_string(tile.frameWidth) + "x" +
                             std::to_string(tile.frameHeight) + " differs from " + firstPath + "'s " +
                             std::to_string(first.frameWidth) + "x" + std::to_string(first.frameHeight));
    if (tile.channels != first.channels)
        return Status::error(path + ": channels " + join(tile.channels) + " differ from " + firstPath + "'s " +
                             join(first.channels));
    if (tile.types != first.types)
        return Status::error(path + ": channel sample types differ from " + firstPath + "'s");
    if (tile.hasCamera != first.hasCamera || tile.worldToCamera != first.worldToCamera ||
        tile.worldToNdc != first.worldToNdc)
        return Status::error(path + ": its camera (EXR worldToCamera, worldToNDC) differs from " + firstPath + "'s");
    return Status::ok();
}

// Tiles may not share a pixel: the first pair that does is named, with the shared rectangle.
Status checkOverlap(const std::vector<std::string>& paths, const std::vector<PixelBounds>& placed,
                    const std::string& path, const PixelBounds& b) {
    for (size_t i = 0; i < placed.size(); ++i) {
        const PixelBounds& o = placed[i];
        const PixelBounds shared{std::max(o.x0, b.x0), std::max(o.y0, b.y0), std::min(o.x1, b.x1),
                                 std::min(o.y1, b.y1)};
        if (shared.x0 < shared.x1 && shared.y0 < shared.y1)
            return Status::error(path + " (pixels " + describe(b) + ") overlaps " + paths[i] + " (pixels " +
                                 describe(o) + ") at pixels " + describe(shared));
    }
    return Status::ok();
}

// Called when the tiles' areas do not add up to the frame: which pixels no tile covers.
Status uncoveredError(const std::vector<PixelBounds>& placed, uint32_t width, uint32_t height) {
    std::vector<bool> covered(uint64_t(width) * height, false);
    for (const PixelBounds& b : placed)
        for (uint32_t y = b.y0; y < b.y1; ++y)
            std::fill_n(covered.begin() + int64_t(uint64_t(y) * width + b.x0), b.width(), true);
    PixelBounds hull{width, height, 0, 0};
    uint64_t missing = 0;
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x)
            if (!covered[uint64_t(y) * width + x]) {
                ++missing;
                hull = {std::min(hull.x0, x), std::min(hull.y0, y), std::max(hull.x1, x + 1), std::max(hull.y1, y + 1)};
            }
    const std::string frame = std::to_string(width) + "x" + std::to_string(height);
    if (missing == hull.pixelCount())
        return Status::error("the tiles do not cover the " + frame + " frame: pixels " + describe(hull) +
                             " (X1, Y1 exclusive) are in no tile");
    return Status::error("the tiles do not cover the " + frame + " frame: " + std::to_string(missing) +
                         " pixels are in no tile, all within pixels " + describe(hull) + " (X1, Y1 exclusive)");
}

void copyInto(const StoredImage& tile, StoredImage& frame) {
    const uint64_t pixelBytes = frame.pixelBytes(), rowBytes = uint64_t(tile.width) * pixelBytes;
    for (uint32_t row = 0; row < tile.height; ++row)
        std::memcpy(frame.pixels.data() + ((uint64_t(tile.originY) + row) * frame.width + tile.originX) * pixelBytes,
                    tile.pixels.data() + row * rowBytes, rowBytes);
}

int assemble(const AssembleArgs& args) {
    if (Status usage = checkUsage(args); !usage) {
        std::fprintf(stderr, "vastray assemble: %s\n", usage.message().c_str());
        return 2;
    }
    const auto fail = [](const Status& status) {
        std::fprintf(stderr, "vastray assemble: %s\n", status.message().c_str());
        return 1;
    };
    StoredImage frame;
    std::vector<PixelBounds> placed;
    for (size_t i = 0; i < args.tiles.size(); ++i) {
        const std::string& path = args.tiles[i];
        auto tile = readStoredImage(path);
        if (!tile) return fail(tile.status());
        if (i == 0) {
            frame = *tile;
            frame.width = tile->frameWidth, frame.height = tile->frameHeight;
            frame.originX = frame.originY = 0;
            frame.pixels.assign(uint64_t(frame.width) * frame.height * frame.pixelBytes(), 0);
        } else if (Status match = checkMatches(path, *tile, args.tiles[0], frame); !match) {
            return fail(match);
        }
        const PixelBounds bounds = boundsOf(*tile);
        if (Status overlap = checkOverlap(args.tiles, placed, path, bounds); !overlap) return fail(overlap);
        placed.push_back(bounds);
        copyInto(*tile, frame);
    }
    uint64_t covered = 0;
    for (const PixelBounds& b : placed) covered += b.pixelCount();
    if (covered != uint64_t(frame.width) * frame.height) return fail(uncoveredError(placed, frame.width, frame.height));
    if (Status written = writeStoredImage(args.output, frame); !written) return fail(written);
    return 0;
}

int runAssemble(const AssembleArgs& args) {
    try {
        return assemble(args);
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "vastray assemble: out of host memory for the full frame\n");
        return 1;
    }
}

}  // namespace

CommandRun addAssembleCommand(CLI::App& app) {
    auto args = std::make_shared<AssembleArgs>();
    CLI::App* cmd = app.add_subcommand(
        "assemble",
        "Join region renders (render --region or --tile) into the full frame: every channel copied as stored, "
        "so the result equals the whole-frame render bit for bit. The tiles must cover the frame exactly once "
        "and agree in frame size and channels.");
    cmd->add_option("tiles", args->tiles, "region images (.exr or .png, the output's format)")->required();
    cmd->add_option("-o,--output", args->output, "the full frame to write (.exr or .png)")->required();
    return [args]() { return runAssemble(*args); };
}

}  // namespace vastray::cli
