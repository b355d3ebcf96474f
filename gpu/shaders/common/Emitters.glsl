// Sampled emissive triangles (core/Emitters.h's pickEmitter and emitterPoint, core/src/PathShading.cpp's
// sampleEmitter, emitterSurfaceLight, emitterMediumLight and emitterHitWeight) in GLSL, step for
// step: next-event estimation's emitter branch and the weight of the emission a bounce finds
// (docs/RENDERING.md, "Emissive triangles"). Needs Shading.glsl, Attributes.glsl (interpolateUv),
// Environment.glsl (powerHeuristic), Volume.glsl (henyeyGreenstein) and MaterialMaps.glsl
// (readMap) before it.
#ifndef VASTRAY_EMITTERS_GLSL
#define VASTRAY_EMITTERS_GLSL

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer EmitterArray { WavefrontEmitter v[]; };

const uint kChoiceEmitter = 3u;  // next-event estimation picked an emissive triangle

// Whether next-event estimation picks an emissive triangle (kDimEmitter < emitterPick).
bool pickEmitterBranch(WavefrontParams p, uint pixel, uint sampleIndex, uint bounce) {
    return p.emitterPick > 0.0 && randomFloat(pixel, sampleIndex, bounce, kDimEmitter, p.seed) < p.emitterPick;
}

// pickEmitter: the alias column floor(bits n / 2^32), kept when u < its keep, else its alias.
uint pickEmitter(WavefrontParams p, uint bits, float u) {
    uint column, low;
    umulExtended(bits, p.emitterCount, column, low);
    const WavefrontEmitter e = EmitterArray(p.emitters).v[column];
    return u < e.keep ? column : e.alias;
}

// sampleEmitter at `origin`: the unit direction to a point drawn on an emissive triangle (moved
// off it towards the origin), its distance (the shadow ray's tMax), its radiance (an emissive
// map read at the point's UV, level 0) and the direction's solid-angle density, emitterPick
// included. false: it brings nothing to origin, or (`mapWaits` set; paged textures) a page of its
// map is not resident: it is asked for, and the path waits as for its own maps.
bool sampleEmitter(WavefrontParams p, vec3 origin, uint pixel, uint sampleIndex, uint bounce, out vec3 direction,
                   out float distance, out vec3 radiance, out float pdf, inout bool mapWaits) {
    direction = vec3(0.0), distance = 0.0, radiance = vec3(0.0), pdf = 0.0;
    const uint i = pickEmitter(p, randomBits(pixel, sampleIndex, bounce, kDimEmitterPick, p.seed),
                               randomFloat(pixel, sampleIndex, bounce, kDimEmitterKeep, p.seed));
    const WavefrontEmitter e = EmitterArray(p.emitters).v[i];
    const vec3 v0 = vec3(e.v0x, e.v0y, e.v0z), v1 = vec3(e.v1x, e.v1y, e.v1z), v2 = vec3(e.v2x, e.v2y, e.v2z);
    // emitterPoint: barycentrics (u2 s, s - u2 s) with s = sqrt(u1).
    const float s = sqrt(randomFloat(pixel, sampleIndex, bounce, kDimEmitterU, p.seed));
    const float u = randomFloat(pixel, sampleIndex, bounce, kDimEmitterV, p.seed) * s;
    const vec3 y = v0 + (v1 - v0) * u + (v2 - v0) * (s - u);
    const WavefrontMaterial m = materialAt(p, e.material);
    const vec3 front = normalize(cross(v1 - v0, v2 - v0));
    const bool frontSeen = dot(front, origin - y) > 0.0;
    if (!frontSeen && m.doubleSided == 0u) return false;
    const vec3 facing = frontSeen ? front : -front;
    const vec3 toPoint = offsetRayOrigin(y, facing) - origin;
    const float squared = dot(toPoint, toPoint);
    if (!(squared > 0.0)) return false;
    distance = sqrt(squared);
    direction = toPoint * (1.0 / distance);
    const float cosine = -dot(facing, direction);
    if (!(cosine > 0.0)) return false;
    radiance = vec3(m.emitR, m.emitG, m.emitB);
    if (kTextures && m.emissiveMap != kNoGpuTexture) {
        const vec2 uv = interpolateUv(vec2(e.t0u, e.t0v), vec2(e.t1u, e.t1v), vec2(e.t2u, e.t2v), u, s - u);
        bool absent = false;
        uint pages[kMaxMapPages];
        uint count = 0u;
        radiance *= readMap(p, m.emissiveMap, m.emissiveUv, uv, MapFootprint(0.0, 0.0, 1.0), absent, pages, count).rgb;
        if (!asksForPages(p, absent, pages, count)) {
            mapWaits = true;
            return false;
        }
    }
    pdf = p.emitterPick * m.emitterDensity * (squared / cosine);
    return pdf > 0.0;
}

// emitterSurfaceLight: what surface s reflects of the drawn point's radiance arriving along
// `direction`, weighted by the power heuristic against the bounce's density. false: none.
bool emitterSurfaceLight(WavefrontParams p, Surface s, vec3 direction, vec3 radiance, float pdf, out vec3 light) {
    return lightSampleReflection(p, s, direction, radiance, pdf, light);
}

// emitterMediumLight: what a point in a volume scatters of it (phase function g, light that
// travelled along `travel`), weighted against the phase function's density.
vec3 emitterMediumLight(vec3 direction, vec3 radiance, float pdf, vec3 travel, float g) {
    const float phase = henyeyGreenstein(g, travel, direction);
    return radiance * (phase * powerHeuristic(pdf, phase) / pdf);
}

// emitterHitWeight: the emission a bounce of density bouncePdf (0: a camera ray) finds at
// distance t on a triangle of area density `density` (0: not sampled), |cos| `cosine`.
float emitterHitWeight(WavefrontParams p, float density, float t, float cosine, float bouncePdf) {
    if (bouncePdf <= 0.0 || !(density > 0.0) || !(p.emitterPick > 0.0)) return 1.0;
    return powerHeuristic(bouncePdf, p.emitterPick * density * (t * t / cosine));
}

#endif  // VASTRAY_EMITTERS_GLSL
