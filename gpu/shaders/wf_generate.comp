// Camera rays of a wave's paths (core/Camera.h's CameraRays::primary): jittered by the pixel
// dimensions of the path's random numbers, or through the pixel centre for the AOVs. Resets
// each path's state, marks its closest-hit ray for walking and its shadow ray as absent, and
// queues the camera rays (queue pc.queue). An AOV ray belongs to no path to shade.
#version 460
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require

#include "common/WavefrontPrelude.glsl"
#include "common/Random.glsl"

layout(local_size_x = kWavefrontWorkgroupSize) in;

void main() {
    const uint j = gl_GlobalInvocationID.x;
    ParamsRef params = ParamsRef(pc.params);
    appendToQueue(params, pc.queue, true, j < wavePaths() ? 1u : 0u, j, 0u);
    if (j >= wavePaths()) return;
    const uint seed = params.p.seed, width = params.p.imageWidth;
    const uint local = j / pc.sampleCount;  // the tile's pixel
    const uint pixel = pc.firstPixel + (local / pc.tileWidth) * width + local % pc.tileWidth;
    const uint sampleIndex = pc.firstSample + j % pc.sampleCount;
    float jx = 0.5, jy = 0.5;
    if (pc.mode == kGeneratePaths) {
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
    Vec4Array(params.p.rayOrigin).v[j] = vec4(params.p.eyeX, params.p.eyeY, params.p.eyeZ, kInfinity);
    Vec4Array(params.p.rayDirection).v[j] = vec4(direction, 0.0);
    UVec2Array(params.p.rayState).v[j] = uvec2(kRayPending, 0u);
    UVec2Array(params.p.rayState).v[shadow] = uvec2(0u);
    Vec4Array(params.p.throughput).v[j] = vec4(1.0, 1.0, 1.0, 0.0);
    Vec4Array(params.p.radiance).v[j] = vec4(0.0);
    const uint walking = pc.mode == kGeneratePaths ? kPathWalkClosest : 0u;
    UVec4Array(params.p.pathInfo).v[j] = uvec4(pixel, sampleIndex, kPathAlive | walking, 0u);
}
