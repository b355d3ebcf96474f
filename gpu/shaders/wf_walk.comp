// One walk pass: the rays of queue pc.queue, closest-hit rays (index j, path j) and shadow rays
// (pathCapacity + j) that generate or shade started (kWalkQueue), or rays parked by the paging
// step before (a park queue). Each ray walks its cells of the top-level tree front to back and
// traces those of resident chunks. Out of core, a cell whose chunk is not resident does not stop
// the walk: the ray goes on tracing the resident cells beyond it, and at the end it is parked if
// it still waits for such a cell (a shadow ray that found a hit waits for nothing): counted in
// the demand counter of the first such cell's chunk and in the look-ahead counters of the
// others' (the pager loads by the first, decodes the others early and fills free slots with
// them), and queued on the step's park queue (pc.parkQueue). Its state keeps the first cell it
// waits for (the cells before it are done) and which of the kRayDoneBits cells after it are done;
// a parked ray walks again in the first pass of the next paging step (the step's later passes do
// not see it: nothing new is resident during a step) and traces the resident cells it has not
// done. So every resident chunk a waiting ray needs is traced by it at once, and a chunk need not
// come back for rays that waited elsewhere while it was resident. The hit does not depend on the
// order cells are traced in: hits merge under one total order (t, front before back, lower chunk)
// and a cell's trace finds its hits up to the best so far inclusive, so an out-of-core render
// equals the in-core one bit for bit (the cost AOV counts the work done, which is more out of
// core). A cell is pruned once a hit lies before it (any hit, for shadow rays). A ray that
// finishes clears its bit in its path's walk bits (WavefrontParams::walkBits, device memory
// wherever the path state lies); the last of a path's rays to finish queues the path for shading
// (kShadeQueue).
#version 460
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require

#include "common/WavefrontPrelude.glsl"
// Cut-outs and blends (docs/RENDERING.md, "Blending"): testTriangle
// (common/KdTraversal.glsl) asks cutAway, defined below, about every hit it would keep.
#define VASTRAY_CUTOUTS 1
bool cutAway(uint tri, uvec3 corners, float u, float v);
// Positions in 8 bytes a vertex (vertex(), common/KdTraversal.glsl; the grid in pc).
layout(constant_id = 4) const bool kPackedPositions = false;
#define VASTRAY_PACKED_POSITIONS 1
#include "common/KdTraversal.glsl"
#include "common/Bvh4Traversal.glsl"
#include "common/SlotTable.glsl"
#include "common/Attributes.glsl"
#include "common/NormalMap.glsl"
#include "common/Texture.glsl"
#include "common/Random.glsl"

layout(local_size_x = kWavefrontWorkgroupSize) in;

// Specialization constants (Wavefront.cpp): what a render does not need is not compiled in.
layout(constant_id = 0) const bool kCountCost = true;  // the cost AOV: cells and triangles traced per pixel
layout(constant_id = 1) const bool kPaging = true;     // some chunk is not resident: rays may park
layout(constant_id = 2) const bool kCutouts = false;   // some material is a cut-out or a blend (core isAlphaTested)
layout(constant_id = 3) const bool kBlends = false;    // some material is a blend (core isBlended): rays draw coins
// constant_id 4, kPackedPositions, is declared above (common/KdTraversal.glsl reads it).

// The slot whose chunk the walk traces (cutAway reads its materials, UVs and primitive ids).
ChunkSlot cutoutSlot;
// The walked ray's key for its blend coins (core/PathShading.h alphaRayBase).
uint alphaBase;

// core/PathShading.h's alphaDiscards for triangle `tri` of cutoutSlot's chunk (corners: its
// vertices) at barycentrics (u, v): a blend's coin (alphaCoin: its primitive id hashed with the
// ray's key) at or above the base colour alpha times its map's alpha at level 0; a cut-out's
// product below its cutoff. The map's level-0 pages are pinned in the pool (DeviceTextures): never
// absent.
bool cutAway(uint tri, uvec3 corners, float u, float v) {
    if (!kCutouts) return false;
    ParamsRef params = ParamsRef(pc.params);
    uint material = (cutoutSlot.flags & kSlotMaterialIds) != 0u ? UintArray(cutoutSlot.materialIds).v[tri] : 0u;
    material = material < params.p.materialCount ? material : 0u;
    const WavefrontMaterial m = MaterialArray(params.p.materials).v[material];
    const bool blended = kBlends && m.alphaBlend != 0u;
    const bool mapped = m.baseColorMap != kNoGpuTexture && (cutoutSlot.flags & kSlotUvs) != 0u;
    if (!blended && (!(m.alphaCutoff > 0.0) || !mapped)) return false;
    float alpha = m.baseAlpha;
    if (mapped) {
        FloatArray t = FloatArray(cutoutSlot.uvs);
        const vec2 uv = interpolateUv(vec2(t.v[2u * corners.x], t.v[2u * corners.x + 1u]),
                                      vec2(t.v[2u * corners.y], t.v[2u * corners.y + 1u]),
                                      vec2(t.v[2u * corners.z], t.v[2u * corners.z + 1u]), u, v);
        uint missing = kTexturePageAbsent;
        alpha *= sampleTexture(GpuTextureArray(params.p.textures).v[m.baseColorMap], mapUv(m.baseColorUv, uv), 0.0,
                               TextureWords(params.p.texturePages), TextureWords(params.p.texturePool), missing).a;
        if (missing != kTexturePageAbsent) return false;
    }
    if (!blended) return alpha < m.alphaCutoff;
    const uint primitive = (cutoutSlot.flags & kSlotPrimitiveIds) != 0u ? UintArray(cutoutSlot.primitiveIds).v[tri] : tri;
    return !(float(pcgHash(alphaBase ^ primitive) >> 8u) * (1.0 / 16777216.0) < alpha);
}

