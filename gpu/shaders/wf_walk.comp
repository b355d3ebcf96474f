// One walk pass over a stream: the rays of queue pc.queue, the wave's closest-hit rays (index j)
// and shadow rays (pathCapacity + j) that generate or shade started; in later passes the
// ones still pending. Each ray walks its cells of the top-level tree front to back from where
// its last pass stopped, and traces the cells whose chunks became resident for this pass
// (chunkEpoch == pass). A chunk resident for an earlier pass of the stream was traced then by
// every ray still pending now, so it is skipped even if it has been evicted since. A cell whose
// chunk has not been resident in this stream adds the ray to that chunk's demand counter; the
// ray stays pending and resumes at its first such cell in the next pass, after the host has
// paged chunks in. So each chunk is paged in at most once per stream, and every pass pages in
// at least one chunk: a stream ends after at most as many passes as it needs chunks. A cell is pruned once a hit lies before it (any hit, for shadow rays). Hits merge under
// one total order (t, front before back, lower chunk), so the closest hit does not depend on
// which chunks were resident when: an out-of-core render equals the in-core one bit for bit.
#version 460
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require

#include "common/WavefrontPrelude.glsl"
#include "common/KdTraversal.glsl"
#include "common/Bvh4Traversal.glsl"
#include "common/SlotTable.glsl"

layout(local_size_x = kWavefrontWorkgroupSize) in;

const uint kAovCostBit = 32u;  // vastray::kAovCost

bool replaces(TraceHit h, uint chunk, bool found, float bestT, bool bestFront, uint bestChunk) {
    if ((h.flags & kHitFound) == 0u) return false;
    if (!found || h.t < bestT) return true;
    if (h.t != bestT) return false;
    const bool front = (h.flags & kHitFrontFacing) != 0u;
    if (front != bestFront) return front;
    return chunk < bestChunk;
}

// The closest hit's record: position and geometric normal as core/PathShading.h evaluates them
// (StreamHit.glsl's order, `precise`), primitive and material ids when the slot holds them.
void writeHit(ParamsRef params, uint ray, ChunkSlot s, TraceHit h, uint chunk, uint flags) {
    const ChunkView c = chunkView(s);
    UintArray indices = UintArray(c.indices);
    const vec3 v0 = vertex(c, indices.v[3u * h.triangle]);
    const vec3 v1 = vertex(c, indices.v[3u * h.triangle + 1u]);
    const vec3 v2 = vertex(c, indices.v[3u * h.triangle + 2u]);
    precise vec3 e1 = v1 - v0;
    precise vec3 e2 = v2 - v0;
    precise vec3 position = v0 + e1 * h.u + e2 * h.v;
    precise float nx = e1.y * e2.z - e1.z * e2.y;
    precise float ny = e1.z * e2.x - e1.x * e2.z;
    precise float nz = e1.x * e2.y - e1.y * e2.x;
    const uint primitive = (s.flags & kSlotPrimitiveIds) != 0u ? UintArray(s.primitiveIds).v[h.triangle] : 0xFFFFFFFFu;
    const uint material = (s.flags & kSlotMaterialIds) != 0u ? UintArray(s.materialIds).v[h.triangle] : 0u;
    Vec4Array(params.p.hitPosition).v[ray] = vec4(position, h.t);
    Vec4Array(params.p.hitNormal).v[ray] = vec4(nx, ny, nz, uintBitsToFloat(flags));
    UVec4Array(params.p.hitIds).v[ray] = uvec4(primitive, material, chunk, 0u);
}

shared uint groupRays;

