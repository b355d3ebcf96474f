// Non-recursive KD-tree traversal of one chunk with a fixed stack of kTraceStackSize entries.
// This mirrors core/src/KdTreeTraversal.cpp decision for decision (same t-margins, same early
// out, same tie rule, same node/triangle counters), so the result equals intersectKdTree (and,
// with anyHit, occludedKdTree) bit for bit. Included by trace.comp, stream_trace.comp and
// stream_walk.comp.
// Needs GL_EXT_buffer_reference and GL_EXT_shader_explicit_arithmetic_types_int64, and
// shared/TraceTypes.h (TraceHit, kTraceStackSize, flag bits) and shared/StreamTypes.h
// (kSlotLongTriangle) before it.
#ifndef VASTRAY_KD_TRAVERSAL_GLSL
#define VASTRAY_KD_TRAVERSAL_GLSL

#include "common/Watertight.glsl"

layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer UintArray { uint v[]; };
layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer UVec2Words { uvec2 v[]; };
#ifndef VASTRAY_FLOAT_ARRAY  // common/WavefrontState.glsl declares it for the wavefront kernels
#define VASTRAY_FLOAT_ARRAY
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer FloatArray { float v[]; };
#endif

// Same values as KdTreeTraversal.cpp's kRelativeMargin / kAbsoluteMargin.
const float kRelativeMargin = 1e-5;
const float kAbsoluteMargin = 1e-6;

// The arrays of one resident chunk (buffer device addresses) and its tree's bounds.
struct ChunkView {
    uint64_t nodes, leafRefs, positions, indices, singleSided;
    uint nodeCount;
    bool hasSingleSided;
    bool indexDeltas16;  // indices as kSlotIndexDeltas16 says (shared/StreamTypes.h): 2 words a triangle
    vec3 lo, hi;
};

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

// The part of prepareTraversalRay that does not depend on the chunk (the watertight shear and
// 1/direction): computed once per ray, however many chunks the ray visits.
bool prepareRayConstants(vec3 origin, vec3 direction, out TraversalRay r) {
    r.origin = origin, r.direction = direction;
    r.invDirection = vec3(0.0), r.slack = 0.0;
    if (!prepareWatertightRay(origin, direction, r.watertight)) return false;
    for (int a = 0; a < 3; ++a) r.invDirection[a] = 1.0 / direction[a];
    return true;
}

// The part that does: the absolute margin, from the largest coordinate of the origin and the
// chunk's bounds.
void setChunkSlack(ChunkView c, inout TraversalRay r) {
    const float scale = cppMax(cppMax(maxAbs(r.origin), maxAbs(c.lo)), maxAbs(c.hi));
    precise float scaled = kAbsoluteMargin * scale;
    r.slack = scaled / maxAbs(r.direction);
}

