// The slot table as wf_walk.comp reads it: a resident chunk's arrays as a ChunkView (nodes are
// Bvh4Node; there are no leaf references). Included after shared/StreamTypes.h and
// common/KdTraversal.glsl.
#ifndef VASTRAY_SLOT_TABLE_GLSL
#define VASTRAY_SLOT_TABLE_GLSL

layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer SlotTable { ChunkSlot v[]; };

ChunkView chunkView(ChunkSlot s) {
    return ChunkView(s.nodes, 0ul, s.positions, s.indices, s.singleSided, s.nodeCount,
                     (s.flags & kSlotSingleSided) != 0u, (s.flags & kSlotIndexDeltas16) != 0u,
                     vec3(s.boundsLoX, s.boundsLoY, s.boundsLoZ),
                     vec3(s.boundsHiX, s.boundsHiY, s.boundsHiZ));
}

#endif  // VASTRAY_SLOT_TABLE_GLSL
