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

#endif  // VASTRAY_WAVEFRONT_STATE_GLSL
