// Structs that cross the host/device line for stream_trace.comp and stream_walk.comp (the
// streaming backend), compiled both as C++ (layout checked by static_assert) and as GLSL
// (scalar members and structs of them only).
// GLSL needs GL_EXT_shader_explicit_arithmetic_types_int64 enabled before including this.
#ifndef VASTRAY_GPU_SHARED_STREAM_TYPES_H
#define VASTRAY_GPU_SHARED_STREAM_TYPES_H

#ifdef __cplusplus
#include <cstddef>
#include <cstdint>
namespace vastray::gpu {
using uint = uint32_t;
#endif

// ChunkSlot::flags bits: which optional arrays the slot holds.
const uint kSlotSingleSided = 1u;
const uint kSlotPrimitiveIds = 2u;
const uint kSlotMaterialIds = 4u;

// One device slot of the chunk pool, as the slot table holds it: buffer device addresses of the
// resident chunk's arrays (laid out as vastray::ChunkLayout says) and its tree's bounds.
struct ChunkSlot {
    uint64_t nodes;
    uint64_t leafRefs;
    uint64_t positions;
    uint64_t indices;
    uint64_t singleSided;   // bytes packed four to a word; valid with kSlotSingleSided
    uint64_t primitiveIds;  // valid with kSlotPrimitiveIds
    uint64_t materialIds;   // valid with kSlotMaterialIds
    uint nodeCount;
    uint flags;
    float boundsLoX, boundsLoY, boundsLoZ;
    float boundsHiX, boundsHiY, boundsHiZ;
};

// A ray (vastray::StreamRay) and its result (vastray::StreamHit), byte for byte.
struct StreamRayGpu {
    float originX, originY, originZ;
    float tMin;
    float directionX, directionY, directionZ;
    float tMax;
};
struct StreamHitGpu {
    float t;
    float positionX, positionY, positionZ;
    float normalX, normalY, normalZ;
    uint primitive;
    uint material;
    uint flags;  // kHitFound | kHitFrontFacing (TraceTypes.h), equal to kStreamHitFound/FrontFacing
    uint nodesVisited;
    uint trianglesTested;
};

// Push constants of stream_trace.comp: rays [0, rayCount) of the batch against slot `slot`.
struct StreamPushConstants {
    uint64_t slotTable;
    uint64_t rays;
    uint64_t hits;
    uint slot;
    uint rayCount;
    uint anyHit;
    uint padding;
};

// stream_walk.comp: whole rays through the top-level tree and the resident chunks of its cells.
// Its per-ray record: the hit as the queued path's merge leaves it (the winning cell's trace),
// then the walk's own figures. chunk: the hit's chunk, kWalkNoHit without a hit, or
// kWalkIncomplete when a cell the ray needed was not resident (the host then traces that ray
// the queued way, and the record's other fields mean nothing). Laid out as vastray's StreamResult.
const uint kWalkNoHit = 0xFFFFFFFFu;
const uint kWalkIncomplete = 0xFFFFFFFEu;
struct StreamWalkGpu {
    StreamHitGpu hit;
    uint chunk;
    uint cellsTraced;      // cells traced (not pruned by a nearer hit)
    uint trianglesTested;  // over every cell traced
    uint cell;             // the hit's cell: index among the ray's non-empty cells, front to back
};

// Push constants of stream_walk.comp: rays [0, rayCount), all closest-hit or all any-hit.
// topNodes: the package's top-level tree (KdNode, 2 words; a leaf's first word is its chunk);
// chunkSlots: per chunk, its slot or kWalkNoHit when not resident; touched: per chunk, set to 1
// when a ray traced one of its cells.
struct StreamWalkPushConstants {
    uint64_t slotTable;
    uint64_t rays;
    uint64_t results;
    uint64_t topNodes;
    uint64_t chunkSlots;
    uint64_t touched;
    uint rayCount;
    uint anyHit;
    uint topNodeCount;
    uint chunkCount;
    float boundsLoX, boundsLoY, boundsLoZ;  // the package bounds (PackageInfo::bounds)
    float boundsHiX, boundsHiY, boundsHiZ;
    uint padding0, padding1;
};

#ifdef __cplusplus
static_assert(sizeof(StreamWalkGpu) == 64 && offsetof(StreamWalkGpu, chunk) == 48);
static_assert(sizeof(StreamWalkPushConstants) == 96 && offsetof(StreamWalkPushConstants, rayCount) == 48 &&
              offsetof(StreamWalkPushConstants, boundsLoX) == 64);
static_assert(sizeof(ChunkSlot) == 88 && offsetof(ChunkSlot, nodeCount) == 56 && offsetof(ChunkSlot, boundsHiZ) == 84);
static_assert(sizeof(StreamRayGpu) == 32 && sizeof(StreamHitGpu) == 48 && offsetof(StreamHitGpu, flags) == 36);
static_assert(sizeof(StreamPushConstants) == 40 && offsetof(StreamPushConstants, slot) == 24);
}  // namespace vastray::gpu
#endif

#endif  // VASTRAY_GPU_SHARED_STREAM_TYPES_H
