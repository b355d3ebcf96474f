// Samples a batch of texture queries through the page pool (common/Texture.glsl): the GPU side
// of GpuTextureSampler, which tests hold against core/Texture.h's sampleTexture.
#version 460
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require

#include "shared/TextureTypes.h"
#include "common/Attributes.glsl"
#include "common/Texture.glsl"

layout(local_size_x = 64) in;

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer QueryArray { TextureQuery v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) writeonly buffer ResultArray { vec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) writeonly buffer MissingArray { uint v[]; };

layout(push_constant, std430) uniform PushBlock { TextureProbePushConstants pc; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= pc.queryCount) return;
    const TextureQuery q = QueryArray(pc.queries).v[i];
    uint missing = kTexturePageAbsent;
    const vec4 value = sampleTexture(GpuTextureArray(pc.textures).v[q.texture], vec2(q.u, q.v), q.lod,
                                     TextureWords(pc.pageTable), TextureWords(pc.pool), missing);
    ResultArray(pc.results).v[i] = value;
    MissingArray(pc.missing).v[i] = missing;
}
