// The streaming backend's trace kernel: rays of one batch against the chunk resident in one slot
// of the pool. One thread per ray; the traversal (common/KdTraversal.glsl) equals core's
// intersectKdTree / occludedKdTree bit for bit, and position and normal are evaluated in
// core/PathShading.h's order with `precise`, so every backend hands the integrator the same floats.
#version 460
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require

#include "shared/TraceTypes.h"
#include "shared/StreamTypes.h"
#include "common/KdTraversal.glsl"

layout(local_size_x = kTraceWorkgroupSize) in;

layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer SlotTable { ChunkSlot v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer RayArray { StreamRayGpu v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) writeonly buffer HitArray { StreamHitGpu v[]; };

layout(push_constant, std430) uniform PushBlock { StreamPushConstants pc; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= pc.rayCount) return;
    const ChunkSlot s = SlotTable(pc.slotTable).v[pc.slot];
    const ChunkView c = ChunkView(s.nodes, s.leafRefs, s.positions, s.indices, s.singleSided, s.nodeCount,
                                  (s.flags & kSlotSingleSided) != 0u, vec3(s.boundsLoX, s.boundsLoY, s.boundsLoZ),
                                  vec3(s.boundsHiX, s.boundsHiY, s.boundsHiZ));
    const StreamRayGpu ray = RayArray(pc.rays).v[i];
    const vec3 origin = vec3(ray.originX, ray.originY, ray.originZ);
    const vec3 direction = vec3(ray.directionX, ray.directionY, ray.directionZ);
    const TraceHit h = traverse(c, origin, direction, ray.tMin, ray.tMax, pc.anyHit != 0u);

    StreamHitGpu result;
    result.t = 0.0;
    result.positionX = result.positionY = result.positionZ = 0.0;
    result.normalX = result.normalY = result.normalZ = 0.0;
    result.primitive = 0xFFFFFFFFu;
    result.material = 0u;
    result.flags = pc.anyHit != 0u ? (h.flags & kHitFound) : h.flags;
    result.nodesVisited = h.nodesVisited;
    result.trianglesTested = h.trianglesTested;
    if ((h.flags & kHitFound) != 0u && pc.anyHit == 0u) {
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
    HitArray(pc.hits).v[i] = result;
}