void main() {
    const uint k = gl_GlobalInvocationID.x;
    ParamsRef params = ParamsRef(pc.params);
    const uint queued = RwUintArray(params.p.queueCounts).v[pc.queue];
    const uint ray = k < queued ? rayQueue(params, pc.queue).v[k] : 0u;
    const uint capacity = params.p.pathCapacity;
    const bool anyHit = ray >= capacity;
    const uint j = anyHit ? ray - capacity : ray;
    Vec4Array normals = Vec4Array(params.p.hitNormal);
    uint flags = k < queued ? floatBitsToUint(normals.v[ray].w) : 0u;
    RwUintArray demand = RwUintArray(params.p.demand);
    const uint chunkCount = params.p.chunkCount;
    if (pc.pass == 0u) {  // every ray of the stream is pending in its first pass: count them
        if (gl_LocalInvocationIndex == 0u) groupRays = 0u;
        barrier();
        if ((flags & kRayPending) != 0u) atomicAdd(groupRays, 1u);
        barrier();
        if (gl_LocalInvocationIndex == 0u && groupRays != 0u) atomicAdd(demand.v[chunkCount + 1u], groupRays);
    }
    if ((flags & kRayPending) == 0u) return;

    gRayFromSurface = (flags & kRayFromSurface) != 0u;
    const vec4 o = Vec4Array(params.p.rayOrigin).v[ray], d = Vec4Array(params.p.rayDirection).v[ray];
    const vec3 origin = o.xyz, direction = d.xyz;
    const float tMax = o.w;
    bool found = (flags & kHitFound) != 0u;
    float bestT = found ? Vec4Array(params.p.hitPosition).v[ray].w : 0.0;
    bool bestFront = (flags & kHitFrontFacing) != 0u;
    uint bestChunk = found ? UVec4Array(params.p.hitIds).v[ray].z : kWalkNoHit;
    TraceHit best = TraceHit(0.0, 0.0, 0.0, 0u, 0u, 0u, 0u, 0u);
    bool newBest = false, missing = false;
    uint bestSlot = 0u, cells = 0u, triangles = 0u;
    float resume = d.w;

    const ChunkView top = ChunkView(0ul, 0ul, 0ul, 0ul, 0ul, params.p.topNodeCount, false,
                                    vec3(params.p.boundsLoX, params.p.boundsLoY, params.p.boundsLoZ),
                                    vec3(params.p.boundsHiX, params.p.boundsHiY, params.p.boundsHiZ));
    UintArray topNodes = UintArray(params.p.topNodes);
    UintArray chunkSlots = UintArray(params.p.chunkSlots);
    UintArray chunkEpoch = UintArray(params.p.chunkEpoch);
    SlotTable slots = SlotTable(params.p.slotTable);
    TraversalRay r;
    float t0 = d.w, t1 = tMax;
    if (top.nodeCount != 0u && prepareTraversalRay(top, origin, direction, r) && clipToBounds(top, r, t0, t1)) {
        uint stackSize = 0u, index = 0u;
        for (;;) {
            const uint word0 = topNodes.v[2u * index], word1 = topNodes.v[2u * index + 1u];
            if ((word1 & 3u) != 3u) {
                index = descend(r, word0, word1, index, t0, t1, stackSize);
                continue;
            }
            const uint chunk = word0;  // a top-level leaf's first word is its chunk (kEmptyCell: none)
            if (chunk < chunkCount) {
                precise float cellT0 = t0 - margin(r, t0);
                precise float cellT1 = t1 + margin(r, t1);
                if (found && (anyHit || bestT < cellT0)) {
                    if (anyHit) break;
                } else {
                    const uint epoch = chunkEpoch.v[chunk];
                    if (epoch == kNotResidentThisStream) {
                        if (!missing) resume = t0;
                        missing = true;
                        atomicAdd(demand.v[chunk], 1u);
                    } else if (epoch == pc.pass) {
                        const uint slot = chunkSlots.v[chunk];
                        RwUintArray(params.p.touched).v[chunk] = 1u;
                        const float tMinCell = cppMax(0.0, cellT0);
                        const float tMaxCell = cppMin(found ? bestT : tMax, cellT1);
                        const TraceHit h = traverseBvh4(chunkView(slots.v[slot]), r, tMinCell, tMaxCell, anyHit);
                        ++cells;
                        triangles += h.trianglesTested;
                        if (anyHit ? (h.flags & kHitFound) != 0u : replaces(h, chunk, found, bestT, bestFront, bestChunk)) {
                            best = h, found = true, newBest = true;
                            bestT = h.t, bestFront = (h.flags & kHitFrontFacing) != 0u;
                            bestChunk = chunk, bestSlot = slot;
                            if (anyHit) break;
                        }
                    }
                }
            }
            if (stackSize == 0u) break;
            --stackSize;
            index = stackNode[stackSize], t0 = stackT0[stackSize], t1 = stackT1[stackSize];
        }
    }
    if (anyHit && found) missing = false;  // blocked: nothing behind the hit matters
    if (missing) atomicAdd(demand.v[chunkCount], 1u);
    flags = (found ? kHitFound : 0u) | (bestFront && !anyHit ? kHitFrontFacing : 0u) | (missing ? kRayPending : 0u) |
            (gRayFromSurface ? kRayFromSurface : 0u);
    if (newBest && !anyHit) {
        writeHit(params, ray, slots.v[bestSlot], best, bestChunk, flags);
    } else {
        normals.v[ray].w = uintBitsToFloat(flags);
    }
    if (missing) Vec4Array(params.p.rayDirection).v[ray].w = resume;
    if ((params.p.aovs & kAovCostBit) != 0u && cells != 0u) {
        const uint pixel = j / pc.sampleCount;
        atomicAdd(RwUintArray(params.p.outCost).v[2u * pixel], cells);
        atomicAdd(RwUintArray(params.p.outCost).v[2u * pixel + 1u], triangles);
    }
}
