// Adds the wave's samples to each tile pixel's sum, one sample at a time in sample order, so
// the sum's floats do not depend on how many samples a wave holds (that depends on the budget);
// with mode 1 also writes the pixel's mean radiance and alpha for the host to read.
#version 460
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require

#include "common/WavefrontPrelude.glsl"

layout(local_size_x = kWavefrontWorkgroupSize) in;

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= pc.pixelCount) return;
    ParamsRef params = ParamsRef(pc.params);
    Vec4Array accum = Vec4Array(params.p.accum);
    const vec4 sum = addSamples(params, accum.v[i], i * pc.sampleCount, pc.sampleCount);
    accum.v[i] = sum;
    if (pc.mode == 1u) Vec4Array(params.p.outColor).v[i] = pixelMean(params, sum);
}
