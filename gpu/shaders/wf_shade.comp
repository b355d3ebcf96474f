// One scattering event of each path in the shade queue, the paths whose rays are all walked
// (cpu/src/Integrators.cpp's tracePath and ambientOcclusion, step for step): first the shadow
// ray of the previous event (the sun's light, or the occlusion test), then the closest hit of
// this one: sky (or environment map) on a miss; emission, next-event estimation to the sun or
// the environment map (a shadow ray), the Lambertian bounce and Russian roulette on a hit. With
// volumes, free flight along the ray first: a real collision before the hit scatters there
// instead (next-event estimation through the volumes, the phase function's bounce). New rays
// are queued on pc.queue for walking. A path whose volume tracking parks at a brick that is not
// resident (paged volumes) writes its park record and nothing else: it joins kShadeWaitQueue
// and shades again from the same state once the bricks are resident, its tracking resuming
// where it parked.
// Each path carries its own bounce, so paths of one wave may be at different bounces. Streamed
// waves (pc.mode kWaveStreamed): a path that starts no ray has ended; the last of its group's
// block to end restarts the group at once with kKernelRestartGroups (common/StreamGroups.glsl: its
// block added to its pixel, its next block started; a group the window has no pixel for joins
// pc.groupQueue, idle), else queues the group (pc.groupQueue) for wf_generate.comp.
#version 460
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require

#include "common/WavefrontPrelude.glsl"
#include "common/Random.glsl"
#include "common/Shading.glsl"
#include "common/Attributes.glsl"
#include "common/Environment.glsl"
#include "common/Volume.glsl"
#include "common/Lights.glsl"
#include "common/Texture.glsl"
#include "common/MaterialMaps.glsl"

layout(local_size_x = kWavefrontWorkgroupSize) in;

// Streamed waves' restarts (kKernelRestartGroups): a workgroup ends few groups at once, so it loads
// their samples 4 at a time (4 KiB of shared memory, not wf_generate's 16 KiB).
#define VASTRAY_SAMPLE_BATCH 4u
#include "common/StreamGroups.glsl"

// Specialization constants (Wavefront.cpp): what a render does not need is not compiled in.
layout(constant_id = 0) const bool kAmbientOcclusion = false;  // the ao integrator, else path
layout(constant_id = 1) const bool kSun = true;                // the sun has irradiance
layout(constant_id = 2) const bool kEmission = true;           // some material emits
layout(constant_id = 3) const bool kShadingNormals = false;    // the scene has per-vertex normals
layout(constant_id = 4) const bool kVertexColors = false;      // the scene has per-vertex colours
layout(constant_id = 5) const bool kEnvironmentMap = false;    // an environment map replaces the sky
layout(constant_id = 6) const bool kVolumes = false;           // the scene has density volumes
layout(constant_id = 7) const bool kMicrofacet = false;        // some material is glossy (not Lambertian)
layout(constant_id = 8) const bool kLights = false;            // the render has punctual lights
layout(constant_id = 9) const bool kClearcoat = false;         // some material has a clear coat
layout(constant_id = 10) const bool kTextures = false;         // some material has maps (and the hits UVs)
layout(constant_id = 11) const bool kNormalMaps = false;       // some material has a normal map (and the hits frames)
layout(constant_id = 12) const bool kEmitters = false;         // next-event estimation samples emissive triangles
layout(constant_id = 16) const bool kStateInHostMemory = false;  // the path state lies in host memory
// (13-15, which leaf codecs the volumes use: common/Volume.glsl)

// (after the constants: a drawn point on an emitter reads its emissive map only with kTextures)
#include "common/Emitters.glsl"

// Starts ray `ray` of path j (j, or its shadow ray) from `origin`, which both its rays share (a
// path's shadow ray and bounce leave the same point), as does the ray cone's width there.
void startRay(WavefrontParams p, uint j, uint ray, vec3 origin, float coneWidth, vec3 direction, float tMax,
              bool fromSurface) {
    Vec4Array(p.rayOrigin).v[j] = vec4(origin, coneWidth);
    Vec4Array(p.rayDirection).v[ray] = vec4(direction, tMax);
    UVec2Array(p.rayState).v[ray] = uvec2(kRayPending | (fromSurface ? kRayFromSurface : 0u), 0u);
}

