#pragma once
// Walks a chunk BVH on the host, for the tests of its builder (core) and of the package reader
// (streamer): the same containment rules in one place.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "vastray/core/Bvh4.h"

namespace vastray::test {

// Every triangle is in exactly one leaf, and each corner lies in the child box the kernel
// decodes for its leaf and in the box of the node above (up to the rounding of the decoded
// box's one fp32 sum: one ulp of the coordinate, which the traversal's margins cover).
// Triangle p of the leaf order is order[p] of the input when order is given (the builder's
// output), p itself otherwise (a decoded chunk, already sorted). Returns the deepest node.
inline uint32_t expectBvhHoldsItsTriangles(const Bvh4& t, const std::vector<Vec3f>& positions,
                                           const std::vector<uint32_t>& indices, const std::vector<uint32_t>* order) {
    const uint32_t triangles = uint32_t(indices.size() / 3);
    EXPECT_EQ(validateBvh4Nodes(t.nodes, triangles), "");
    if (t.nodes.empty()) return 0;
    auto inside = [](Vec3f p, const Aabb& box) {
        for (int a = 0; a < 3; ++a) {
            const float ulp = std::nextafter(std::abs(p[a]), INFINITY) - std::abs(p[a]);
            if (p[a] < box.lo[a] - ulp || p[a] > box.hi[a] + ulp) return false;
        }
        return true;
    };
    std::vector<int> seen(triangles, 0);
    uint32_t deepest = 0;
    struct Item { uint32_t node, depth; Aabb box; };
    std::vector<Item> stack{{0, 0, t.bounds}};
    while (!stack.empty()) {
        const Item item = stack.back();
        stack.pop_back();
        deepest = std::max(deepest, item.depth);
        const Bvh4Node& n = t.nodes[item.node];
        for (int i = 0; i < 4; ++i) {
            const uint32_t w = n.child[i];
            if (w == kBvh4EmptyChild) continue;
            const Aabb box = bvh4ChildBox(n, i);
            if (!bvh4IsLeaf(w)) {
                stack.push_back({w, item.depth + 1, box});
                continue;
            }
            for (uint32_t p = bvh4LeafFirst(w); p < bvh4LeafFirst(w) + bvh4LeafCount(w); ++p) {
                const uint32_t tri = order ? (*order)[p] : p;
                ++seen[tri];
                for (int k = 0; k < 3; ++k) {
                    const Vec3f c = positions[indices[3 * size_t(tri) + k]];
                    EXPECT_TRUE(inside(c, box) && inside(c, item.box)) << "triangle " << tri << " corner " << k;
                }
            }
        }
    }
    for (uint32_t tri = 0; tri < triangles; ++tri) EXPECT_EQ(seen[tri], 1) << "triangle " << tri;
    return deepest;
}

}  // namespace vastray::test