const uint kShadowAlphaSalt = 0x9E3779B9u;  // core/PathShading.h

// alphaRayBase of ray `ray` (anyHit: path j's shadow ray): keyed by its path's pixel, sample and
// bounce; a shadow ray's bounce is the event that started it (the path's field, less one when its
// bounce ray was started too).
uint rayAlphaBase(ParamsRef params, uint j, bool anyHit) {
    const uvec2 info = UVec2Array(params.p.pathInfo).v[j];
    const uint field = pathBounce(info.y);
    const uint bounce = anyHit && (pathFlags(info.y) & kPathAlive) != 0u ? field - 1u : field;
    return randomBits(info.x, pathSample(info.y), bounce, kDimAlpha, params.p.seed) ^ (anyHit ? kShadowAlphaSalt : 0u);
}

bool replaces(TraceHit h, uint chunk, bool found, float bestT, bool bestFront, uint bestChunk) {
    if ((h.flags & kHitFound) == 0u) return false;
    if (!found || h.t < bestT) return true;
    if (h.t != bestT) return false;
    const bool front = (h.flags & kHitFrontFacing) != 0u;
    if (front != bestFront) return front;
    return chunk < bestChunk;
}

// The closest hit's record: position and geometric normal as core/PathShading.h evaluates them
// (StreamHit.glsl's order, `precise`), primitive and material ids when the slot holds them, and
// the interpolated shading normal (hitNormal.w's bits) and colour (hitIds.w) when it holds
// those (kNoNormal and white otherwise), and the interpolated UV with the triangle's world area
// per UV area (hitUv) when the slot holds UVs (only when the render reads them), with the triangle's UV derivatives in its normal map's
// texture space (hitFrame) when its material has one: the chunk may be evicted before the path
// is shaded.
void writeHit(ParamsRef params, uint ray, ChunkSlot s, TraceHit h, uint chunk) {
    const ChunkView c = chunkView(s);
    const uvec3 corner = triangleVertices(c, h.triangle);
    const vec3 v0 = vertex(c, corner.x), v1 = vertex(c, corner.y), v2 = vertex(c, corner.z);
    precise vec3 e1 = v1 - v0;
    precise vec3 e2 = v2 - v0;
    precise vec3 position = v0 + e1 * h.u + e2 * h.v;
    precise float nx = e1.y * e2.z - e1.z * e2.y;
    precise float ny = e1.z * e2.x - e1.x * e2.z;
    precise float nz = e1.x * e2.y - e1.y * e2.x;
    const uint primitive = (s.flags & kSlotPrimitiveIds) != 0u ? UintArray(s.primitiveIds).v[h.triangle] : 0xFFFFFFFFu;
    const uint material = (s.flags & kSlotMaterialIds) != 0u ? UintArray(s.materialIds).v[h.triangle] : 0u;
    uint shadingNormal = kNoNormal, color = 0x3FFFFFFFu;
    if ((s.flags & kSlotNormals) != 0u) {
        UintArray n = UintArray(s.normals);
        shadingNormal = interpolateNormal(n.v[corner.x], n.v[corner.y], n.v[corner.z], h.u, h.v);
    }
    if ((s.flags & kSlotColors) != 0u) {
        UintArray c = UintArray(s.colors);
        color = interpolateColor(c.v[corner.x], c.v[corner.y], c.v[corner.z], h.u, h.v);
    }
    if ((s.flags & kSlotUvs) != 0u) {
        FloatArray t = FloatArray(s.uvs);
        const vec2 uv0 = vec2(t.v[2u * corner.x], t.v[2u * corner.x + 1u]);
        const vec2 uv1 = vec2(t.v[2u * corner.y], t.v[2u * corner.y + 1u]);
        const vec2 uv2 = vec2(t.v[2u * corner.z], t.v[2u * corner.z + 1u]);
        const vec2 uv = interpolateUv(uv0, uv1, uv2, h.u, h.v);
        RwFloatArray hitUv = RwFloatArray(params.p.hitUv);
        hitUv.v[kHitUvFloats * ray] = uv.x, hitUv.v[kHitUvFloats * ray + 1u] = uv.y;
        hitUv.v[kHitUvFloats * ray + 2u] = worldPerUvArea(vec3(nx, ny, nz), uv0, uv1, uv2);
        if (params.p.hitFrame != 0ul && ray < params.p.pathCapacity) {
            const WavefrontMaterial m = MaterialArray(params.p.materials).v[material < params.p.materialCount ? material : 0u];
            vec3 dpdu = vec3(0.0), dpdv = vec3(0.0);
            if (m.normalMap != kNoGpuTexture) uvDerivatives(m.normalUv, v0, v1, v2, uv0, uv1, uv2, dpdu, dpdv);
            RwFloatArray frame = RwFloatArray(params.p.hitFrame);
            for (uint c = 0u; c < 3u; ++c) frame.v[6u * ray + c] = dpdu[c], frame.v[6u * ray + 3u + c] = dpdv[c];
        }
    }
    Vec4Array(params.p.hitPosition).v[ray] = vec4(position, h.t);
    // Written as words: a normal's code read back as a float could be flushed or canonicalized.
    UVec4Array(params.p.hitNormal).v[ray] = uvec4(floatBitsToUint(vec3(nx, ny, nz)), shadingNormal);
    UVec4Array(params.p.hitIds).v[ray] = uvec4(primitive, material, chunk, color);
}

