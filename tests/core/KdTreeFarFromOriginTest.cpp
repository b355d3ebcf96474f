// Regression: a reference's padded bounds may reach outside its node box when triangles are
// small next to their distance from the origin; binning must never index outside its bins.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "vastray/core/KdTree.h"
#include "vastray/core/TriangleIntersect.h"

namespace vastray {
namespace {

struct Grid {
    std::vector<Vec3f> positions;
    std::vector<uint32_t> indices;
};

// The options the package builder uses for chunk trees (shallow, leaves of a few triangles).
KdBuildOptions chunkLikeOptions() {
    KdBuildOptions options;
    options.maxLeafSize = 4;
    options.intersectionCost = 2.0f;
    options.bins = 16;
    return options;
}

// A wavy height field of n×n cells of size `cell`, placed at `offset` on every axis.
Grid farGrid(int n, float cell, float offset) {
    Grid grid;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x)
            grid.positions.push_back({offset + x * cell, offset + 0.3f * cell * std::sin(0.7f * x + 1.3f * y),
                                      offset + y * cell});
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const uint32_t a = y * (n + 1) + x, b = a + 1, c = a + n + 1, d = c + 1;
            grid.indices.insert(grid.indices.end(), {a, c, d, a, d, b});
        }
    return grid;
}

TEST(KdTreeFarFromOrigin, BuildsAndFindsEveryTriangleFromAbove) {
    for (float offset : {1.0e3f, 1.0e5f}) {
        const int n = 120;
        const float cell = offset * 2e-6f;  // triangles a few ulps of the offset wide
        Grid grid = farGrid(n, cell, offset);
        const uint32_t count = uint32_t(grid.indices.size() / 3);
        const KdTree tree = buildKdTree(grid.positions.data(), grid.indices.data(), count, chunkLikeOptions());
        ASSERT_FALSE(tree.nodes.empty());
        // A ray straight down through each cell centre hits something.
        size_t misses = 0;
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const Ray ray{{offset + (x + 0.5f) * cell, offset + 10 * cell, offset + (y + 0.5f) * cell}, {0, -1, 0}};
                KdHit hit;
                misses += !intersectKdTree(tree, grid.positions.data(), grid.indices.data(), nullptr, ray, 0,
                                           INFINITY, &hit);
            }
        EXPECT_EQ(misses, 0u) << "offset " << offset;
    }
}

TEST(KdTreeFarFromOrigin, ThinStackOfLargeTrianglesFarAway) {
    // 200 overlapping unit-size triangles in layers 1e-5 apart at z ~ 1000: node boxes are far
    // thinner in z than the conservative padding of a straddling triangle's clipped bounds.
    Grid grid;
    for (uint32_t k = 0; k < 200; ++k) {
        const float z = 1000.0f + 1e-5f * float(k), s = 0.01f * float(k % 17);
        grid.positions.push_back({1000.0f + s, 1000.0f, z});
        grid.positions.push_back({1001.0f, 1000.0f + s, z});
        grid.positions.push_back({1000.0f + s, 1001.0f - s, z});
        grid.indices.insert(grid.indices.end(), {3 * k, 3 * k + 1, 3 * k + 2});
    }
    const KdTree tree = buildKdTree(grid.positions.data(), grid.indices.data(), 200, chunkLikeOptions());
    ASSERT_FALSE(tree.nodes.empty());
    const Ray ray{{1000.6f, 1000.3f, 1010.0f}, {0, 0, -1}};
    KdHit hit;
    ASSERT_TRUE(intersectKdTree(tree, grid.positions.data(), grid.indices.data(), nullptr, ray, 0, INFINITY, &hit));
    EXPECT_GE(hit.t, 9.99f);
}

class KdTreeSmallTrianglesFarAway : public ::testing::TestWithParam<float> {};

TEST_P(KdTreeSmallTrianglesFarAway, ConservativeBoundsCrossingLaterPlanesAreHandled) {
    const float offset = GetParam();
    // Triangles of size ~0.05 far from the origin: the 2^-20 padding of a straddler's part
    // bounds (0.01 at 1e4, 0.3 at 3e5) reaches past the triangle, so later planes cut padded
    // bounds without cutting the triangle. The side it does not reach must not get an empty
    // (inverted) part: that used to index outside the SAH bins.
    Grid grid;
    uint64_t state = 12345;
    auto next = [&state] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return float(state >> 40) / float(1 << 24);
    };
    const uint32_t count = 40000;
    for (uint32_t k = 0; k < count; ++k) {
        const Vec3f c{offset + 10 * next(), offset + 10 * next(), offset + 10 * next()};
        for (int v = 0; v < 3; ++v)
            grid.positions.push_back({c.x + 0.05f * next(), c.y + 0.05f * next(), c.z + 0.05f * next()});
        grid.indices.insert(grid.indices.end(), {3 * k, 3 * k + 1, 3 * k + 2});
    }
    const KdTree tree = buildKdTree(grid.positions.data(), grid.indices.data(), count, chunkLikeOptions());
    ASSERT_FALSE(tree.nodes.empty());
    for (const KdNode& node : tree.nodes) {
        if (!node.isLeaf()) {
            ASSERT_TRUE(std::isfinite(node.split()));
        }
    }
    // The tree finds the same closest hit as testing every triangle (same triangle test, so
    // the same t bit for bit), for rays through triangle centroids.
    size_t mismatches = 0;
    for (uint32_t k = 0; k < count; k += 97) {
        const Vec3f* p = &grid.positions[3 * k];
        const Ray ray{(p[0] + p[1] + p[2]) * (1.0f / 3) - Vec3f{0.3f, 0.2f, 1.0f}, {0.3f, 0.2f, 1.0f}};
        float best = INFINITY;
        for (uint32_t t = 0; t < count; ++t) {
            TriangleHit h;
            if (intersectTriangle(ray, grid.positions[3 * t], grid.positions[3 * t + 1], grid.positions[3 * t + 2],
                                  false, 0, best, &h))
                best = h.t;
        }
        KdHit hit;
        const bool found = intersectKdTree(tree, grid.positions.data(), grid.indices.data(), nullptr, ray, 0, INFINITY, &hit);
        mismatches += found != std::isfinite(best) || (found && hit.t != best);
    }
    EXPECT_EQ(mismatches, 0u);
}

INSTANTIATE_TEST_SUITE_P(Offsets, KdTreeSmallTrianglesFarAway, ::testing::Values(1e4f, 1e5f, 3e5f));

}  // namespace
}  // namespace vastray
