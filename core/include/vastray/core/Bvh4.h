#pragma once
// Per-chunk bounding volume hierarchy: four children per node, child boxes quantized to 8 bits
// in the node's frame (Ylitie, Karras and Laine 2017, "Efficient incoherent ray traversal on
// GPUs through compressed wide BVHs", narrowed to four children), 56-byte nodes in depth-first
// order, and triangles reordered so that every leaf is a contiguous range (no reference array).
// Built at import (binned SAH), stored in the package, traversed by
// gpu/shaders/common/Bvh4Traversal.glsl. docs/GEOMETRY.md has the format and why it replaced
// the chunk KD-tree.
#include <cstdint>
#include <string>
#include <vector>

#include "vastray/core/Aabb.h"
#include "vastray/core/Vec3.h"

namespace vastray {

// Deepest 4-wide node below the root (root = 0); the traversal's stack holds three entries per
// level, so this bounds the kernel's private memory. The builder guarantees it by construction.
inline constexpr uint32_t kBvh4MaxDepth = 24;
inline constexpr uint32_t kBvh4MaxLeafTriangles = 16;
inline constexpr uint32_t kBvh4MaxTriangles = 1u << 27;  // leaf words hold 27 bits of triangle index
inline constexpr uint32_t kBvh4EmptyChild = 0xFFFFFFFFu;
inline constexpr uint32_t kBvh4LeafBit = 0x80000000u;

// child[i]: kBvh4EmptyChild; an interior node's index (always above this node's); or a leaf,
// kBvh4LeafBit | (count - 1) << 27 | first triangle.
// Child i's box on axis a is [origin[a] + qlo * 2^e, origin[a] + qhi * 2^e] with
// qlo = byte i of qlo[a], qhi = byte i of qhi[a] and e = byte a of exponents - 127: the products
// are exact in fp32 and the box encloses the child's triangles up to the rounding of one sum,
// which the traversal's margins cover.
struct Bvh4Node {
    float origin[3];
    uint32_t exponents;
    uint32_t qlo[3];
    uint32_t qhi[3];
    uint32_t child[4];
};
static_assert(sizeof(Bvh4Node) == 56, "Bvh4Node is shared with the GPU shader and the package format");

inline uint32_t bvh4LeafWord(uint32_t first, uint32_t count) {
    return kBvh4LeafBit | ((count - 1) << 27) | first;
}
inline bool bvh4IsLeaf(uint32_t word) { return word != kBvh4EmptyChild && (word & kBvh4LeafBit) != 0; }
inline uint32_t bvh4LeafFirst(uint32_t word) { return word & ((1u << 27) - 1); }
inline uint32_t bvh4LeafCount(uint32_t word) { return ((word >> 27) & 15u) + 1; }

struct Bvh4 {
    Aabb bounds;                  // of the triangles, world space
    std::vector<Bvh4Node> nodes;  // root at 0; empty when there are no triangles
    std::vector<uint32_t> order;  // order[i]: the input triangle stored at position i
    uint32_t maxDepth = 0;        // deepest node (root = 0), <= kBvh4MaxDepth
};

// SAH cost model of the binary tree the 4-wide one is collapsed from: a node of n triangles
// stays a leaf when n <= maxLeafSize and intersectionCost * n is not above the best split's
// traversalCost + intersectionCost * (A_left n_left + A_right n_right) / A.
struct Bvh4BuildOptions {
    float traversalCost = 1.0f;
    float intersectionCost = 1.0f;
    uint32_t maxLeafSize = 4;  // clamped to [1, kBvh4MaxLeafTriangles]
    uint32_t bins = 16;        // SAH bins per axis, clamped to [4, 64]
};

// positions/indices: the chunk's triangles (3 indices per triangle, finite positions).
// Deterministic: the same input always gives the same nodes and order. triangleCount must not
// exceed kBvh4MaxTriangles.
Bvh4 buildBvh4(const Vec3f* positions, const uint32_t* indices, uint32_t triangleCount,
               const Bvh4BuildOptions& options = {});

// The box of child `i` of a node, as the kernel computes it (fp32, origin + q * 2^e).
Aabb bvh4ChildBox(const Bvh4Node& node, int i);

// Checks a tree read from a file before a device trusts it: child indices above their parent
// and below nodes.size(), leaves inside [0, triangleCount), depth <= kBvh4MaxDepth, exponent
// bytes in [1, 254], finite origins. Empty when valid, otherwise what is wrong and where.
std::string validateBvh4Nodes(const std::vector<Bvh4Node>& nodes, uint32_t triangleCount);

}  // namespace vastray
