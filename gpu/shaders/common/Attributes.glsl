// Per-vertex shading attributes and the hit record's copies of them: the GLSL twin of
// core/VertexAttributes.h (docs/RENDERING.md, "Vertex attributes"). Octahedral normals in two
// 16-bit snorm words, colours as sRGB8, the hit's colour as 10-bit linear channels.
#ifndef VASTRAY_ATTRIBUTES_GLSL
#define VASTRAY_ATTRIBUTES_GLSL

const uint kNoNormal = 0x80008000u;

float signNotZero(float v) { return v < 0.0 ? -1.0 : 1.0; }

uint snorm16(float v) { return uint(int(round(clamp(v, -1.0, 1.0) * 32767.0))) & 0xFFFFu; }

uint encodeOctahedral(vec3 n) {
    const float sum = abs(n.x) + abs(n.y) + abs(n.z);
    if (!(sum > 0.0) || isinf(sum)) return kNoNormal;
    float x = n.x / sum, y = n.y / sum;
    if (n.z < 0.0) {
        const float fx = (1.0 - abs(y)) * signNotZero(x), fy = (1.0 - abs(x)) * signNotZero(y);
        x = fx, y = fy;
    }
    return snorm16(x) | (snorm16(y) << 16);
}

vec3 decodeOctahedral(uint code) {
    float x = max(float(int(code << 16) >> 16) / 32767.0, -1.0);
    float y = max(float(int(code) >> 16) / 32767.0, -1.0);
    const float z = 1.0 - abs(x) - abs(y);
    if (z < 0.0) {
        const float fx = (1.0 - abs(y)) * signNotZero(x), fy = (1.0 - abs(x)) * signNotZero(y);
        x = fx, y = fy;
    }
    return normalize(vec3(x, y, z));
}

float srgbToLinear(float c) { return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4); }

vec3 unpackColor(uint packed) {
    return vec3(srgbToLinear(float(packed & 0xFFu) / 255.0), srgbToLinear(float((packed >> 8) & 0xFFu) / 255.0),
                srgbToLinear(float((packed >> 16) & 0xFFu) / 255.0));
}

uint interpolateNormal(uint n0, uint n1, uint n2, float u, float v) {
    if (n0 == kNoNormal || n1 == kNoNormal || n2 == kNoNormal) return kNoNormal;
    const float w = 1.0 - u - v;
    return encodeOctahedral(decodeOctahedral(n0) * w + decodeOctahedral(n1) * u + decodeOctahedral(n2) * v);
}

uint unorm10(float v) { return uint(round(clamp(v, 0.0, 1.0) * 1023.0)); }

uint interpolateColor(uint c0, uint c1, uint c2, float u, float v) {
    const float w = 1.0 - u - v;
    const vec3 c = unpackColor(c0) * w + unpackColor(c1) * u + unpackColor(c2) * v;
    return unorm10(c.x) | (unorm10(c.y) << 10) | (unorm10(c.z) << 20);
}

vec3 unpackHitColor(uint packed) {
    return vec3(float(packed & 1023u), float((packed >> 10) & 1023u), float((packed >> 20) & 1023u)) / 1023.0;
}

// The shading normal of a hit: its interpolated normal turned to the side of `facing` (the unit
// geometric normal on the ray's side), or `facing` itself when the hit has none.
vec3 shadingNormalAt(uint code, vec3 facing) {
    if (code == kNoNormal) return facing;
    const vec3 n = decodeOctahedral(code);
    return dot(n, facing) < 0.0 ? -n : n;
}

// The hit's texture coordinates (core/VertexAttributes.h interpolateUv): w * uv0 + u * uv1 + v * uv2
// with every product and sum rounded on its own, as the host's.
vec2 interpolateUv(vec2 uv0, vec2 uv1, vec2 uv2, float u, float v) {
    precise float w = 1.0 - u - v;
    precise vec2 a = w * uv0;
    precise vec2 b = u * uv1;
    precise vec2 c = v * uv2;
    precise vec2 ab = a + b;
    precise vec2 sum = ab + c;
    return sum;
}

// core/RayCone.h's worldPerUvArea from the triangle's unnormalized geometric normal (e1 x e2) and
// its corners' UVs: |e1 x e2| / |duv1 x duv2|, 0 when the UVs span no area or it is not finite.
float worldPerUvArea(vec3 crossE, vec2 uv0, vec2 uv1, vec2 uv2) {
    const float world = length(crossE);
    const vec2 d1 = uv1 - uv0, d2 = uv2 - uv0;
    const float uv = abs(d1.x * d2.y - d1.y * d2.x);
    const float ratio = world / uv;
    return uv > 0.0 && !isinf(ratio) && !isnan(ratio) ? ratio : 0.0;
}

#endif  // VASTRAY_ATTRIBUTES_GLSL
