// Access to the device wavefront's parameters and path state (shared/WavefrontTypes.h) for the
// wf_*.comp kernels. Needs GL_EXT_buffer_reference and 64-bit
// integers, and shared/WavefrontTypes.h before it.
#ifndef VASTRAY_WAVEFRONT_STATE_GLSL
#define VASTRAY_WAVEFRONT_STATE_GLSL

layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer ParamsRef { WavefrontParams p; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer Vec4Array { vec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer UVec4Array { uvec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 8) buffer UVec2Array { uvec2 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer RwUintArray { uint v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer RwFloatArray { float v[]; };
#define VASTRAY_FLOAT_ARRAY
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer FloatArray { float v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer MaterialArray { WavefrontMaterial v[]; };

layout(push_constant, std430) uniform PushBlock { WavefrontPush pc; };

// Index of path j's shadow ray among the rays.
uint shadowRayIndex(WavefrontParams p, uint j) { return p.pathCapacity + j; }

// A path's word (WavefrontParams::pathInfo .y): its flags, the bounce of its closest-hit ray and
// its sample index. The walk clears flags in it with atomics; the other fields stay.
uint pathWord(uint flags, uint bounce, uint sampleIndex) {
    return flags | (bounce << kPathBounceShift) | (sampleIndex << kPathSampleShift);
}
// Path j's walk bits (kWalkClosest, kWalkShadow; WavefrontParams::walkBits): set for the rays
// generate or shade start (every bit of the path is clear then), cleared by the walk for each ray
// that finishes, which gets the path's bits before its own was cleared. Where they lie in the
// path word, the word's writer sets them (walksInWord); apart, startWalksApart does.
uint walkWord(WavefrontParams p, uint j) { return p.walkBitsApart != 0u ? j >> 2u : 2u * j + 1u; }
uint walkShift(WavefrontParams p, uint j) { return p.walkBitsApart != 0u ? 8u * (j & 3u) : kPathWalkShift; }
uint walksInWord(WavefrontParams p, uint bits) { return p.walkBitsApart != 0u ? 0u : bits << kPathWalkShift; }
void startWalksApart(WavefrontParams p, uint j, uint bits) {
    if (p.walkBitsApart != 0u && bits != 0u) atomicOr(RwUintArray(p.walkBits).v[walkWord(p, j)], bits << walkShift(p, j));
}
uint finishWalk(WavefrontParams p, uint j, uint bit) {
    const uint shift = walkShift(p, j);
    return (atomicAnd(RwUintArray(p.walkBits).v[walkWord(p, j)], ~(bit << shift)) >> shift) & (kWalkClosest | kWalkShadow);
}
uint pathFlags(uint word) { return word & ((1u << kPathFlagBits) - 1u); }
uint pathBounce(uint word) { return (word >> kPathBounceShift) & ((1u << kPathBounceBits) - 1u); }
uint pathSample(uint word) { return word >> kPathSampleShift; }

// Queue q: the ray queues (kWalkQueue: the rays every walk pass walks; kParkQueue and
// kParkQueue + 1: the rays a paging step parks, and those the one before parked), kShadeQueue (the
// paths whose rays are all walked) or kShadeWaitQueue (paths waiting for volume bricks or texture
// pages; pathCapacity entries each after the ray queues), and the group queues (kGroupQueue,
// kGroupQueue + 1; (pathCapacity + 1) / 2 entries each, gpu/src/PoolLayout.h's queueOffset);
// dense, in no particular order (each ray's walk and each path's shading is independent of the
// others', so the order changes nothing but the schedule).
RwUintArray queueOf(ParamsRef params, uint q) {
    const uint64_t capacity = params.p.pathCapacity;
    const uint64_t at = q < kShadeQueue ? uint64_t(q) * 8ul * capacity
                      : q <= kGroupQueue ? (8ul * kShadeQueue + uint64_t(q - kShadeQueue) * 4ul) * capacity
                                         : (8ul * kShadeQueue + 8ul) * capacity + 4ul * ((capacity + 1ul) / 2ul);
    return RwUintArray(params.p.queues + at);
}
uint queueCount(ParamsRef params, uint q) { return RwUintArray(params.p.queueCounts).v[q]; }

shared uint groupAppendCount;
shared uint groupAppendBase;
// Reserves `count` entries of queue q for this invocation and returns where they start: one
// atomic per workgroup reserves the group's range (and raises the queue's indirect dispatch to
// cover it). With `started`, the entries are rays that begin their walk, counted in
// demand[chunkCount + 1]. Every invocation of the workgroup must call it (it has barriers).
uint reserveInQueue(ParamsRef params, uint q, bool started, uint count) {
    if (gl_LocalInvocationIndex == 0u) groupAppendCount = 0u;
    barrier();
    const uint local = count > 0u ? atomicAdd(groupAppendCount, count) : 0u;
    barrier();
    if (gl_LocalInvocationIndex == 0u && groupAppendCount > 0u) {
        groupAppendBase = atomicAdd(RwUintArray(params.p.queueCounts).v[q], groupAppendCount);
        const uint end = groupAppendBase + groupAppendCount;
        atomicMax(RwUintArray(params.p.queueArgs).v[3u * q], (end + kWavefrontWorkgroupSize - 1u) / kWavefrontWorkgroupSize);
        if (started) atomicAdd(RwUintArray(params.p.demand).v[params.p.chunkCount + 1u], groupAppendCount);
    }
    barrier();
    return groupAppendBase + local;
}
// Appends up to two entries per invocation to queue q (every invocation of the workgroup must
// call it).
void appendToQueue(ParamsRef params, uint q, bool started, uint count, uint first, uint second) {
    const uint at = reserveInQueue(params, q, started, count);
    RwUintArray queue = queueOf(params, q);
    if (count > 0u) queue.v[at] = first;
    if (count > 1u) queue.v[at + 1u] = second;
}

// A pixel's sum (radiance, camera hits) with the samples of paths first .. first + samples - 1
// added one at a time in sample order, and its mean over the pixel's samples: wf_accumulate.comp
// adds them here, the streamed waves' groups (wf_generate.comp) the same floats in the same order.
vec4 addSamples(ParamsRef params, vec4 sum, uint first, uint samples) {
    for (uint s = 0u; s < samples; ++s) {
        sum.xyz += Vec4Array(params.p.radiance).v[first + s].xyz;
        sum.w += (UVec2Array(params.p.pathInfo).v[first + s].y & kPathCameraHit) != 0u ? 1.0 : 0.0;
    }
    return sum;
}
vec4 pixelMean(ParamsRef params, vec4 sum) {
    const float spp = float(params.p.samplesPerPixel);
    return vec4(sum.xyz / spp, sum.w / spp);
}

// Streamed waves: the window of open tiles (shared/WavefrontTypes.h, StreamWindow).
layout(buffer_reference, std430, buffer_reference_align = 16) buffer StreamRef { StreamWindow w; };

#endif  // VASTRAY_WAVEFRONT_STATE_GLSL
