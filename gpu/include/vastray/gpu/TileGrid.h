#pragma once
// How the device wavefront cuts an image into tiles when a wave cannot hold all its paths: a
// grid of near-square rectangles of at most maxPixels pixels each, every column of tiles the
// same width (but the last) and every row the same height (but the last). Square tiles keep a
// wave's camera rays, and the bounces from where they land, in a small part of the scene, so an
// out-of-core wave reaches fewer chunks than a strip of whole rows would (PERF_NOTES 39).
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace vastray::gpu {

struct TileGrid {
    uint32_t tileWidth = 0, tileHeight = 0;  // of every tile but those in the last column / row
    uint32_t columns = 0, rows = 0;
    uint64_t count() const { return uint64_t(columns) * rows; }
};

// width, height, maxPixels >= 1.
inline TileGrid planTiles(uint32_t width, uint32_t height, uint64_t maxPixels) {
    TileGrid g;
    if (uint64_t(width) * height <= maxPixels) {
        g.tileWidth = width, g.tileHeight = height, g.columns = g.rows = 1;
        return g;
    }
    // Columns from the square side, then the widest tile that many columns need; rows as tall as
    // the pixel limit allows, evened out over the image.
    const double side = std::sqrt(double(maxPixels));
    g.columns = uint32_t(std::clamp<double>(std::ceil(width / side), 1.0, double(width)));
    g.tileWidth = (width + g.columns - 1) / g.columns;
    g.columns = (width + g.tileWidth - 1) / g.tileWidth;
    const uint64_t tallest = std::max<uint64_t>(1, maxPixels / g.tileWidth);
    g.rows = uint32_t((height + tallest - 1) / tallest);
    g.tileHeight = (height + g.rows - 1) / g.rows;
    g.rows = (height + g.tileHeight - 1) / g.tileHeight;
    return g;
}

}  // namespace vastray::gpu
