// Whole rays through a scene whose chunks are resident: each thread walks its ray's cells in
// the top-level tree front to back (core's kdLeavesAlongRay, decision for decision) and traces
// each cell's chunk as the queued path would (RayStreamer, in order): the same clipped
// intervals, the same pruning by a nearer hit, the same merge order (t, front before back,
// earlier cell). So a ray's record equals what the host's walk, queues and merges make of it,
// bit for bit, without a round trip per cell. A ray that needs a chunk that is not resident
// stops with kWalkIncomplete and is left to the queued path.
#version 460
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require

#include "shared/TraceTypes.h"
#include "shared/StreamTypes.h"
// The top-level walk keeps its pending nodes below the chunk traversal's.
#define VASTRAY_STACK_ENTRIES (2u * kTraceStackSize)
#include "common/KdTraversal.glsl"
#include "common/StreamHit.glsl"

layout(local_size_x = kTraceWorkgroupSize) in;

layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer RayArray { StreamRayGpu v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) writeonly buffer WalkArray { StreamWalkGpu v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) writeonly buffer FlagArray { uint v[]; };

layout(push_constant, std430) uniform PushBlock { StreamWalkPushConstants pc; };

// RayStreamer's replaces(): nearer, then front before back, then the earlier cell.
bool replaces(TraceHit h, uint cell, bool found, TraceHit best, uint bestCell) {
    if ((h.flags & kHitFound) == 0u) return false;
    if (!found || h.t < best.t) return true;
    if (h.t != best.t) return false;
    const bool front = (h.flags & kHitFrontFacing) != 0u, bestFront = (best.flags & kHitFrontFacing) != 0u;
    if (front != bestFront) return front;
    return cell < bestCell;
}

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= pc.rayCount) return;
    const bool anyHit = pc.anyHit != 0u;
    const StreamRayGpu ray = RayArray(pc.rays).v[i];
    const vec3 origin = vec3(ray.originX, ray.originY, ray.originZ);
    const vec3 direction = vec3(ray.directionX, ray.directionY, ray.directionZ);
    const ChunkView top = ChunkView(0ul, 0ul, 0ul, 0ul, 0ul, pc.topNodeCount, false,
                                    vec3(pc.boundsLoX, pc.boundsLoY, pc.boundsLoZ),
                                    vec3(pc.boundsHiX, pc.boundsHiY, pc.boundsHiZ));
    UintArray topNodes = UintArray(pc.topNodes);
    UintArray chunkSlots = UintArray(pc.chunkSlots);
    SlotTable slots = SlotTable(pc.slotTable);

    TraceHit best = TraceHit(0.0, 0.0, 0.0, 0u, 0u, 0u, 0u, 0u);
    bool found = false, complete = true;
    uint bestChunk = kWalkNoHit, bestSlot = 0u, bestCell = 0u, cell = 0u, cellsTraced = 0u, triangles = 0u;
    TraversalRay r;
    float t0 = ray.tMin, t1 = ray.tMax;
    if (pc.topNodeCount != 0u && prepareTraversalRay(top, origin, direction, r) && clipToBounds(top, r, t0, t1)) {
        uint stackSize = 0u, index = 0u;
        for (;;) {
            const uint word0 = topNodes.v[2u * index], word1 = topNodes.v[2u * index + 1u];
            if ((word1 & 3u) != 3u) {
                index = descend(r, word0, word1, index, t0, t1, stackSize);
                continue;
            }
            const uint chunk = word0;  // a top-level leaf's first word is its chunk (kEmptyCell: none)
            if (chunk < pc.chunkCount) {
                precise float cellT0 = t0 - margin(r, t0);
                precise float cellT1 = t1 + margin(r, t1);
                if (!(found && (anyHit || best.t < cellT0))) {  // not pruned: trace the cell
                    const uint slot = chunkSlots.v[chunk];
                    if (slot == kWalkNoHit) {
                        complete = false;
                        break;
                    }
                    FlagArray(pc.touched).v[chunk] = 1u;
                    const float tMin = cppMax(ray.tMin, cellT0);
                    const float tMax = cppMin(found ? best.t : ray.tMax, cellT1);
                    const TraceHit h =
                        traverse(chunkView(slots.v[slot]), origin, direction, tMin, tMax, anyHit, stackSize);
                    ++cellsTraced;
                    triangles += h.trianglesTested;
                    if (anyHit ? ((h.flags & kHitFound) != 0u && !found) : replaces(h, cell, found, best, bestCell)) {
                        best = h, found = true;
                        bestChunk = chunk, bestSlot = slot, bestCell = cell;
                    }
                }
                ++cell;
            }
            if (stackSize == 0u) break;
            --stackSize;
            index = stackNode[stackSize], t0 = stackT0[stackSize], t1 = stackT1[stackSize];
        }
    }
    // Member by member: glslang 12 exhausts memory on a whole-struct store of this record.
    WalkArray record = WalkArray(pc.results);
    record.v[i].hit = found ? streamHit(slots.v[bestSlot], best, anyHit) : emptyStreamHit();
    record.v[i].chunk = complete ? bestChunk : kWalkIncomplete;
    record.v[i].cellsTraced = cellsTraced;
    record.v[i].trianglesTested = triangles;
    record.v[i].cell = bestCell;
}
