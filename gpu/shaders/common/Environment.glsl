// The environment map and next-event estimation's choice of light (core/EnvironmentMap.h,
// core/src/PathShading.cpp's unshadowedDirectLight and environmentHitWeight) in GLSL, step for
// step. docs/RENDERING.md, "Environment map" and "Lights", specifies them. Needs
// WavefrontState.glsl, Random.glsl and Shading.glsl before it.
#ifndef VASTRAY_ENVIRONMENT_GLSL
#define VASTRAY_ENVIRONMENT_GLSL


vec3 skyUp(WavefrontParams p) { return vec3(p.skyUpX, p.skyUpY, p.skyUpZ); }
// The map's frame (environmentFrame, computed on the host): tangent, bitangent and skyUp.
vec3 envTangent(WavefrontParams p) { return vec3(p.envTangentX, p.envTangentY, p.envTangentZ); }
vec3 envBitangent(WavefrontParams p) { return vec3(p.envBitangentX, p.envBitangentY, p.envBitangentZ); }

uint envTexelAt(WavefrontParams p, float u, float v) {
    const uint x = min(uint(u * float(p.envWidth)), p.envWidth - 1u);
    const uint y = min(uint(v * float(p.envHeight)), p.envHeight - 1u);
    return y * p.envWidth + x;
}

// The texel towards unit d, and sin(theta) there.
uint envTexelToward(WavefrontParams p, vec3 d, out float sinTheta) {
    const float x = dot(d, envTangent(p)), y = dot(d, envBitangent(p)), z = dot(d, skyUp(p));
    sinTheta = sqrt(x * x + y * y);
    // GLSL leaves atan(0, 0) undefined (C++'s atan2 gives 0).
    float phi = sinTheta == 0.0 ? 0.0 : atan(y, x);
    if (phi < 0.0) phi += 2.0 * kPi;
    const float theta = sinTheta == 0.0 ? (z < 0.0 ? kPi : 0.0) : atan(sinTheta, z);
    return envTexelAt(p, phi * (0.5 / kPi), theta * (1.0 / kPi));
}

vec3 envTexelRadiance(WavefrontParams p, uint t) {
    FloatArray rgb = FloatArray(p.envRgb);
    return vec3(rgb.v[3u * t], rgb.v[3u * t + 1u], rgb.v[3u * t + 2u]);
}

vec3 environmentRadiance(WavefrontParams p, vec3 d) {
    float sinTheta;
    return envTexelRadiance(p, envTexelToward(p, d, sinTheta));
}

float environmentPdf(WavefrontParams p, vec3 d) {
    float sinTheta;
    const uint t = envTexelToward(p, d, sinTheta);
    if (sinTheta <= 0.0) return 0.0;
    return FloatArray(p.envDensity).v[t] / (2.0 * kPi * kPi * sinTheta);
}

// The last index i in [0, n) with cdf[first + i] <= u, and u's place in that interval.
uint pickInterval(FloatArray cdf, uint first, uint n, float u, out float offset) {
    uint lo = 0u, hi = n;
    while (hi - lo > 1u) {
        const uint mid = (lo + hi) / 2u;
        if (cdf.v[first + mid] <= u) lo = mid; else hi = mid;
    }
    const float below = cdf.v[first + lo], width = cdf.v[first + lo + 1u] - below;
    offset = width > 0.0 ? clamp((u - below) / width, 0.0, 1.0) : 0.5;
    return lo;
}

// sampleEnvironment: a direction from the map's density; pdf 0: none.
vec3 sampleEnvironment(WavefrontParams p, float u1, float u2, out vec3 radiance, out float pdf) {
    pdf = 0.0;
    radiance = vec3(0.0);
    float dv, du;
    const uint y = pickInterval(FloatArray(p.envMarginal), 0u, p.envHeight, u1, dv);
    const uint x = pickInterval(FloatArray(p.envConditional), y * (p.envWidth + 1u), p.envWidth, u2, du);
    const float v = (float(y) + dv) / float(p.envHeight), u = (float(x) + du) / float(p.envWidth);
    const float theta = kPi * v, phi = 2.0 * kPi * u;
    const float sinTheta = sin(theta);
    if (!(sinTheta > 0.0)) return vec3(0.0);
    const uint t = y * p.envWidth + x;
    radiance = envTexelRadiance(p, t);
    pdf = FloatArray(p.envDensity).v[t] / (2.0 * kPi * kPi * sinTheta);
    // Frame::toWorld's order of operations.
    return normalize(envTangent(p) * (sinTheta * cos(phi)) + envBitangent(p) * (sinTheta * sin(phi)) +
                     skyUp(p) * cos(theta));
}

float powerHeuristic(float chosen, float other) {
    if (!(chosen > 0.0)) return 0.0;
    const float ratio = other / chosen;
    return 1.0 / (1.0 + ratio * ratio);
}

// lightSampleReflection: f cos radiance times the power heuristic against the bounce's density,
// over lightPdf, for a direction a light sampler drew; false: none (below either normal).
bool lightSampleReflection(WavefrontParams p, Surface s, vec3 direction, vec3 radiance, float lightPdf, out vec3 light) {
    light = vec3(0.0);
    const float cosine = dot(s.ns, direction);
    if (cosine <= 0.0 || dot(s.n, direction) <= 0.0) return false;
    if (s.glossy) {
        float bsdfDensity;
        const vec3 reflection = glossyReflection(p, s, direction, bsdfDensity);
        light = (reflection * radiance) * (powerHeuristic(lightPdf, bsdfDensity) / lightPdf);
        return maxComponent(light) > 0.0;
    }
    const float weight = powerHeuristic(lightPdf, cosine / kPi) / lightPdf;
    light = (s.base * radiance) * ((cosine / kPi) * weight);
    return true;
}

// unshadowedDirectLight with a map: the light reflected towards the ray (base colour applied,
// the path's throughput not yet) and the shadow ray's direction; false: no shadow ray.
bool environmentDirectLight(WavefrontParams p, Surface s, uint pixel, uint sampleIndex, uint bounce, out vec3 light,
                            out vec3 direction) {
    const float pickSun = p.sunPick;
    if (pickSun >= 1.0 || (pickSun > 0.0 && randomFloat(pixel, sampleIndex, bounce, kDimLightPick, p.seed) < pickSun)) {
        if (!unshadowedSunLight(p, s, light)) return false;
        if (pickSun < 1.0) light = light * (1.0 / pickSun);
        direction = vec3(p.sunX, p.sunY, p.sunZ);
        return true;
    }
    vec3 radiance;
    float pdf;
    direction = sampleEnvironment(p, randomFloat(pixel, sampleIndex, bounce, kDimLightU, p.seed),
                                  randomFloat(pixel, sampleIndex, bounce, kDimLightV, p.seed), radiance, pdf);
    if (!(pdf > 0.0)) return false;
    return lightSampleReflection(p, s, direction, radiance, (1.0 - pickSun) * pdf, light);
}

// environmentHitWeight: bouncePdf 0 is a camera ray.
float environmentHitWeight(WavefrontParams p, vec3 d, float bouncePdf) {
    if (bouncePdf <= 0.0 || p.sunPick >= 1.0) return 1.0;
    return powerHeuristic(bouncePdf, (1.0 - p.sunPick) * environmentPdf(p, d));
}

#endif  // VASTRAY_ENVIRONMENT_GLSL
