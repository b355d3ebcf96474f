// The chunk slot table of the streaming backend (read by wf_walk.comp), compiled both as C++
// (layout checked by static_assert) and as GLSL (scalar members and structs of them only).
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
const uint kSlotNormals = 8u;
const uint kSlotColors = 16u;
const uint kSlotUvs = 32u;
// The indices as two words a triangle: its first vertex index, then the second's and the third's
// offsets from it as 16-bit two's complement (low half, high half), each within +-32767; a long
// triangle (an offset beyond that) has kSlotLongTriangle as its second word and, as its first, where
// its three indices lie (in words from the array's start, after every triangle's two). Without
// the flag, three words a triangle (vastray::kChunkIndexDeltas16).
const uint kSlotIndexDeltas16 = 64u;
const uint kSlotLongTriangle = 0x80008000u;

// Entries of the chunk traversal's stack (Bvh4Traversal.glsl): three per level below the root
// and three for the deepest nodes' children; checked against vastray::kBvh4MaxDepth on the host.
const uint kBvh4StackSize = 75u;

// One device slot of the chunk pool, as the slot table holds it: buffer device addresses of the
// resident chunk's arrays (laid out as vastray::ChunkLayout says) and its BVH's bounds.
struct ChunkSlot {
    uint64_t nodes;  // vastray::Bvh4Node
    uint64_t positions;
    uint64_t indices;       // 3 words a triangle, or as kSlotIndexDeltas16 says
    uint64_t singleSided;   // bytes packed four to a word; valid with kSlotSingleSided
    uint64_t primitiveIds;  // valid with kSlotPrimitiveIds
    uint64_t materialIds;   // valid with kSlotMaterialIds
    uint64_t normals;       // per vertex, octahedral (core/VertexAttributes.h); valid with kSlotNormals
    uint64_t colors;        // per vertex, sRGB8; valid with kSlotColors
    uint64_t uvs;           // per vertex, 2 x f32 (u, v); valid with kSlotUvs
    uint nodeCount;
    uint flags;
    float boundsLoX, boundsLoY, boundsLoZ;
    float boundsHiX, boundsHiY, boundsHiZ;
};

// WavefrontParams::chunkSlots of a chunk that has no slot (equals vastray::kEmptyCell).
const uint kWalkNoHit = 0xFFFFFFFFu;

#ifdef __cplusplus
static_assert(sizeof(ChunkSlot) == 104 && offsetof(ChunkSlot, nodeCount) == 72 && offsetof(ChunkSlot, boundsHiZ) == 100);
}  // namespace vastray::gpu
#endif

#endif  // VASTRAY_GPU_SHARED_STREAM_TYPES_H
