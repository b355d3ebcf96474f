// Structs that cross the host/device line for trace.comp, compiled both as C++ (with the layout
// checked by static_assert below) and as GLSL (std430 / scalar members only, so both agree).
// GLSL needs GL_EXT_shader_explicit_arithmetic_types_int64 enabled before including this.
#ifndef VASTRAY_GPU_SHARED_TRACE_TYPES_H
#define VASTRAY_GPU_SHARED_TRACE_TYPES_H

#ifdef __cplusplus
#include <cstddef>
#include <cstdint>
namespace vastray::gpu {
using uint = uint32_t;
#endif

const uint kTraceWorkgroupSize = 64u;
// Entries of the per-ray traversal stack; equals vastray::kMaxKdDepth (checked on the host).
const uint kTraceStackSize = 40u;

// TraceHit::flags bits.
const uint kHitFound = 1u;
const uint kHitFrontFacing = 2u;

// One ray; the point at parameter t is origin + t * direction, searched in [tMin, tMax].
struct TraceRay {
    float originX, originY, originZ;
    float tMin;
    float directionX, directionY, directionZ;
    float tMax;
};

// Closest hit of one ray. t, u, v and triangle are meaningful only when flags has kHitFound;
// the counters are filled for every ray (they mirror KdHit's).
struct TraceHit {
    float t;
    float u;  // barycentric weight of the triangle's second vertex
    float v;  // barycentric weight of the third vertex
    uint triangle;
    uint flags;
    uint nodesVisited;
    uint trianglesTested;
    uint padding;
};

// Push constants of trace.comp. The arrays are read through buffer device addresses (no
// descriptor sets, and no maxStorageBufferRange limit on a chunk): nodes are KdNode (2 words),
// positions are 3 floats per vertex, indices 3 per triangle, singleSided one byte per
// triangle packed four to a word (read only when hasSingleSided != 0).
struct TracePushConstants {
    uint64_t nodes;
    uint64_t leafRefs;
    uint64_t positions;
    uint64_t indices;
    uint64_t singleSided;
    uint64_t rays;
    uint64_t hits;
    uint rayCount;
    uint nodeCount;
    uint hasSingleSided;
    uint padding;
    float boundsLoX, boundsLoY, boundsLoZ;  // the chunk tree's bounds (KdTree::bounds)
    float boundsHiX, boundsHiY, boundsHiZ;
};

#ifdef __cplusplus
static_assert(sizeof(TraceRay) == 32 && offsetof(TraceRay, tMin) == 12 && offsetof(TraceRay, tMax) == 28);
static_assert(sizeof(TraceHit) == 32 && offsetof(TraceHit, flags) == 16 &&
              offsetof(TraceHit, trianglesTested) == 24);
static_assert(offsetof(TracePushConstants, hits) == 48 && offsetof(TracePushConstants, rayCount) == 56 &&
              offsetof(TracePushConstants, boundsLoX) == 72 && offsetof(TracePushConstants, boundsHiZ) == 92);
static_assert(sizeof(TracePushConstants) == 96 && sizeof(TracePushConstants) <= 128,
              "128 bytes is the push-constant size every Vulkan device guarantees");
}  // namespace vastray::gpu
#endif

#endif  // VASTRAY_GPU_SHARED_TRACE_TYPES_H
