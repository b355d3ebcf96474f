// Non-recursive KD-tree traversal (pbrt-v3 KdTreeAccel::Intersect style) with a fixed stack of
// kMaxKdDepth entries. The GPU shader mirrors this file; keep it free of recursion and of
// anything without a direct GLSL equivalent.
//
// Robustness: child intervals come from float plane distances that can be off by a few ulps,
// while triangles are tested against the caller's whole [tMin, tMax]. Every decision that skips
// a child or a node therefore keeps a small margin in t (relative + scene-scale absolute), so a
// node is skipped only when it certainly cannot hold a hit; the margin costs a few extra node
// visits near planes, never a wrong answer.
#include <algorithm>
#include <cmath>
#include <limits>

#include "vastray/core/KdTree.h"
#include "vastray/core/TriangleIntersect.h"

namespace vastray {
namespace {

constexpr float kRelativeMargin = 1e-5f;  // ~80 ulps of the plane distance
constexpr float kAbsoluteMargin = 1e-6f;  // times scene scale / |largest direction component|

struct StackEntry {
    uint32_t node;
    float tMin;
    float tMax;
};

struct TraversalRay {
    WatertightRay watertight;
    float origin[3];
    float direction[3];
    float invDirection[3];
    float slack;  // absolute part of the margin, in units of t
};

float maxAbs(const Vec3f& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

bool prepareTraversalRay(const Aabb& bounds, const Ray& ray, TraversalRay* out) {
    if (!prepareWatertightRay(ray, &out->watertight)) return false;
    for (int a = 0; a < 3; ++a) {
        out->origin[a] = ray.origin[a];
        out->direction[a] = ray.direction[a];
        out->invDirection[a] = 1.0f / ray.direction[a];  // +-inf for a zero component: never used then
    }
    const float scale = std::max({maxAbs(ray.origin), maxAbs(bounds.lo), maxAbs(bounds.hi)});
    out->slack = kAbsoluteMargin * scale / maxAbs(ray.direction);
    return true;
}

float margin(const TraversalRay& r, float t) {
    return std::isfinite(t) ? r.slack + kRelativeMargin * std::abs(t) : r.slack;
}

// Distance along the ray to the plane x[axis] = value; 0 (not NaN) when the origin lies on it
// and the direction component is so small that its reciprocal overflowed.
float planeDistance(const TraversalRay& r, int axis, float value) {
    const float t = (value - r.origin[axis]) * r.invDirection[axis];
    return t == t ? t : 0.0f;
}

// Slab test against the tree bounds, closed boxes; a zero direction component is handled
// explicitly so 0 * inf never enters the interval.
bool clipToBounds(const Aabb& bounds, const TraversalRay& r, float* tMin, float* tMax) {
    if (bounds.isEmpty() || !(*tMin <= *tMax)) return false;
    for (int a = 0; a < 3; ++a) {
        if (r.direction[a] == 0.0f) {
            if (!(r.origin[a] >= bounds.lo[a] && r.origin[a] <= bounds.hi[a])) return false;
            continue;
        }
        float tNear = planeDistance(r, a, bounds.lo[a]);
        float tFar = planeDistance(r, a, bounds.hi[a]);
        if (tNear > tFar) std::swap(tNear, tFar);
        *tMin = std::max(*tMin, tNear - margin(r, tNear));
        *tMax = std::min(*tMax, tFar + margin(r, tFar));
    }
    return *tMin <= *tMax;
}

// Closest hit so far with the order-independent tie rule.
bool betterHit(const TriangleHit& h, uint32_t triangle, bool found, const KdHit& best) {
    if (!found || h.t != best.t) return !found || h.t < best.t;
    if (h.frontFacing != best.frontFacing) return h.frontFacing;
    return triangle < best.triangle;
}

// Steps from an interior node to the child to visit now, pushing the other one when the ray
// interval reaches both. [t0, t1] is updated to the interval of the child returned.
uint32_t descend(const TraversalRay& r, const KdNode& node, uint32_t index, float* t0, float* t1,
                 StackEntry* stack, uint32_t* stackSize) {
    const int axis = int(node.axis());
    const float split = node.split();
    const uint32_t below = index + 1, above = node.aboveChild();
    if (r.direction[axis] == 0.0f) {  // parallel to the plane: the origin's side, or both if on it
        if (r.origin[axis] != split) return r.origin[axis] < split ? below : above;
        stack[(*stackSize)++] = {above, *t0, *t1};
        return below;
    }
    const bool belowFirst = r.direction[axis] > 0.0f;
    const uint32_t first = belowFirst ? below : above, second = belowFirst ? above : below;
    const float tPlane = planeDistance(r, axis, split);
    const float m = margin(r, tPlane);
    if (tPlane < *t0 - m) return second;
    if (tPlane > *t1 + m) return first;
    stack[(*stackSize)++] = {second, std::max(*t0, tPlane - m), *t1};
    *t1 = std::min(*t1, tPlane + m);
    return first;
}

// Shared loop of intersect and occluded. anyHit: stop at the first hit in range.
bool traverse(const KdTree& tree, const Vec3f* positions, const uint32_t* indices, const uint8_t* singleSided,
              const Ray& ray, float tMin, float tMax, bool anyHit, KdHit* best) {
    best->nodesVisited = best->trianglesTested = 0;
    TraversalRay r;
    float t0 = tMin, t1 = tMax;
    if (tree.nodes.empty() || !prepareTraversalRay(tree.bounds, ray, &r) || !clipToBounds(tree.bounds, r, &t0, &t1))
        return false;
    StackEntry stack[kMaxKdDepth];
    uint32_t stackSize = 0;
    uint32_t index = 0;
    bool found = false;
    for (;;) {
        // Early out: a hit before this node's entry (with margin) cannot be beaten in it.
        if (!found || !(best->t < t0 - margin(r, t0))) {
            const KdNode node = tree.nodes[index];
            ++best->nodesVisited;
            if (!node.isLeaf()) {
                index = descend(r, node, index, &t0, &t1, stack, &stackSize);
                continue;
            }
            const uint32_t* refs = tree.leafRefs.data() + node.firstRef();
            for (uint32_t i = 0, n = node.primitiveCount(); i < n; ++i) {
                const uint32_t tri = refs[i];
                const uint32_t* v = indices + 3 * size_t(tri);
                const bool cull = singleSided && singleSided[tri];
                TriangleHit h;
                ++best->trianglesTested;
                if (!intersectTriangle(r.watertight, positions[v[0]], positions[v[1]], positions[v[2]], cull,
                                       tMin, found ? best->t : tMax, &h))
                    continue;
                if (!betterHit(h, tri, found, *best)) continue;
                best->t = h.t, best->u = h.u, best->v = h.v, best->frontFacing = h.frontFacing;
                best->triangle = tri;
                found = true;
                if (anyHit) return true;
            }
        }
        if (stackSize == 0) break;
        const StackEntry e = stack[--stackSize];
        index = e.node, t0 = e.tMin, t1 = e.tMax;
    }
    return found;
}

}  // namespace

bool intersectKdTree(const KdTree& tree, const Vec3f* positions, const uint32_t* indices,
                     const uint8_t* singleSided, const Ray& ray, float tMin, float tMax, KdHit* hit) {
    return traverse(tree, positions, indices, singleSided, ray, tMin, tMax, false, hit);
}

bool occludedKdTree(const KdTree& tree, const Vec3f* positions, const uint32_t* indices,
                    const uint8_t* singleSided, const Ray& ray, float tMin, float tMax, KdHit* counters) {
    KdHit hit;
    return traverse(tree, positions, indices, singleSided, ray, tMin, tMax, true, counters ? counters : &hit);
}

void kdLeavesAlongRay(std::span<const KdNode> nodes, const Aabb& bounds, const Ray& ray, float tMin, float tMax,
                      std::vector<KdLeafVisit>* out) {
    out->clear();
    TraversalRay r;
    float t0 = tMin, t1 = tMax;
    if (nodes.empty() || !prepareTraversalRay(bounds, ray, &r) || !clipToBounds(bounds, r, &t0, &t1)) return;
    StackEntry stack[kMaxKdDepth];
    uint32_t stackSize = 0;
    uint32_t index = 0;
    for (;;) {
        const KdNode node = nodes[index];
        if (!node.isLeaf()) {
            index = descend(r, node, index, &t0, &t1, stack, &stackSize);
            continue;
        }
        out->push_back({index, t0 - margin(r, t0), t1 + margin(r, t1)});
        if (stackSize == 0) break;
        const StackEntry e = stack[--stackSize];
        index = e.node, t0 = e.tMin, t1 = e.tMax;
    }
}

}  // namespace vastray