// Walks one ray; returns whether it is parked (queued again) and whether it finished the last
// walk its path waited for (queued for shading).
void walk(ParamsRef params, uint ray, out bool parked, out bool pathReady) {
    parked = false, pathReady = false;
    const uint capacity = params.p.pathCapacity;
    const bool anyHit = ray >= capacity;
    const uint j = anyHit ? ray - capacity : ray;
    UVec2Array states = UVec2Array(params.p.rayState);
    const uvec2 state = states.v[ray];
    uint flags = state.x;
    if ((flags & kRayPending) == 0u) return;
    RwUintArray demand = RwUintArray(params.p.demand);
    const uint chunkCount = params.p.chunkCount;
    UintArray topNodes = UintArray(params.p.topNodes);
    UintArray chunkSlots = UintArray(params.p.chunkSlots);
    const uint parkWord = state.y;  // the leaf of the first cell it waits for + 1, or 0
    if (kBlends) alphaBase = rayAlphaBase(params, j, anyHit);
    gRayFromSurface = (flags & kRayFromSurface) != 0u;
    const vec4 d = Vec4Array(params.p.rayDirection).v[ray];
    const vec3 origin = Vec4Array(params.p.rayOrigin).v[j].xyz, direction = d.xyz;  // both rays' origin
    const float tMax = d.w;
    bool found = (flags & kHitFound) != 0u;
    float bestT = found && !anyHit ? Vec4Array(params.p.hitPosition).v[ray].w : 0.0;
    bool bestFront = (flags & kHitFrontFacing) != 0u;
    uint bestChunk = found && !anyHit ? UVec4Array(params.p.hitIds).v[ray].z : kWalkNoHit;
    TraceHit best = TraceHit(0.0, 0.0, 0.0, 0u, 0u, 0u, 0u, 0u);
    bool newBest = false;
    uint bestSlot = 0u, cells = 0u, triangles = 0u, parkedLeaf = 0u;
    // Out of core: the cells it waits for (the first one's leaf and chunk, how many). A hit found
    // later in the walk lies in a later cell, so it prunes none of them. Cells are counted from
    // the first one waited for: `since` from the last walk's (its done bits: doneBefore), `after`
    // from this walk's (the done bits it leaves: doneNow).
    bool beforeFirst = parkWord != 0u;  // cells before the last walk's first are done (or pruned)
    const uint doneBefore = flags >> kRayDoneShift;
    uint since = 0u, after = 0u, doneNow = 0u, waiting = 0u, firstWaitChunk = 0u;

    const ChunkView top = ChunkView(0ul, 0ul, 0ul, 0ul, 0ul, params.p.topNodeCount, false, false,
                                    vec3(params.p.boundsLoX, params.p.boundsLoY, params.p.boundsLoZ),
                                    vec3(params.p.boundsHiX, params.p.boundsHiY, params.p.boundsHiZ));
    SlotTable slots = SlotTable(params.p.slotTable);
    TraversalRay r;
    float t0 = 0.0, t1 = tMax;
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
                bool done = false;
                if (kPaging) {
                    if (beforeFirst) {
                        beforeFirst = index + 1u != parkWord;
                        done = beforeFirst;
                    } else if (parkWord != 0u) {
                        ++since;
                        done = since <= kRayDoneBits && ((doneBefore >> (since - 1u)) & 1u) != 0u;
                    }
                }
                bool first = false, traced = false;
                precise float cellT0 = t0 - margin(r, t0);
                precise float cellT1 = t1 + margin(r, t1);
                if (done) {
                } else if (found && (anyHit || bestT < cellT0)) {
                    if (anyHit) break;
                } else {
                    const uint slot = chunkSlots.v[chunk];
                    if (slot == kWalkNoHit) {  // (without kPaging the host has every chunk resident)
                        if (kPaging) {
                            first = waiting++ == 0u;
                            if (first) parkedLeaf = index, firstWaitChunk = chunk;
                            else atomicAdd(RwUintArray(params.p.ahead).v[chunk], 1u);
                        }
                    } else {
                        RwUintArray(params.p.touched).v[chunk] = 1u;
                        const float tMinCell = cppMax(0.0, cellT0);
                        const float tMaxCell = cppMin(found ? bestT : tMax, cellT1);
                        const ChunkSlot s = slots.v[slot];
                        if (kCutouts) cutoutSlot = s;
                        const TraceHit h = traverseBvh4(chunkView(s), r, tMinCell, tMaxCell, anyHit);
                        ++cells, traced = true;
                        triangles += h.trianglesTested;
                        if (anyHit ? (h.flags & kHitFound) != 0u : replaces(h, chunk, found, bestT, bestFront, bestChunk)) {
                            best = h, found = true, newBest = true;
                            bestT = h.t, bestFront = (h.flags & kHitFrontFacing) != 0u;
                            bestChunk = chunk, bestSlot = slot;
                            if (anyHit) break;
                        }
                    }
                }
                // A cell beyond the window is traced again if it is resident at a later walk
                // (the same hits), or waited for if it is not.
                if (kPaging && waiting != 0u && !first) {
                    ++after;
                    if ((done || traced) && after <= kRayDoneBits) doneNow |= 1u << (after - 1u);
                }
            }
            if (stackSize == 0u) break;
            --stackSize;
            index = stackNode[stackSize], t0 = stackT0[stackSize], t1 = stackT1[stackSize];
        }
    }
    // A shadow ray that found a hit beyond a cell it waits for needs that cell no more.
    parked = kPaging && waiting != 0u && !(anyHit && found);
    if (parked) {
        atomicAdd(demand.v[firstWaitChunk], 1u);
        atomicAdd(demand.v[chunkCount], 1u);
    }
    flags = (found ? kHitFound : 0u) | (bestFront && !anyHit ? kHitFrontFacing : 0u) | (parked ? kRayPending : 0u) |
            (gRayFromSurface ? kRayFromSurface : 0u) | (parked ? doneNow << kRayDoneShift : 0u);
    const uint newParkWord = parked ? parkedLeaf + 1u : 0u;
    if (newBest && !anyHit) writeHit(params, ray, slots.v[bestSlot], best, bestChunk);
    states.v[ray] = uvec2(flags, newParkWord);
    if (kCountCost && cells != 0u) {
        // The tile pixel of a tile's wave, or the window pixel of a streamed wave's group.
        const uint pixel = pc.mode == kWaveStreamed ? UVec2Array(params.p.groupState).v[j / pc.sampleCount].y
                                                  : j / pc.sampleCount;
        atomicAdd(RwUintArray(params.p.outCost).v[2u * pixel], cells);
        atomicAdd(RwUintArray(params.p.outCost).v[2u * pixel + 1u], triangles);
    }
    if (!parked) {
        const uint mine = anyHit ? kWalkShadow : kWalkClosest;
        const uint before = finishWalk(params.p, j, mine);
        pathReady = (before & mine) != 0u && (before & (kWalkClosest | kWalkShadow) & ~mine) == 0u;
    }
}

void main() {
    const uint k = gl_GlobalInvocationID.x;
    ParamsRef params = ParamsRef(pc.params);
    const uint ray = k < queueCount(params, pc.queue) ? queueOf(params, pc.queue).v[k] : 0xFFFFFFFFu;
    bool parked = false, pathReady = false;
    if (ray != 0xFFFFFFFFu) walk(params, ray, parked, pathReady);
    const uint capacity = params.p.pathCapacity;
    appendToQueue(params, pc.parkQueue, false, parked ? 1u : 0u, ray, 0u);
    appendToQueue(params, kShadeQueue, false, pathReady ? 1u : 0u, ray >= capacity ? ray - capacity : ray, 0u);
}
