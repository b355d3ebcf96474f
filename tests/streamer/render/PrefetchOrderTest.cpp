// The order in which a cold out-of-core render queues chunks for decoding: the first row of the
// image a chunk's cell may cover, top first, nearer first within a band, unseen chunks last.
#include <gtest/gtest.h>

#include <vector>

#include "render/PrefetchOrder.h"

namespace vastray::test {
namespace {

// The eye at z = 5 looking down -z with a 90-degree field: a point (x, y, z) in front of it lies
// at screen y / (5 - z), row (1 - y / (5 - z)) * 50 of a 100-row image.
Camera frontCamera() {
    Camera c;
    c.eye = {0, 0, 5}, c.target = {0, 0, 0}, c.up = {0, 1, 0}, c.fovYDegrees = 90.0f;
    return c;
}

Aabb box(Vec3f lo, Vec3f hi) {
    Aabb b;
    b.lo = lo, b.hi = hi;
    return b;
}

const PixelBounds kFrame{0, 0, 100, 100};

uint32_t firstRowSeen(const Aabb& cell, const Camera& camera, const PixelBounds& bounds) {
    return vastray::firstRowSeen(cell, CameraRays(camera, 100, 100), bounds, 100, 100);
}

TEST(PrefetchOrder, FirstRowIsTheProjectedTopOfTheBox) {
    const Camera camera = frontCamera();
    // Top corners at y = 2, nearest the eye at z = 0.1: row (1 - 2 / 4.9) * 50 = 29.6.
    EXPECT_EQ(firstRowSeen(box({-0.5f, 1, -0.1f}, {0.5f, 2, 0.1f}), camera, kFrame), 29u);
    // Below the centre: the top y = -1 lies farthest from the eye's level at z = -0.1: row 59.8.
    EXPECT_EQ(firstRowSeen(box({-0.5f, -2, -0.1f}, {0.5f, -1, 0.1f}), camera, kFrame), 59u);
    // A box reaching above the frame starts at row 0.
    EXPECT_EQ(firstRowSeen(box({-0.5f, -1, -0.1f}, {0.5f, 9, 0.1f}), camera, kFrame), 0u);
}

TEST(PrefetchOrder, BoxesBehindTheEyeOrOutsideTheViewAreUnseen) {
    const Camera camera = frontCamera();
    EXPECT_EQ(firstRowSeen(box({-1, -1, 6}, {1, 1, 7}), camera, kFrame), 100u);      // behind
    EXPECT_EQ(firstRowSeen(box({20, -1, -1}, {21, 1, 1}), camera, kFrame), 100u);    // far right
    EXPECT_EQ(firstRowSeen(box({-1, 20, -1}, {1, 21, 1}), camera, kFrame), 100u);    // far above
    // A box around the eye may cover any row.
    EXPECT_EQ(firstRowSeen(box({-1, -1, 4}, {1, 1, 6}), camera, kFrame), 0u);
}

TEST(PrefetchOrder, RowsCountFromTheRegionsTop) {
    const Camera camera = frontCamera();
    const PixelBounds lowerHalf{0, 50, 100, 100};
    EXPECT_EQ(firstRowSeen(box({-0.5f, -2, -0.1f}, {0.5f, -1, 0.1f}), camera, lowerHalf), 9u);
    EXPECT_EQ(firstRowSeen(box({-0.5f, 1, -0.1f}, {0.5f, 2, 0.1f}), camera, lowerHalf), 50u);  // above it
    // Spanning the region's top edge: its first row.
    EXPECT_EQ(firstRowSeen(box({-0.5f, -2, -0.1f}, {0.5f, 2, 0.1f}), camera, lowerHalf), 0u);
    const PixelBounds leftQuarter{0, 0, 25, 100};
    EXPECT_EQ(firstRowSeen(box({1, 1, -0.1f}, {2, 2, 0.1f}), camera, leftQuarter), 100u);  // right of it
}

TEST(PrefetchOrder, TopBandsFirstNearerFirstWithinABandUnseenLast) {
    PackageInfo package;
    auto add = [&](Aabb cell) {
        ChunkInfo c;
        c.id = uint32_t(package.chunks.size()), c.cell = cell;
        package.chunks.push_back(c);
    };
    add(box({-0.5f, -2, -0.1f}, {0.5f, -1, 0.1f}));    // 0: row 59
    add(box({-0.5f, 1, -0.1f}, {0.5f, 2, 0.1f}));      // 1: row 29, 4.9 from the eye
    add(box({-1, -1, 6}, {1, 1, 7}));                  // 2: behind the eye, 1 from it
    add(box({-2.5f, 2.5f, -5.1f}, {-1.5f, 4.5f, -4.9f}));  // 3: row (1 - 4.5 / 9.9) * 50 = 27.3, 9.9 away
    add(box({20, -1, -1}, {21, 1, 1}));                // 4: outside the view, ~20 away
    const std::vector<uint32_t> order = prefetchOrder(package, frontCamera(), kFrame, 100, 100);
    // Bands of 100 / 16 = 6 rows: rows 27 and 29 share band 4 (the nearer, 1, first), row 59 is
    // band 9; the unseen last, nearer first.
    EXPECT_EQ(order, (std::vector<uint32_t>{1, 3, 0, 2, 4}));
}

}  // namespace
}  // namespace vastray::test
