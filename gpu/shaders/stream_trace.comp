// The streaming backend's trace kernel: rays of one batch against the chunk resident in one slot
// of the pool. One thread per ray; the traversal (common/KdTraversal.glsl) equals core's
// intersectKdTree / occludedKdTree bit for bit, and the hit record (common/StreamHit.glsl) is
// evaluated in core/PathShading.h's order, so every backend hands the integrator the same floats.
#version 460
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require

#include "shared/TraceTypes.h"
#include "shared/StreamTypes.h"
#include "common/KdTraversal.glsl"
#include "common/StreamHit.glsl"

layout(local_size_x = kTraceWorkgroupSize) in;

layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer RayArray { StreamRayGpu v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) writeonly buffer HitArray { StreamHitGpu v[]; };

layout(push_constant, std430) uniform PushBlock { StreamPushConstants pc; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= pc.rayCount) return;
    const ChunkSlot s = SlotTable(pc.slotTable).v[pc.slot];
    const StreamRayGpu ray = RayArray(pc.rays).v[i];
    const vec3 origin = vec3(ray.originX, ray.originY, ray.originZ);
    const vec3 direction = vec3(ray.directionX, ray.directionY, ray.directionZ);
    const TraceHit h = traverse(chunkView(s), origin, direction, ray.tMin, ray.tMax, pc.anyHit != 0u, 0u);
    HitArray(pc.hits).v[i] = streamHit(s, h, pc.anyHit != 0u);
}
