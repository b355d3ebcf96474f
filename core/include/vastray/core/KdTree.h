#pragma once
// Per-chunk KD-tree: SAH builder, compact 8-byte nodes in depth-first order, and a
// non-recursive traversal with a fixed-size stack that the GPU shader mirrors exactly.
#include <bit>
#include <cstdint>
#include <span>
#include <vector>

#include "vastray/core/Aabb.h"
#include "vastray/core/Ray.h"
#include "vastray/core/Vec3.h"

namespace vastray {

// Hard cap on tree depth; also the number of entries of the traversal stack.
inline constexpr uint32_t kMaxKdDepth = 40;

// interior: word0 = bits of the float split position,
//           word1 = (aboveChild << 2) | axis; the below child is the next node.
// leaf:     word0 = index of its first entry in KdTree::leafRefs,
//           word1 = (primitiveCount << 2) | 3.
struct KdNode {
    uint32_t word0;
    uint32_t word1;

    bool isLeaf() const { return (word1 & 3u) == 3u; }
    uint32_t axis() const { return word1 & 3u; }
    float split() const { return std::bit_cast<float>(word0); }
    uint32_t aboveChild() const { return word1 >> 2; }
    uint32_t primitiveCount() const { return word1 >> 2; }
    uint32_t firstRef() const { return word0; }

    static KdNode interior(uint32_t axis, float split, uint32_t aboveChild) {
        return {std::bit_cast<uint32_t>(split), (aboveChild << 2) | axis};
    }
    static KdNode leaf(uint32_t firstRef, uint32_t count) { return {firstRef, (count << 2) | 3u}; }
};
static_assert(sizeof(KdNode) == 8, "KdNode is shared with the GPU shader and the package format");

struct KdTree {
    Aabb bounds;                     // bounds of the triangles, world space
    std::vector<KdNode> nodes;       // root at 0; empty when there are no triangles
    std::vector<uint32_t> leafRefs;  // triangle indices into the chunk's triangle arrays
    uint32_t maxDepth = 0;           // deepest leaf reached (root = 0), <= kMaxKdDepth
};

// SAH cost model: cost(split) = traversalCost + intersectionCost * (pBelow*nBelow + pAbove*nAbove)
// * (1 - emptyBonus if one side is empty); a node stays a leaf when that is not below
// intersectionCost * n. The defaults were picked with bench/kd_build_bench: against
// intersectionCost 1.5 they cut references per triangle from ~10 to ~4.5 on a sphere and build
// 2-3x faster, at equal rays/s.
struct KdBuildOptions {
    float traversalCost = 1.0f;
    float intersectionCost = 0.75f;
    float emptyBonus = 0.2f;    // in [0, 1): reward for cutting off empty space
    uint32_t maxLeafSize = 2;   // a node with this many references or fewer is a leaf
    uint32_t bins = 32;         // SAH bins per axis, clamped to [4, 64]
    uint32_t maxDepth = 0;      // 0: min(8 + 1.3 * log2(N), kMaxKdDepth); otherwise clamped to kMaxKdDepth
};

// The options scene packages use for chunk trees: depth capped at log2(N) + 3 and leaves of
// up to 4 triangles keep a chunk near 32 resident bytes per triangle (pbrt's 8 + 1.3·log2 N
// depth rule gives about 50; docs/PERF_NOTES.md).
KdBuildOptions compactKdBuildOptions(uint32_t triangleCount);

// positions/indices: the chunk's triangles (3 indices per triangle). Deterministic: the same
// input always gives identical nodes and references. Triangles are assumed finite (the
// importer rejects NaN/Inf); degenerate triangles are kept and simply never hit.
KdTree buildKdTree(const Vec3f* positions, const uint32_t* indices, uint32_t triangleCount,
                   const KdBuildOptions& options = {});

// The same tree with every interior node at depth maxDepth (root = 0) made a leaf that holds
// each triangle of the leaves below it once, in ascending order. Hits do not change (the tie
// rule does not depend on the tree); fewer nodes and references, more triangle tests per ray.
// Deterministic; depth-first order as buildKdTree writes it.
KdTree truncateKdTree(const KdTree& tree, uint32_t maxDepth);

struct KdHit {
    float t = 0;
    float u = 0;  // barycentric weight of the triangle's second vertex
    float v = 0;  // barycentric weight of the third vertex
    uint32_t triangle = 0;
    bool frontFacing = false;
    uint32_t nodesVisited = 0;     // counters filled by every call, hit or not
    uint32_t trianglesTested = 0;
};

// Closest hit with tMin <= t <= tMax. Ties at exactly the same t: front-facing beats
// back-facing, then the lower triangle index, so the result never depends on traversal order.
// singleSided: one byte per triangle (nonzero: invisible from behind), or null for all
// double-sided. hit may not be null. Returns false for a zero or non-finite ray.
bool intersectKdTree(const KdTree& tree, const Vec3f* positions, const uint32_t* indices,
                     const uint8_t* singleSided, const Ray& ray, float tMin, float tMax, KdHit* hit);

// Any hit with tMin <= t <= tMax (shadow rays); stops at the first one found.
// counters, when given, receives nodesVisited and trianglesTested.
bool occludedKdTree(const KdTree& tree, const Vec3f* positions, const uint32_t* indices,
                    const uint8_t* singleSided, const Ray& ray, float tMin, float tMax, KdHit* counters = nullptr);

// A leaf the ray reaches, with the ray's interval inside it widened by the traversal margin
// on both ends (so consecutive leaves' intervals overlap and leave no gap).
struct KdLeafVisit {
    uint32_t node;  // index of the leaf in the node array
    float t0, t1;
};

// Every leaf of a tree (nodes + the bounds its root splits) that [tMin, tMax] of the ray
// reaches, front to back up to the margins, with the same decisions as intersectKdTree. The
// scene package's top-level tree is walked with this; `out` is cleared first. A ray with a
// zero direction or one that misses the bounds reaches no leaf.
void kdLeavesAlongRay(std::span<const KdNode> nodes, const Aabb& bounds, const Ray& ray, float tMin, float tMax,
                      std::vector<KdLeafVisit>* out);

struct KdTreeStats {
    uint64_t nodes = 0;
    uint64_t leaves = 0;
    uint64_t emptyLeaves = 0;
    uint64_t references = 0;
    uint32_t maxDepth = 0;
    double meanLeafSize = 0;  // references per non-empty leaf
};
KdTreeStats computeKdTreeStats(const KdTree& tree);

}  // namespace vastray