// surviveRoulette (core/PathShading.h): after scattering event `bounce`.
bool surviveRoulette(inout vec3 throughput, uint pixel, uint sampleIndex, uint bounce, uint seed) {
    if (bounce + 1u < kRouletteStartBounce) return true;
    const float survival = min(kMaxSurvival, maxComponent(throughput));
    if (!(randomFloat(pixel, sampleIndex, bounce, kDimRoulette, seed) < survival)) return false;
    throughput *= 1.0 / survival;
    return true;
}

// Shades path j; count, first and second: the rays it started (at most two), to be queued. A path
// that starts none has ended (`ended`; streamed waves: its group's block is done when its last
// path ends). Returns false when it must wait for volume bricks (it wrote only its park record then).
bool shade(uint j, inout uint count, inout uint first, inout uint second, out bool ended) {
    ended = false;
    const WavefrontParams p = ParamsRef(pc.params).p;
    const uvec2 info = UVec2Array(p.pathInfo).v[j];
    uint flags = pathFlags(info.y), nextBounce = pathBounce(info.y), walks = 0u;  // walks: the rays it starts
    if ((flags & (kPathAlive | kPathShadowPending)) == 0u) return true;
    const bool ao = kAmbientOcclusion;
    const uint shadow = shadowRayIndex(p, j);
    const vec4 carriedRadiance = Vec4Array(p.radiance).v[j];
    vec3 radiance = carriedRadiance.xyz;
    // The ray cone (core/RayCone.h; textures only): its spread, and its width at this event.
    float spread = kTextures ? carriedRadiance.w : 0.0, coneWidth = 0.0;
    const bool shadowDone = (flags & kPathShadowPending) != 0u;  // its walk state is cleared at the end
    if (shadowDone) {
        const bool blocked = (UVec2Array(p.rayState).v[shadow].x & kHitFound) != 0u;
        if (ao)
            radiance = blocked ? vec3(0.0) : vec3(1.0);
        else if (!blocked)
            radiance += Vec4Array(p.pendingSun).v[j].xyz;
        flags &= ~kPathShadowPending;
    }
    if ((flags & kPathAlive) != 0u) {
        flags &= ~kPathAlive;
        const uvec4 hitNormal = UVec4Array(p.hitNormal).v[j];
        const vec3 direction = Vec4Array(p.rayDirection).v[j].xyz;
        const vec4 carried = Vec4Array(p.throughput).v[j];
        vec3 throughput = carried.xyz;
        const uint bounce = nextBounce, pixel = info.x, sampleIndex = pathSample(info.y);
        const bool hitFound = (UVec2Array(p.rayState).v[j].x & kHitFound) != 0u;
        // Whole vectors are loaded once: Mesa 22's lavapipe read `Vec4Array(a).v[j].w` as .x after a
        // load of `Vec4Array(a).v[j].xyz` (the SPIR-V asks for component 3).
        const vec4 hit = Vec4Array(p.hitPosition).v[j];
        const vec4 rayStart = Vec4Array(p.rayOrigin).v[j];
        const float coneStart = kTextures ? rayStart.w : 0.0;
        // Volumes (docs/RENDERING.md, "Volumes"): free flight up to the surface (or to infinity);
        // a real collision before it is this event's scattering point instead.
        // Paged: a tracking parked in the transmittance has its free flight's result in the park.
        VolumeRandom rnd = VolumeRandom(pixel, sampleIndex, bounce, p.seed, 0u);
        VolumePark park = kVolumes ? loadPark(p, j) : noPark();
        const bool resumed = park.phase != kParkNone;
        bool scattered = false;
        float tCollision = 0.0;
        uint which = 0u;
        if (kVolumes && park.phase == kParkTransmittance)
            scattered = park.found, tCollision = park.tCollision, which = park.which;
        else if (kVolumes && !ao)
            scattered = sampleVolumeCollision(p, rayStart.xyz, direction,
                                              hitFound ? hit.w : kInfinity, rnd, tCollision,
                                              which, park);
        // The scattering event's point, and what it does with the path (albedo, phase or bounce).
        vec3 origin, albedo, light, toLight = vec3(p.sunX, p.sunY, p.sunZ), n = vec3(0.0), ns = vec3(0.0);
        float g = 0.0, lightDistance = kInfinity;
        // Next-event estimation's first choice (docs/RENDERING.md, "Emissive triangles"): an
        // emissive triangle (kChoiceEmitter); then ("Lights") a punctual light's direction,
        // distance and irradiance, or the sun or map (kChoiceEnvironment).
        uint choice = kChoiceEnvironment;
        vec3 emitterRadiance;
        float emitterPdf;
        vec3 punctualDirection, punctualIrradiance;
        float punctualDistance;
        bool event = false, shoots = false;
        bool mapWaits = false;  // next-event estimation's point on an emitter read an absent page of its map
        Surface surface = Surface(vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), false, 0.0, 1.0, 0.0, vec3(1.0), 0.0, 0.0, 0.04,
                                  vec3(0.0));
        if (scattered) {
            const WavefrontVolume v = VolumeArray(p.volumes).v[which];
            origin = rayStart.xyz + direction * tCollision;
            if (kTextures) coneWidth = coneStart + spread * tCollision;
            albedo = vec3(v.albedoR, v.albedoG, v.albedoB);
            g = v.anisotropy;
            if (bounce == 0u) flags |= kPathCameraHit;
            // The absorbed share glows (an emission grid): sigma_a / sigma_t = 1 - albedo.
            radiance += (throughput * (vec3(1.0) - albedo)) * volumeEmission(v, origin);
            event = bounce < p.maxDepth;
            if (event && kEmitters && pickEmitterBranch(p, pixel, sampleIndex, bounce)) {
                choice = kChoiceEmitter;
                shoots = sampleEmitter(p, origin, pixel, sampleIndex, bounce, toLight, lightDistance, emitterRadiance,
                                       emitterPdf, mapWaits);
                if (shoots) light = emitterMediumLight(toLight, emitterRadiance, emitterPdf, direction, g);
            } else if (event && kLights)
                choice = choosePunctualLight(p, origin, pixel, sampleIndex, bounce, punctualDirection, punctualDistance,
                                             punctualIrradiance);
            if (event && choice == kChoicePunctual) {
                toLight = punctualDirection, lightDistance = punctualDistance;
                light = punctualIrradiance * henyeyGreenstein(g, direction, toLight);
                shoots = true;
            } else if (event && choice == kChoiceEnvironment)
                shoots = mediumDirectLight(p, kEnvironmentMap, direction, g, pixel, sampleIndex, bounce, light, toLight);
        } else if (!hitFound) {
            if (ao)
                radiance = vec3(1.0);
            else if (kEnvironmentMap)
                radiance += throughput * environmentRadiance(p, direction) *
                            environmentHitWeight(p, direction, bounce == 0u ? 0.0 : carried.w);
            else
                radiance += throughput * skyRadiance(p, direction);
        } else {
            n = facingNormal(uintBitsToFloat(hitNormal.xyz), direction);
            origin = offsetRayOrigin(hit.xyz, n);
            if (kTextures) coneWidth = coneStart + spread * hit.w;
            if (bounce == 0u) flags |= kPathCameraHit;
            if (ao) {
                const float range = p.aoDistance > 0.0 ? p.aoDistance : kInfinity;
                startRay(p, j, shadow, origin, 0.0, cosineDirection(n, pixel, sampleIndex, 0u, p.seed), range, true);
                flags |= kPathShadowPending, walks |= kWalkShadow;
                first = shadow, count = 1u;
            } else {
                const uvec4 ids = UVec4Array(p.hitIds).v[j];
                const WavefrontMaterial m = materialAt(p, ids.y);
                // The factors times the maps (docs/RENDERING.md, "Textures"). A page that is not
                // resident (paged textures): the path waits, nothing of it written, and shades
                // again from the same state once its pages are loaded.
                MaterialValues values = materialFactors(m);
                if (kTextures && hasMaps(m) && !(kVolumes && volumeMissed) &&
                    !sampleMaterialMaps(p, m, hitUvOf(p, j), hitFootprint(p, j, direction, n, coneWidth), values))
                    return false;
                // Vertex colour and shading normal (docs/RENDERING.md, "Vertex attributes"): the
                // colour scales the base colour; the shading normal takes the Lambertian cosines,
                // and light or a bounce below the geometric surface is cut.
                albedo = values.baseColor * (kVertexColors ? unpackHitColor(ids.w) : vec3(1.0));
                ns = kShadingNormals ? shadingNormalAt(hitNormal.w, n) : n;
                // The coat keeps the unbent normal (glTF: a base normal map does not apply to it).
                const vec3 nc = ns;
                if (kNormalMaps && values.normalMapped) ns = bentNormal(p, j, hitNormal, n, values.tangentNormal);
                // Emission, weighted against next-event estimation where it samples this triangle.
                if (kEmission)
                    radiance += (throughput * values.emissive) *
                                (kEmitters ? emitterHitWeight(p, m.emitterDensity, hit.w, -dot(n, direction),
                                                              bounce == 0u ? 0.0 : carried.w)
                                           : 1.0);
                event = bounce < p.maxDepth;
                // Without kClearcoat the coat is a constant 0 and its steps fold away.
                const float coat = kClearcoat ? values.clearcoat : 0.0;
                // Glossy or Lambertian by the factors (core isLambertian), as the reference decides.
                surface = Surface(n, ns, albedo, -direction,
                                  kMicrofacet && (m.metallic > 0.0 || m.specular > 0.0 || (kClearcoat && m.clearcoat > 0.0)),
                                  values.metallic, values.roughness, m.specular,
                                  vec3(m.specularColorR, m.specularColorG, m.specularColorB), coat,
                                  values.clearcoatRoughness, m.dielectricF0, nc);
                // Next-event estimation: an emissive triangle, a punctual light, or the sun, or with a
                // map the sun or the map.
                if (event && kEmitters && pickEmitterBranch(p, pixel, sampleIndex, bounce)) {
                    choice = kChoiceEmitter;
                    shoots = sampleEmitter(p, origin, pixel, sampleIndex, bounce, toLight, lightDistance,
                                           emitterRadiance, emitterPdf, mapWaits) &&
                             emitterSurfaceLight(p, surface, toLight, emitterRadiance, emitterPdf, light);
                } else if (event && kLights)
                    choice = choosePunctualLight(p, origin, pixel, sampleIndex, bounce, punctualDirection,
                                                 punctualDistance, punctualIrradiance);
                if (event && choice == kChoicePunctual) {
                    toLight = punctualDirection, lightDistance = punctualDistance;
                    shoots = reflectedLight(p, surface, toLight, punctualIrradiance, light);
                } else if (event && choice == kChoiceEnvironment && kEnvironmentMap)
                    shoots = environmentDirectLight(p, surface, pixel, sampleIndex, bounce, light, toLight);
                else if (event && choice == kChoiceEnvironment && kSun)
                    shoots = unshadowedSunLight(p, surface, light);
            }
        }
        if (kVolumes && volumeMissed) {
            storePark(p, j, park);
            return false;
        }
        // Nothing of this shading is written yet: the path waits for the page and shades again
        // from the same state (a volume's park, if it resumed from one, as it was).
        if (kTextures && kEmitters && mapWaits) return false;
        if (event) {
            // The sun's or map's share of next-event estimation is 1 - punctualPick.
            if (kLights && shoots && choice == kChoiceEnvironment && p.punctualPick > 0.0)
                light = light * (1.0 / (1.0 - p.punctualPick));
            // The other lights' share is 1 - emitterPick.
            if (kEmitters && shoots && choice != kChoiceEmitter && p.emitterPick > 0.0)
                light = light * (1.0 / (1.0 - p.emitterPick));
            // A volume's light arrives through the volumes; the surface's light has its albedo.
            if (kVolumes && shoots) {
                light *= volumeTransmittance(p, origin, toLight, lightDistance, rnd, park);
                if (volumeMissed) {
                    park.found = scattered, park.tCollision = tCollision, park.which = which;
                    storePark(p, j, park);
                    return false;
                }
                shoots = maxComponent(light) > 0.0;
            }
            if (shoots) {
                Vec4Array(p.pendingSun).v[j] = vec4(scattered ? (throughput * albedo) * light : throughput * light, 0.0);
                startRay(p, j, shadow, origin, coneWidth, toLight, lightDistance, !scattered);
                flags |= kPathShadowPending, walks |= kWalkShadow;
                first = shadow, count = 1u;
            }
            bool survives = false;
            vec3 bounced = vec3(0.0);
            float bouncePdf = 0.0;
            const bool glossy = kMicrofacet && surface.glossy;
            if (glossy) {
                // The metallic-roughness bounce: throughput times f cos / pdf, then roulette.
                vec3 weight;
                survives = scatterSurface(p, surface, pixel, sampleIndex, bounce, bounced, weight, bouncePdf);
                if (survives) {
                    throughput *= weight;
                    survives = surviveRoulette(throughput, pixel, sampleIndex, bounce, p.seed);
                }
            } else {
                throughput *= albedo;
                survives = surviveRoulette(throughput, pixel, sampleIndex, bounce, p.seed);
            }
            if (!glossy && survives && scattered) {
                bounced = sampleHenyeyGreenstein(g, direction, randomFloat(pixel, sampleIndex, bounce, kDimDirectionU, p.seed),
                                                 randomFloat(pixel, sampleIndex, bounce, kDimDirectionV, p.seed));
                bouncePdf = henyeyGreenstein(g, direction, bounced);
            } else if (!glossy && survives) {
                bounced = cosineDirection(ns, pixel, sampleIndex, bounce, p.seed);
                bouncePdf = dot(ns, bounced) / kPi;
                if ((kShadingNormals || kNormalMaps) && dot(bounced, n) <= 0.0) survives = false;
            }
            if (survives) {
                Vec4Array(p.throughput).v[j] = vec4(throughput, kEnvironmentMap || kEmitters ? bouncePdf : 0.0);
                if (kTextures) spread += scatterSpread(bouncePdf, p.scatterSpread);
                startRay(p, j, j, origin, coneWidth, bounced, kInfinity, !scattered);
                flags |= kPathAlive, walks |= kWalkClosest;
                nextBounce = bounce + 1u;
                if (count == 0u) first = j; else second = j;
                ++count;
            }
        }
        if (kVolumes && resumed) storePark(p, j, noPark());
    }
    if (shadowDone && (flags & kPathShadowPending) == 0u) UVec2Array(p.rayState).v[shadow] = uvec2(0u);
    // (Coherent: a restart of the path's group in another workgroup of this dispatch reads them.)
    CoherentVec4Array(p.radiance).v[j] = vec4(radiance, spread);
    CoherentUVec2Array(p.pathInfo).v[j].y = pathWord(flags | walksInWord(p, walks), nextBounce, pathSample(info.y));
    startWalksApart(p, j, walks);
    ended = count == 0u;
    return true;
}