bool prepareTraversalRay(ChunkView c, vec3 origin, vec3 direction, out TraversalRay r) {
    if (!prepareRayConstants(origin, direction, r)) return false;
    setChunkSlack(c, r);
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

bool clipToBounds(ChunkView c, TraversalRay r, inout float tMin, inout float tMax) {
    const vec3 lo = c.lo, hi = c.hi;
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

// The traversal stack. A shader that nests traversals (stream_walk.comp: the top-level tree,
// and a chunk's tree inside one of its leaves) defines VASTRAY_STACK_ENTRIES as the sum of
// their depths before including this file; traverse() then works above a stack base.
#ifndef VASTRAY_STACK_ENTRIES
#define VASTRAY_STACK_ENTRIES kTraceStackSize
#endif
uint stackNode[VASTRAY_STACK_ENTRIES];
float stackT0[VASTRAY_STACK_ENTRIES];
float stackT1[VASTRAY_STACK_ENTRIES];

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

// Vertex i of the chunk: 3 floats, or in a kernel that defines VASTRAY_PACKED_POSITIONS (with its
// kPackedPositions constant and the grid in pc: wf_walk.comp) 8 bytes, the vertex's grid
// coordinates from the origin, 21 bits an axis (vastray::QuantizationGrid::packedPosition): the
// product is exact (a power-of-two step) and the sum rounds once, so the floats are those the
// host decoded (docs/GEOMETRY.md).
vec3 vertex(ChunkView c, uint i) {
#ifdef VASTRAY_PACKED_POSITIONS
    if (kPackedPositions) {
        const uvec2 w = UVec2Words(c.positions).v[i];
        const uvec3 m = uvec3(w.x & 0x1FFFFFu, (w.x >> 21) | ((w.y & 0x3FFu) << 11), w.y >> 10);
        precise vec3 v = vec3(pc.gridOriginX, pc.gridOriginY, pc.gridOriginZ) + vec3(m) * pc.gridStep;
        return v;
    }
#endif
    FloatArray p = FloatArray(c.positions);
    return vec3(p.v[3u * i], p.v[3u * i + 1u], p.v[3u * i + 2u]);
}

// The triangle's three vertex indices: three words, or with indexDeltas16 the first index and
// the other two's 16-bit offsets from it in one 8-byte read (a long triangle's three words where
// its first word says: kSlotLongTriangle, shared/StreamTypes.h).
uvec3 triangleVertices(ChunkView c, uint tri) {
    UintArray indices = UintArray(c.indices);
    uint at = 3u * tri;
    if (c.indexDeltas16) {
        const uvec2 w = UVec2Words(c.indices).v[tri];
        if (w.y != kSlotLongTriangle)
            return uvec3(w.x, w.x + uint(bitfieldExtract(int(w.y), 0, 16)), w.x + uint(int(w.y) >> 16));
        at = w.x;
    }
    return uvec3(indices.v[at], indices.v[at + 1u], indices.v[at + 2u]);
}

bool isSingleSided(ChunkView c, uint triangle) {
    if (!c.hasSingleSided) return false;
    const uint word = UintArray(c.singleSided).v[triangle >> 2];
    return ((word >> (8u * (triangle & 3u))) & 0xffu) != 0u;
}

// The triangle's vertex indices, smallest first: a key for ties that does not depend on where
// the triangle sits in the chunk's arrays (only on the decoded vertices).
uvec3 sortedVertices(uvec3 i) {
    const uint lo = min(i.x, min(i.y, i.z)), hi = max(i.x, max(i.y, i.z));
    return uvec3(lo, i.x + i.y + i.z - lo - hi, hi);
}

bool lessVertices(uvec3 a, uvec3 b) { return a.x != b.x ? a.x < b.x : (a.y != b.y ? a.y < b.y : a.z < b.z); }

// Tests one triangle against [tMin, best so far]; true when it becomes the best hit. Ties in t
// and facing go to the lower triangle index, or with tieByVertices (BVH chunks, whose triangle
// order depends on how the tree was built) to the lower sorted vertex indices.
bool testTriangle(ChunkView c, TraversalRay r, uint tri, float tMin, float tMax, bool tieByVertices,
                  inout TraceHit best, inout bool found) {
    TriangleHit h;
    ++best.trianglesTested;
    const uvec3 i = triangleVertices(c, tri);
    const vec3 v0 = vertex(c, i.x), v1 = vertex(c, i.y), v2 = vertex(c, i.z);
    if (!intersectTriangle(r.watertight, v0, v1, v2, isSingleSided(c, tri), tMin, found ? best.t : tMax, h))
        return false;
    if (tieByVertices && found && h.t == best.t && h.frontFacing == ((best.flags & kHitFrontFacing) != 0u)) {
        const uint b = best.triangle;
        if (!lessVertices(sortedVertices(i), sortedVertices(triangleVertices(c, b)))) return false;
    } else if (!betterHit(h, tri, found, best)) {
        return false;
    }
#ifdef VASTRAY_CUTOUTS
    if (cutAway(tri, i, h.u, h.v)) return false;  // a cut-out's hole (the including kernel's test)
#endif
    best.t = h.t, best.u = h.u, best.v = h.v, best.triangle = tri;
    best.flags = kHitFound | (h.frontFacing ? kHitFrontFacing : 0u);
    found = true;
    return true;
}

// Tests the leaf's triangles against [tMin, best so far]; updates best and found.
void intersectLeaf(ChunkView c, TraversalRay r, uint firstRef, uint count, float tMin, float tMax, bool anyHit,
                   inout TraceHit best, inout bool found) {
    UintArray refs = UintArray(c.leafRefs);
    for (uint i = 0u; i < count; ++i)
        if (testTriangle(c, r, refs.v[firstRef + i], tMin, tMax, false, best, found) && anyHit) return;
}

// Mirrors traverse(): the closest hit, or with anyHit the first one found, for a ray whose
// chunk-independent constants are prepared (prepareRayConstants). The stack entries below
// stackBase belong to the caller and are left alone.
// A chunk traversal's start: the ray with the chunk's margin, and [tMin, tMax] clipped to the
// chunk's bounds in t0, t1. False when the chunk is empty or the ray misses its bounds.
bool enterChunk(ChunkView c, TraversalRay ray, float tMin, float tMax, out TraversalRay r, out float t0, out float t1) {
    r = ray, t0 = tMin, t1 = tMax;
    if (c.nodeCount == 0u) return false;
    setChunkSlack(c, r);
    return clipToBounds(c, r, t0, t1);
}

TraceHit traverseRay(ChunkView c, TraversalRay ray, float tMin, float tMax, bool anyHit, uint stackBase) {
    TraceHit best = TraceHit(0.0, 0.0, 0.0, 0u, 0u, 0u, 0u, 0u);
    TraversalRay r;
    float t0, t1;
    if (!enterChunk(c, ray, tMin, tMax, r, t0, t1)) return best;
    UintArray nodes = UintArray(c.nodes);
    uint stackSize = stackBase, index = 0u;
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
            intersectLeaf(c, r, word0, word1 >> 2, tMin, tMax, anyHit, best, found);
            if (anyHit && found) break;
        }
        if (stackSize == stackBase) break;
        --stackSize;
        index = stackNode[stackSize], t0 = stackT0[stackSize], t1 = stackT1[stackSize];
    }
    return best;
}

// Mirrors traverse() for one ray and one chunk (trace.comp).
TraceHit traverse(ChunkView c, vec3 origin, vec3 direction, float tMin, float tMax, bool anyHit, uint stackBase) {
    TraversalRay r;
    if (!prepareRayConstants(origin, direction, r)) return TraceHit(0.0, 0.0, 0.0, 0u, 0u, 0u, 0u, 0u);
    return traverseRay(c, r, tMin, tMax, anyHit, stackBase);
}

#endif  // VASTRAY_KD_TRAVERSAL_GLSL
