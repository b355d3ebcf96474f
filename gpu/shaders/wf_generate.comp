// Camera rays of a wave's paths (core/Camera.h's CameraRays::primary): jittered by the pixel
// dimensions of the path's random numbers, or through the pixel centre for the AOVs. Resets
// each path's state, marks its closest-hit ray for walking and its shadow ray as absent, and
// queues the camera rays (queue pc.queue). An AOV ray belongs to no path to shade.
// Streamed waves (kGenerateStream, out of core): a thread per group of pc.sampleCount paths
// whose block of samples is done (or that has none): it adds the block's radiance to its
// pixel's sum in sample order (as wf_accumulate.comp does), writes the pixel's mean when that
// was its last block, and starts the pixel's next block, or the window's next pixel; a group
// the window has no pixel for goes to the other group queue, idle.
#version 460
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require

#include "common/WavefrontPrelude.glsl"
#include "common/Random.glsl"

layout(local_size_x = kWavefrontWorkgroupSize) in;

// Path j starts at image pixel `pixel`, sample `sampleIndex` (jittered unless an AOV ray).
void startPath(ParamsRef params, uint j, uint pixel, uint sampleIndex, bool jitter) {
    const uint seed = params.p.seed, width = params.p.imageWidth;
    float jx = 0.5, jy = 0.5;
    if (jitter) {
        jx = randomFloat(pixel, sampleIndex, 0u, kDimPixelX, seed);
        jy = randomFloat(pixel, sampleIndex, 0u, kDimPixelY, seed);
    }
    const float sx = 2.0 * (float(pixel % width) + jx) / params.p.width - 1.0;
    const float sy = 1.0 - 2.0 * (float(pixel / width) + jy) / params.p.height;
    const vec3 forward = vec3(params.p.forwardX, params.p.forwardY, params.p.forwardZ);
    const vec3 right = vec3(params.p.rightX, params.p.rightY, params.p.rightZ);
    const vec3 up = vec3(params.p.upX, params.p.upY, params.p.upZ);
    const vec3 direction = normalize(forward + right * sx + up * sy);
    const uint shadow = shadowRayIndex(params.p, j);
    Vec4Array(params.p.rayOrigin).v[j] = vec4(params.p.eyeX, params.p.eyeY, params.p.eyeZ, 0.0);  // w: cone width 0
    Vec4Array(params.p.rayDirection).v[j] = vec4(direction, kInfinity);
    UVec2Array(params.p.rayState).v[j] = uvec2(kRayPending, 0u);
    UVec2Array(params.p.rayState).v[shadow] = uvec2(0u);
    Vec4Array(params.p.throughput).v[j] = vec4(1.0, 1.0, 1.0, 0.0);
    Vec4Array(params.p.radiance).v[j] = vec4(0.0, 0.0, 0.0, params.p.cameraSpread);  // w: the ray cone's spread
    UVec2Array(params.p.pathInfo).v[j] = uvec2(pixel, pathWord(kPathAlive | (jitter ? kPathWalkClosest : 0u), 0u, sampleIndex));
}

// Streamed waves: group g's next block (or pixel). Returns the paths it started (from g *
// sampleCount); idle: the window had no pixel for it.
uint continueGroup(ParamsRef params, uint g, out bool idle) {
    idle = false;
    const uint groupSize = pc.sampleCount, spp = params.p.samplesPerPixel, first = g * groupSize;
    StreamRef window = StreamRef(params.p.stream);
    UVec2Array states = UVec2Array(params.p.groupState);
    Vec4Array accum = Vec4Array(params.p.accum);
    uvec2 state = states.v[g];
    uint pixel = 0u, next = 0u;
    if (state.x == 0u) {  // its block is done: add it to the pixel's sum, one sample at a time
        const uvec2 info = UVec2Array(params.p.pathInfo).v[first];
        const uint done = pathSample(info.y);
        const uint samples = min(groupSize, spp - done);
        const vec4 sum = addSamples(params, accum.v[g], first, samples);
        accum.v[g] = sum;
        pixel = info.x, next = done + samples;
        if (next >= spp) {  // the pixel is done
            Vec4Array(params.p.outColor).v[state.y] = pixelMean(params, sum);
            atomicAdd(window.w.done[state.y / params.p.tilePixels], 1u);
            state.x = kGroupIdle;
        }
    }
    if (state.x == kGroupIdle) {  // the window's next pixel
        const uint k = atomicAdd(window.w.cursor, 1u);
        uint start = 0u, tile = 0u;
        while (tile < window.w.tileCount && k >= start + window.w.tiles[4u * tile + 2u]) start += window.w.tiles[4u * tile + 2u], ++tile;
        if (tile == window.w.tileCount) {  // none left now (the host rewinds the cursor to the window's end)
            states.v[g] = uvec2(kGroupIdle);
            idle = true;
            return 0u;
        }
        const uint local = k - start, tileWidth = window.w.tiles[4u * tile + 1u];
        pixel = window.w.tiles[4u * tile] + (local / tileWidth) * params.p.imageWidth + local % tileWidth;
        state.y = window.w.tiles[4u * tile + 3u] * params.p.tilePixels + local;
        next = 0u;
        accum.v[g] = vec4(0.0);
    }
    const uint samples = min(groupSize, spp - next);
    for (uint s = 0u; s < samples; ++s) startPath(params, first + s, pixel, next + s, true);
    states.v[g] = uvec2(samples, state.y);
    return samples;
}

void main() {
    const uint j = gl_GlobalInvocationID.x;
    ParamsRef params = ParamsRef(pc.params);
    if (pc.mode == kGenerateStream) {
        const bool all = pc.pixelCount > 0u;
        const uint g = all ? j : j < queueCount(params, pc.groupQueue) ? queueOf(params, pc.groupQueue).v[j] : 0u;
        uint started = 0u;
        bool idle = false;
        if (all ? j < pc.pixelCount : j < queueCount(params, pc.groupQueue)) started = continueGroup(params, g, idle);
        appendRangeToQueue(params, pc.queue, true, started, g * pc.sampleCount);
        appendToQueue(params, pc.groupQueue ^ 1u, false, idle ? 1u : 0u, g, 0u);
        return;
    }
    appendToQueue(params, pc.queue, true, j < wavePaths() ? 1u : 0u, j, 0u);
    if (j >= wavePaths()) return;
    const uint local = j / pc.sampleCount;  // the tile's pixel
    const uint pixel = pc.firstPixel + (local / pc.tileWidth) * params.p.imageWidth + local % pc.tileWidth;
    startPath(params, j, pixel, pc.firstSample + j % pc.sampleCount, pc.mode == kGeneratePaths);
}