// Streamed waves: the group of each path the workgroup ended (kNoGroup where it ended none).
shared uint endedGroup[kWavefrontWorkgroupSize];
const uint kNoGroup = 0xffffffffu;

void main() {
    const uint k = gl_GlobalInvocationID.x;
    ParamsRef params = ParamsRef(pc.params);
    uint count = 0u, first = 0u, second = 0u, path = 0u;
    bool waits = false, ended = false;
    if (k < queueCount(params, kShadeQueue)) {
        path = queueOf(params, kShadeQueue).v[k];
        waits = !shade(path, count, first, second, ended);
    }
    appendToQueue(params, pc.queue, true, count, first, second);
    if (kVolumes || kTextures) appendToQueue(params, kShadeWaitQueue, false, waits ? 1u : 0u, path, 0u);
    if (pc.mode == kWaveStreamed) {  // streamed waves: the last path of a group's block queues the group
        // With the path state in host memory each atomic crosses the bus, so there it is one per
        // group and workgroup, not per path (the queue keeps a group's paths mostly side by side):
        // the workgroup's first invocation that ended a path of group g takes all of them off g's
        // count. In device memory that costs more than the atomics it saves (PERF_NOTES 80).
        const uint g = path / pc.sampleCount, lt = gl_LocalInvocationIndex;
        bool lead = ended;
        uint paths = 1u;
        if (kStateInHostMemory) {
            endedGroup[lt] = ended ? g : kNoGroup;
            barrier();
            paths = 0u;
            for (uint i = 0u; lead && i < kWavefrontWorkgroupSize; ++i)
                if (endedGroup[i] == g) {
                    if (i < lt) lead = false;
                    ++paths;
                }
        }
        // The ended paths' radiance and words (written by shade) before their group's count: a
        // restart in this dispatch, in another workgroup, reads them.
        const bool restarts = (pc.kernelFlags & kKernelRestartGroups) != 0u;
        if (restarts) memoryBarrierBuffer();
        const bool blockDone = lead && atomicAdd(UVec2Array(params.p.groupState).v[g].x, 0u - paths) == paths;
        if (restarts) {
            memoryBarrierBuffer();
            restartGroups(params, blockDone, g, pc.queue, pc.groupQueue);
        } else {
            appendToQueue(params, pc.groupQueue, false, blockDone ? 1u : 0u, g, 0u);
        }
    }
}
