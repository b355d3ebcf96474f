#include <gtest/gtest.h>

#include <vector>

#include "vastray/gpu/TileGrid.h"

namespace vastray::gpu {
namespace {

// Every pixel in exactly one tile, no tile above the limit, tiles near square when the limit
// allows (the point of them: a wave's paths stay in a small part of the scene).
TEST(TileGrid, TilesCoverTheImageOnceWithinTheLimit) {
    struct Case {
        uint32_t width, height;
        uint64_t maxPixels;
    };
    for (const Case c : {Case{1920, 1080, 11530}, Case{1920, 1080, 1u << 21}, Case{1920, 1080, 1},
                         Case{7, 5, 3}, Case{1, 1000, 10}, Case{1000, 1, 10}, Case{64, 64, 4096},
                         Case{64, 64, 4095}, Case{333, 77, 333}}) {
        const TileGrid g = planTiles(c.width, c.height, c.maxPixels);
        std::vector<int> covered(uint64_t(c.width) * c.height, 0);
        for (uint32_t row = 0; row < g.rows; ++row)
            for (uint32_t col = 0; col < g.columns; ++col) {
                const uint32_t x = col * g.tileWidth, y = row * g.tileHeight;
                ASSERT_LT(x, c.width);
                ASSERT_LT(y, c.height);
                const uint32_t w = std::min(g.tileWidth, c.width - x), h = std::min(g.tileHeight, c.height - y);
                EXPECT_LE(uint64_t(w) * h, c.maxPixels) << c.width << "x" << c.height << " limit " << c.maxPixels;
                for (uint32_t j = y; j < y + h; ++j)
                    for (uint32_t i = x; i < x + w; ++i) ++covered[uint64_t(j) * c.width + i];
            }
        for (size_t p = 0; p < covered.size(); ++p)
            ASSERT_EQ(covered[p], 1) << "pixel " << p << " of " << c.width << "x" << c.height << " limit " << c.maxPixels;
    }
    const TileGrid hd = planTiles(1920, 1080, 11530);  // a 4x-over-budget wave of 16 spp paths
    EXPECT_EQ(hd.tileWidth, 107u);
    EXPECT_EQ(hd.tileHeight, 99u);
    EXPECT_EQ(hd.count(), 18u * 11u);
    EXPECT_EQ(planTiles(1920, 1080, 1920 * 1080).count(), 1u) << "a wave that holds the image is one tile";
}

}  // namespace
}  // namespace vastray::gpu
