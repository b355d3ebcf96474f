// Closest hit of each ray against the one chunk GpuChunkTracer holds: one thread per ray; the
// traversal (common/KdTraversal.glsl) equals intersectKdTree bit for bit.
#version 460
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require

#include "shared/TraceTypes.h"
#include "shared/StreamTypes.h"  // kSlotLongTriangle (KdTraversal.glsl)
#include "common/KdTraversal.glsl"

layout(local_size_x = kTraceWorkgroupSize) in;

layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer RayArray { TraceRay v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) writeonly buffer HitArray { TraceHit v[]; };

layout(push_constant, std430) uniform PushBlock { TracePushConstants pc; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= pc.rayCount) return;
    const TraceRay ray = RayArray(pc.rays).v[i];
    const vec3 origin = vec3(ray.originX, ray.originY, ray.originZ);
    const vec3 direction = vec3(ray.directionX, ray.directionY, ray.directionZ);
    const ChunkView c = ChunkView(pc.nodes, pc.leafRefs, pc.positions, pc.indices, pc.singleSided, pc.nodeCount,
                                  pc.hasSingleSided != 0u, false, vec3(pc.boundsLoX, pc.boundsLoY, pc.boundsLoZ),
                                  vec3(pc.boundsHiX, pc.boundsHiY, pc.boundsHiZ));
    HitArray(pc.hits).v[i] = traverse(c, origin, direction, ray.tMin, ray.tMax, false, 0u);
}
