// Closest hit of each ray against one resident chunk: one thread per ray, non-recursive KD-tree
// traversal with a fixed stack of kTraceStackSize entries. This mirrors
// core/src/KdTreeTraversal.cpp decision for decision (same t-margins, same early out, same tie
// rule, same node/triangle counters), so the result equals intersectKdTree bit for bit.
#version 460
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require

#include "shared/TraceTypes.h"
#include "common/Watertight.glsl"

layout(local_size_x = kTraceWorkgroupSize) in;

layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer UintArray { uint v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer FloatArray { float v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer RayArray { TraceRay v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) writeonly buffer HitArray { TraceHit v[]; };

layout(push_constant, std430) uniform PushBlock { TracePushConstants pc; };

// Same values as KdTreeTraversal.cpp's kRelativeMargin / kAbsoluteMargin.
const float kRelativeMargin = 1e-5;
const float kAbsoluteMargin = 1e-6;

struct TraversalRay {
    WatertightRay watertight;
    vec3 origin;
    vec3 direction;
    vec3 invDirection;
    float slack;  // absolute part of the margin, in units of t
};

// std::max / std::min exactly (GLSL's max/min may pick either of +0 and -0).
float cppMax(float a, float b) { return a < b ? b : a; }
float cppMin(float a, float b) { return b < a ? b : a; }

float maxAbs(vec3 v) { return cppMax(cppMax(abs(v.x), abs(v.y)), abs(v.z)); }

vec3 boundsLo() { return vec3(pc.boundsLoX, pc.boundsLoY, pc.boundsLoZ); }
vec3 boundsHi() { return vec3(pc.boundsHiX, pc.boundsHiY, pc.boundsHiZ); }

bool prepareTraversalRay(vec3 origin, vec3 direction, out TraversalRay r) {
    r.origin = origin, r.direction = direction;
    r.invDirection = vec3(0.0), r.slack = 0.0;
    if (!prepareWatertightRay(origin, direction, r.watertight)) return false;
    for (int a = 0; a < 3; ++a) r.invDirection[a] = exactDivide(1.0, direction[a]);
    const float scale = cppMax(cppMax(maxAbs(origin), maxAbs(boundsLo())), maxAbs(boundsHi()));
    precise float scaled = kAbsoluteMargin * scale;
    r.slack = exactDivide(scaled, maxAbs(direction));
    return true;
}

float margin(TraversalRay r, float t) {
    precise float relative = r.slack + kRelativeMargin * abs(t);
    return (isinf(t) || isnan(t)) ? r.slack : relative;
}

// 0 (not NaN) when the origin lies on the plane and 1/direction overflowed.
float planeDistance(TraversalRay r, int axis, float value) {
    precise float t = (value - r.origin[axis]) * r.invDirection[axis];
    return isnan(t) ? 0.0 : t;
}

bool clipToBounds(TraversalRay r, inout float tMin, inout float tMax) {
    const vec3 lo = boundsLo(), hi = boundsHi();
    if (lo.x > hi.x || lo.y > hi.y || lo.z > hi.z || !(tMin <= tMax)) return false;
    for (int a = 0; a < 3; ++a) {
        if (r.direction[a] == 0.0) {
            if (!(r.origin[a] >= lo[a] && r.origin[a] <= hi[a])) return false;
            continue;
        }
        float tNear = planeDistance(r, a, lo[a]);
        float tFar = planeDistance(r, a, hi[a]);
        if (tNear > tFar) {
            const float swap = tNear;
            tNear = tFar, tFar = swap;
        }
        precise float nearWithMargin = tNear - margin(r, tNear);
        precise float farWithMargin = tFar + margin(r, tFar);
        tMin = cppMax(tMin, nearWithMargin);
        tMax = cppMin(tMax, farWithMargin);
    }
    return tMin <= tMax;
}

uint stackNode[kTraceStackSize];
float stackT0[kTraceStackSize];
float stackT1[kTraceStackSize];

// Mirrors descend(): the child to visit now; the other one is pushed when the interval reaches it.
uint descend(TraversalRay r, uint word0, uint word1, uint index, inout float t0, inout float t1,
             inout uint stackSize) {
    const int axis = int(word1 & 3u);
    const float split = uintBitsToFloat(word0);
    const uint below = index + 1u, above = word1 >> 2;
    if (r.direction[axis] == 0.0) {
        if (r.origin[axis] != split) return r.origin[axis] < split ? below : above;
        stackNode[stackSize] = above, stackT0[stackSize] = t0, stackT1[stackSize] = t1;
        ++stackSize;
        return below;
    }
    const bool belowFirst = r.direction[axis] > 0.0;
    const uint first = belowFirst ? below : above, second = belowFirst ? above : below;
    const float tPlane = planeDistance(r, axis, split);
    const float m = margin(r, tPlane);
    precise float planeLo = tPlane - m, planeHi = tPlane + m;
    if (tPlane < t0 - m) return second;
    if (tPlane > t1 + m) return first;
    stackNode[stackSize] = second, stackT0[stackSize] = cppMax(t0, planeLo), stackT1[stackSize] = t1;
    ++stackSize;
    t1 = cppMin(t1, planeHi);
    return first;
}

// Mirrors betterHit(): closest, then front-facing, then the lower triangle index.
bool betterHit(TriangleHit h, uint triangle, bool found, TraceHit best) {
    if (!found || h.t != best.t) return !found || h.t < best.t;
    const bool bestFront = (best.flags & kHitFrontFacing) != 0u;
    if (h.frontFacing != bestFront) return h.frontFacing;
    return triangle < best.triangle;
}

vec3 vertex(uint i) {
    FloatArray p = FloatArray(pc.positions);
    return vec3(p.v[3u * i], p.v[3u * i + 1u], p.v[3u * i + 2u]);
}

bool isSingleSided(uint triangle) {
    if (pc.hasSingleSided == 0u) return false;
    const uint word = UintArray(pc.singleSided).v[triangle >> 2];
    return ((word >> (8u * (triangle & 3u))) & 0xffu) != 0u;
}

// Tests the leaf's triangles against [tMin, best so far]; updates best and found.
void intersectLeaf(TraversalRay r, uint firstRef, uint count, float tMin, float tMax, inout TraceHit best,
                   inout bool found) {
    UintArray refs = UintArray(pc.leafRefs);
    UintArray indices = UintArray(pc.indices);
    for (uint i = 0u; i < count; ++i) {
        const uint tri = refs.v[firstRef + i];
        TriangleHit h;
        ++best.trianglesTested;
        const vec3 v0 = vertex(indices.v[3u * tri]), v1 = vertex(indices.v[3u * tri + 1u]);
        const vec3 v2 = vertex(indices.v[3u * tri + 2u]);
        if (!intersectTriangle(r.watertight, v0, v1, v2, isSingleSided(tri), tMin, found ? best.t : tMax, h))
            continue;
        if (!betterHit(h, tri, found, best)) continue;
        best.t = h.t, best.u = h.u, best.v = h.v, best.triangle = tri;
        best.flags = kHitFound | (h.frontFacing ? kHitFrontFacing : 0u);
        found = true;
    }
}

// Mirrors traverse() with anyHit = false.
TraceHit traverse(vec3 origin, vec3 direction, float tMin, float tMax) {
    TraceHit best = TraceHit(0.0, 0.0, 0.0, 0u, 0u, 0u, 0u, 0u);
    TraversalRay r;
    float t0 = tMin, t1 = tMax;
    if (pc.nodeCount == 0u || !prepareTraversalRay(origin, direction, r) || !clipToBounds(r, t0, t1))
        return best;
    UintArray nodes = UintArray(pc.nodes);
    uint stackSize = 0u, index = 0u;
    bool found = false;
    for (;;) {
        // Early out: a hit before this node's entry (with margin) cannot be beaten in it.
        precise float entry = t0 - margin(r, t0);
        if (!found || !(best.t < entry)) {
            const uint word0 = nodes.v[2u * index], word1 = nodes.v[2u * index + 1u];
            ++best.nodesVisited;
            if ((word1 & 3u) != 3u) {
                index = descend(r, word0, word1, index, t0, t1, stackSize);
                continue;
            }
            intersectLeaf(r, word0, word1 >> 2, tMin, tMax, best, found);
        }
        if (stackSize == 0u) break;
        --stackSize;
        index = stackNode[stackSize], t0 = stackT0[stackSize], t1 = stackT1[stackSize];
    }
    return best;
}

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= pc.rayCount) return;
    const TraceRay ray = RayArray(pc.rays).v[i];
    const vec3 origin = vec3(ray.originX, ray.originY, ray.originZ);
    const vec3 direction = vec3(ray.directionX, ray.directionY, ray.directionZ);
    HitArray(pc.hits).v[i] = traverse(origin, direction, ray.tMin, ray.tMax);
}
