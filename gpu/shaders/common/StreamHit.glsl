// The streaming kernels' hit record: what a trace of one chunk hands the integrator, with
// position and normal evaluated in core/PathShading.h's order with `precise`, so every backend
// gives the same floats. Included by stream_trace.comp and stream_walk.comp after
// shared/StreamTypes.h and common/KdTraversal.glsl.
#ifndef VASTRAY_STREAM_HIT_GLSL
#define VASTRAY_STREAM_HIT_GLSL

layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer SlotTable { ChunkSlot v[]; };

ChunkView chunkView(ChunkSlot s) {
    return ChunkView(s.nodes, s.leafRefs, s.positions, s.indices, s.singleSided, s.nodeCount,
                     (s.flags & kSlotSingleSided) != 0u, vec3(s.boundsLoX, s.boundsLoY, s.boundsLoZ),
                     vec3(s.boundsHiX, s.boundsHiY, s.boundsHiZ));
}

// A miss (and the counters of the trace that found none).
StreamHitGpu emptyStreamHit() {
    StreamHitGpu result;
    result.t = 0.0;
    result.positionX = result.positionY = result.positionZ = 0.0;
    result.normalX = result.normalY = result.normalZ = 0.0;
    result.primitive = 0xFFFFFFFFu;
    result.material = 0u;
    result.flags = 0u;
    result.nodesVisited = 0u;
    result.trianglesTested = 0u;
    return result;
}

// The record of trace h against the chunk in slot s: any-hit traces keep only the found flag
// and the counters; closest-hit traces add t, position, normal, primitive and material.
StreamHitGpu streamHit(ChunkSlot s, TraceHit h, bool anyHit) {
    StreamHitGpu result = emptyStreamHit();
    result.flags = anyHit ? (h.flags & kHitFound) : h.flags;
    result.nodesVisited = h.nodesVisited;
    result.trianglesTested = h.trianglesTested;
    if ((h.flags & kHitFound) != 0u && !anyHit) {
        const ChunkView c = chunkView(s);
        UintArray indices = UintArray(c.indices);
        const vec3 v0 = vertex(c, indices.v[3u * h.triangle]);
        const vec3 v1 = vertex(c, indices.v[3u * h.triangle + 1u]);
        const vec3 v2 = vertex(c, indices.v[3u * h.triangle + 2u]);
        // barycentricPosition and geometricNormal (core/src/PathShading.cpp, core/VecMath.h).
        precise vec3 e1 = v1 - v0;
        precise vec3 e2 = v2 - v0;
        precise vec3 p = v0 + e1 * h.u + e2 * h.v;
        precise float nx = e1.y * e2.z - e1.z * e2.y;
        precise float ny = e1.z * e2.x - e1.x * e2.z;
        precise float nz = e1.x * e2.y - e1.y * e2.x;
        result.t = h.t;
        result.positionX = p.x, result.positionY = p.y, result.positionZ = p.z;
        result.normalX = nx, result.normalY = ny, result.normalZ = nz;
        if ((s.flags & kSlotPrimitiveIds) != 0u) result.primitive = UintArray(s.primitiveIds).v[h.triangle];
        if ((s.flags & kSlotMaterialIds) != 0u) result.material = UintArray(s.materialIds).v[h.triangle];
    }
    return result;
}

#endif  // VASTRAY_STREAM_HIT_GLSL
