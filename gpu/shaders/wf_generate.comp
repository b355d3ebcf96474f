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

#include "common/StreamGroups.glsl"

// Streamed waves: the groups of queue pc.groupQueue, or with pc.pixelCount > 0 the groups 0 ..
// pixelCount - 1 (a thread each); idle ones go to the other group queue.
void generateStream(ParamsRef params, uint j) {
    const bool all = pc.pixelCount > 0u;
    const bool live = all ? j < pc.pixelCount : j < queueCount(params, pc.groupQueue);
    const uint g = !live ? 0u : all ? j : queueOf(params, pc.groupQueue).v[j];
    restartGroups(params, live, g, pc.queue, 2u * kGroupQueue + 1u - pc.groupQueue);
}

void main() {
    const uint j = gl_GlobalInvocationID.x;
    ParamsRef params = ParamsRef(pc.params);
    if (pc.mode == kGenerateStream) {
        generateStream(params, j);
        return;
    }
    appendToQueue(params, pc.queue, true, j < wavePaths() ? 1u : 0u, j, 0u);
    if (j >= wavePaths()) return;
    const uint local = j / pc.sampleCount;  // the tile's pixel
    const uint pixel = pc.firstPixel + (local / pc.tileWidth) * params.p.imageWidth + local % pc.tileWidth;
    startPath(params, j, pixel, pc.firstSample + j % pc.sampleCount, pc.mode == kGeneratePaths);
}
