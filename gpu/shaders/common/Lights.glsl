// Punctual lights (core/Light.h's pickLight and lightAt, core/src/PathShading.cpp's
// choosePunctualLight) in GLSL, step for step: next-event estimation's choice between a
// punctual light and the sun or environment map (docs/RENDERING.md, "Lights").
#ifndef VASTRAY_LIGHTS_GLSL
#define VASTRAY_LIGHTS_GLSL

layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer LightArray { WavefrontLight v[]; };

const uint kLightDirectional = 0u, kLightSpot = 2u;  // vastray::LightType
const uint kChoiceEnvironment = 0u, kChoicePunctual = 1u, kChoiceNone = 2u;  // vastray::LightChoice

// pickLight: the first light whose cdf exceeds u (the last when rounding leaves none).
uint pickLight(WavefrontParams p, float u) {
    uint lo = 0u, hi = p.lightCount - 1u;
    while (lo < hi) {
        const uint mid = (lo + hi) / 2u;
        if (LightArray(p.lights).v[mid].cdf > u) hi = mid; else lo = mid + 1u;
    }
    return lo;
}

// lightAt: the unit direction towards light l from `point`, its distance (infinite for a
// directional light) and the irradiance it brings to a surface facing it; false: none.
bool lightAt(WavefrontLight l, vec3 point, out vec3 direction, out float distance, out vec3 irradiance) {
    const vec3 radiant = vec3(l.radiantR, l.radiantG, l.radiantB), axis = vec3(l.dirX, l.dirY, l.dirZ);
    direction = -axis, distance = kInfinity, irradiance = radiant;
    if (l.type == kLightDirectional) return true;
    const vec3 d = vec3(l.posX, l.posY, l.posZ) - point;
    const float squared = dot(d, d);
    if (!(squared > 0.0)) return false;
    distance = sqrt(squared);
    direction = d * (1.0 / distance);
    float attenuation = 1.0 / squared;
    if (l.type == kLightSpot) {
        const float cone = clamp(dot(axis, -direction) * l.coneScale + l.coneOffset, 0.0, 1.0);
        attenuation *= cone * cone;
    }
    irradiance = radiant * attenuation;
    return attenuation > 0.0;
}

// choosePunctualLight at `origin` (kDimPunctual): kChoiceEnvironment, kChoicePunctual (direction,
// distance and irradiance divided by both pick probabilities) or kChoiceNone.
uint choosePunctualLight(WavefrontParams p, vec3 origin, uint pixel, uint sampleIndex, uint bounce, out vec3 direction,
                         out float distance, out vec3 irradiance) {
    direction = vec3(0.0), distance = kInfinity, irradiance = vec3(0.0);
    if (!(p.punctualPick > 0.0)) return kChoiceEnvironment;
    const float u = randomFloat(pixel, sampleIndex, bounce, kDimPunctual, p.seed);
    if (!(u < p.punctualPick)) return kChoiceEnvironment;
    const WavefrontLight l = LightArray(p.lights).v[pickLight(p, u / p.punctualPick)];
    if (!lightAt(l, origin, direction, distance, irradiance)) return kChoiceNone;
    irradiance *= 1.0 / (p.punctualPick * l.pick);
    return kChoicePunctual;
}

#endif  // VASTRAY_LIGHTS_GLSL
