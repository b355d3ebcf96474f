// Access to the device wavefront's parameters and path state (shared/WavefrontTypes.h) for the
// wf_*.comp kernels. Needs GL_EXT_buffer_reference and 64-bit
// integers, and shared/WavefrontTypes.h before it.
#ifndef VASTRAY_WAVEFRONT_STATE_GLSL
#define VASTRAY_WAVEFRONT_STATE_GLSL

layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer ParamsRef { WavefrontParams p; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer Vec4Array { vec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer UVec4Array { uvec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer RwUintArray { uint v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer RwFloatArray { float v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer MaterialArray { WavefrontMaterial v[]; };

layout(push_constant, std430) uniform PushBlock { WavefrontPush pc; };

// Index of path j's shadow ray among the rays.
uint shadowRayIndex(WavefrontParams p, uint j) { return p.pathCapacity + j; }

// Ray queue q: the ray indices a stream walks, dense, in no particular order (each ray's walk
// is independent of the others', so the order changes nothing but the schedule).
RwUintArray rayQueue(ParamsRef params, uint q) { return RwUintArray(params.p.queues + uint64_t(q) * 8ul * params.p.pathCapacity); }

// Appends up to two rays per invocation to queue pc.queue: one atomic per workgroup reserves
// the group's range. Every invocation of the workgroup must call it (it has barriers).
shared uint groupAppendCount;
shared uint groupAppendBase;
void appendRays(ParamsRef params, uint count, uint first, uint second) {
    if (gl_LocalInvocationIndex == 0u) groupAppendCount = 0u;
    barrier();
    const uint local = count > 0u ? atomicAdd(groupAppendCount, count) : 0u;
    barrier();
    if (gl_LocalInvocationIndex == 0u)
        groupAppendBase = groupAppendCount > 0u ? atomicAdd(RwUintArray(params.p.queueCounts).v[pc.queue], groupAppendCount) : 0u;
    barrier();
    RwUintArray queue = rayQueue(params, pc.queue);
    if (count > 0u) queue.v[groupAppendBase + local] = first;
    if (count > 1u) queue.v[groupAppendBase + local + 1u] = second;
}

#endif  // VASTRAY_WAVEFRONT_STATE_GLSL
