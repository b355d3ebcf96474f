// The shading steps of the `path` and `ao` integrators (core/PathShading.h, core/Sampling.h,
// core/RayOffset.h) in GLSL, step for step. docs/RENDERING.md specifies them; the device's
// float functions (sqrt, cos, sin, division) may round differently from the host's, so images
// agree with the Embree reference within noise-level tolerance, not bit for bit.
#ifndef VASTRAY_SHADING_GLSL
#define VASTRAY_SHADING_GLSL

const float kPi = 3.14159265358979323846;
const uint kRouletteStartBounce = 3u;
const float kMaxSurvival = 0.95;

vec3 skyRadiance(WavefrontParams p, vec3 direction) {
    const float height = dot(direction, vec3(p.skyUpX, p.skyUpY, p.skyUpZ));
    if (height < 0.0) return vec3(p.groundR, p.groundG, p.groundB);
    const vec3 horizon = vec3(p.horizonR, p.horizonG, p.horizonB);
    return horizon + (vec3(p.zenithR, p.zenithG, p.zenithB) - horizon) * height;
}

// Unit geometric normal on the side the ray came from.
vec3 facingNormal(vec3 geometric, vec3 rayDirection) {
    const vec3 n = normalize(geometric);
    return dot(n, rayDirection) > 0.0 ? -n : n;
}

// Wächter and Binder 2019 (core/RayOffset.h): the point moved along n by a number of float
// ULPs proportional to n, or by a tiny absolute step near the origin.
vec3 offsetRayOrigin(vec3 p, vec3 n) {
    const float kOrigin = 1.0 / 32.0, kFloatScale = 1.0 / 65536.0, kIntScale = 256.0;
    vec3 result;
    for (int a = 0; a < 3; ++a) {
        const int ulps = int(kIntScale * n[a]);
        const int bits = floatBitsToInt(p[a]) + (p[a] < 0.0 ? -ulps : ulps);
        result[a] = abs(p[a]) < kOrigin ? p[a] + kFloatScale * n[a] : intBitsToFloat(bits);
    }
    return result;
}

// frameAround (core/Sampling.h): Duff et al. 2017's branchless basis about unit n, sign from
// n.z >= 0; its tangent and bitangent.
void frameAround(vec3 n, out vec3 tangent, out vec3 bitangent) {
    const float sign = n.z >= 0.0 ? 1.0 : -1.0;
    const float a = -1.0 / (sign + n.z);
    const float b = n.x * n.y * a;
    tangent = vec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    bitangent = vec3(b, sign + n.y * n.y * a, -n.y);
}

// Frame::toWorld of frameAround(n).
vec3 toWorld(vec3 n, vec3 local) {
    vec3 tangent, bitangent;
    frameAround(n, tangent, bitangent);
    return tangent * local.x + bitangent * local.y + n * local.z;
}

vec3 cosineDirection(vec3 n, uint pixel, uint sampleIndex, uint bounce, uint seed) {
    const float u1 = randomFloat(pixel, sampleIndex, bounce, kDimDirectionU, seed);
    const float u2 = randomFloat(pixel, sampleIndex, bounce, kDimDirectionV, seed);
    const float r = sqrt(u1);
    const float phi = 2.0 * kPi * u2;
    return normalize(toWorld(n, vec3(r * cos(phi), r * sin(phi), sqrt(max(0.0, 1.0 - u1)))));
}

float maxComponent(vec3 v) { return max(max(v.x, v.y), v.z); }

#include "common/Microfacet.glsl"

// reflectedLight (core/src/PathShading.cpp): the light of `irradiance` arriving from unit
// `direction` reflected at surface point s (Lambertian, or its metallic-roughness BSDF), before
// the path's throughput; false (no shadow ray) when there is none or it lies below either normal.
bool reflectedLight(WavefrontParams p, Surface s, vec3 direction, vec3 irradiance, out vec3 light) {
    light = vec3(0.0);
    const float cosine = dot(s.ns, direction);
    if (maxComponent(irradiance) <= 0.0 || cosine <= 0.0 || dot(s.n, direction) <= 0.0) return false;
    if (s.glossy) {
        float pdf;
        light = glossyReflection(p, s, direction, pdf) * irradiance;
        return maxComponent(light) > 0.0;
    }
    light = (s.base * irradiance) * (cosine / kPi);
    return true;
}

// unshadowedSunLight: the sun's light reflected at surface point s.
bool unshadowedSunLight(WavefrontParams p, Surface s, out vec3 light) {
    return reflectedLight(p, s, vec3(p.sunX, p.sunY, p.sunZ), vec3(p.sunR, p.sunG, p.sunB), light);
}

WavefrontMaterial materialAt(WavefrontParams p, uint id) {
    return MaterialArray(p.materials).v[id < p.materialCount ? id : 0u];
}

#endif  // VASTRAY_SHADING_GLSL
