#include "Integrators.h"

#include <cmath>
#include <limits>

#include "vastray/core/RayOffset.h"
#include "vastray/core/Sampling.h"
#include "vastray/core/VecMath.h"
#include "vastray/core/Volume.h"

namespace vastray {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

// The light towards `direction` from `origin`, zero when the shadow ray is blocked within
// `distance`, times the volumes' transmittance (random numbers after *counter's).
Vec3f shadowedLight(const ShadingContext& context, Vec3f light, Vec3f origin, Vec3f direction, float distance,
                    RandomKey key, uint32_t* counter, uint64_t& rays) {
    ++rays;
    if (context.scene.occluded({origin, direction}, distance, alphaRayBase(key, true, context.options.seed))) return {};
    if (context.options.volumes)
        light = light * volumeTransmittance(*context.options.volumes, origin, direction, distance, key,
                                            context.options.seed, counter);
    return light;
}

std::span<const LightEntry> lightsOf(const RenderOptions& options) {
    return options.lights ? std::span<const LightEntry>(*options.lights) : std::span<const LightEntry>();
}

// Next-event estimation's probability of picking an emissive triangle (emitterPickProbability).
float emitterPick(const RenderOptions& options) {
    return emitterPickProbability(options.environment, lightsOf(options), options.emitters.get());
}

// Next-event estimation's light at a surface `point` or (point null) at a point in a volume
// scattering light that travels along `travel` with anisotropy g: an emissive triangle's, a
// punctual light's, or the sun's or the environment map's (docs/RENDERING.md, "Lights" and
// "Emissive triangles"); zero when the shadow ray from `origin` is blocked.
Vec3f directLight(const ShadingContext& context, const SurfacePoint* point, Vec3f travel, float g, Vec3f origin,
                  RandomKey key, uint32_t* counter, uint64_t& rays) {
    const RenderOptions& options = context.options;
    const std::span<const LightEntry> lights = lightsOf(options);
    const float pickEmitter = emitterPick(options);
    if (pickEmitter > 0.0f && randomFloat(key, kDimEmitter, options.seed) < pickEmitter) {
        EmitterSample s;
        if (!sampleEmitter(*options.emitters, context.mesh.materials, context.textures, pickEmitter, origin, key,
                           options.seed, &s))
            return {};
        Vec3f light;
        if (!point) light = emitterMediumLight(s, travel, g);
        else if (!emitterSurfaceLight(*point, s, &light)) return {};
        return shadowedLight(context, light, origin, s.direction, s.distance, key, counter, rays);
    }
    const float punctualPick = punctualPickProbability(options.environment, lights);
    Vec3f light, direction, irradiance;
    float distance = kInfinity;
    switch (choosePunctualLight(lights, punctualPick, origin, key, options.seed, &direction, &distance, &irradiance)) {
        case LightChoice::None: return {};
        case LightChoice::Punctual:
            if (!point) light = irradiance * henyeyGreenstein(g, travel, direction);
            else if (!reflectedLight(*point, direction, irradiance, &light)) return {};
            break;
        case LightChoice::Environment:
            if (point ? !unshadowedDirectLight(options.environment, context.sunDirection, *point, key, options.seed,
                                               &light, &direction)
                      : !unshadowedMediumLight(options.environment, context.sunDirection, travel, g, key,
                                               options.seed, &light, &direction))
                return {};
            if (punctualPick > 0.0f) light = light * (1.0f / (1.0f - punctualPick));
            break;
    }
    if (pickEmitter > 0.0f) light = light * (1.0f / (1.0f - pickEmitter));
    return shadowedLight(context, light, origin, direction, distance, key, counter, rays);
}

}  // namespace

SurfacePoint surfaceAt(const ShadingContext& context, const SceneHit& hit, Vec3f rayDirection, RayCone cone) {
    const TriangleMesh& mesh = context.mesh;
    const Vec3f v0 = mesh.positions[mesh.indices[3 * hit.triangle]];
    const Vec3f v1 = mesh.positions[mesh.indices[3 * hit.triangle + 1]];
    const Vec3f v2 = mesh.positions[mesh.indices[3 * hit.triangle + 2]];
    const uint32_t* corners = &mesh.indices[3 * size_t(hit.triangle)];
    const Material& material = materialAt(mesh.materials, mesh.materialOf(hit.triangle));
    MaterialSample sample;
    UvDerivatives derivatives;
    const bool mapped = !mesh.uvs.empty() && !context.textures.empty() && material.textures.any();
    if (mapped) {
        const std::array<float, 2> t0 = mesh.uvs[corners[0]], t1 = mesh.uvs[corners[1]], t2 = mesh.uvs[corners[2]];
        const MapFootprint footprint{worldPerUvArea(v0, v1, v2, t0, t1, t2), coneWidthAt(cone, hit.t),
                                     dot(rayDirection, normalize(geometricNormal(v0, v1, v2)))};
        sample = sampleMaterial(material, context.textures, interpolateUv(t0, t1, t2, hit.u, hit.v), &footprint);
        if (sample.normalMapped)
            derivatives = uvDerivatives(material.textures.slots[uint32_t(TextureSlot::Normal)].transform, v0, v1, v2,
                                        t0, t1, t2);
    }
    return makeSurfacePoint(barycentricPosition(v0, v1, v2, hit.u, hit.v), geometricNormal(v0, v1, v2),
                            rayDirection, material,
                            hitAttributes(mesh.normals, mesh.colors, corners[0], corners[1], corners[2], hit.u, hit.v),
                            mapped ? &sample : nullptr, &derivatives);
}

SampleResult tracePath(const ShadingContext& context, Ray ray, RandomKey key, uint64_t& rays) {
    const RenderOptions& options = context.options;
    SampleResult result;
    Vec3f throughput{1, 1, 1};
    float bouncePdf = 0;  // the solid-angle density of the last bounce; 0 for the camera ray
    RayCone cone{0.0f, context.cameraSpread};  // the ray's (docs/RENDERING.md, "Texture level of detail")
    for (uint32_t bounce = 0;; ++bounce) {
        key.bounce = bounce;
        SceneHit hit;
        ++rays;
        const bool surface = context.scene.intersect(ray, kInfinity, &hit, alphaRayBase(key, false, options.seed));
        // Volumes (docs/RENDERING.md, "Volumes"): free flight up to the surface (or to infinity);
        // a real collision before it is this event's scattering point instead.
        uint32_t counter = 0;
        VolumeCollision collision;
        if (options.volumes && sampleVolumeCollision(*options.volumes, ray.origin, ray.direction,
                                                     surface ? hit.t : kInfinity, key, options.seed, &counter,
                                                     &collision)) {
            if (bounce == 0) result.cameraRayHit = true;
            const Volume& volume = (*options.volumes)[collision.volume];
            const VolumeMaterial& m = volume.material;
            const Vec3f albedo{m.albedo[0], m.albedo[1], m.albedo[2]};
            const Vec3f position = ray.origin + ray.direction * collision.t;
            // The absorbed share glows (an emission grid): sigma_a / sigma_t = 1 - albedo.
            if (!volume.emissionVoxels.empty())
                result.radiance = result.radiance +
                                  mul(mul(throughput, Vec3f{1, 1, 1} - albedo), volumeEmission(volume, position));
            if (bounce == options.maxDepth) break;
            result.radiance = result.radiance + mul(mul(throughput, albedo),
                                                    directLight(context, nullptr, ray.direction, m.anisotropy,
                                                                position, key, &counter, rays));
            throughput = mul(throughput, albedo);
            if (!surviveRoulette(throughput, bounce, key, options.seed)) break;
            const Vec3f direction = sampleHenyeyGreenstein(m.anisotropy, ray.direction,
                                                           randomFloat(key, kDimDirectionU, options.seed),
                                                           randomFloat(key, kDimDirectionV, options.seed));
            bouncePdf = henyeyGreenstein(m.anisotropy, ray.direction, direction);
            cone = scatterCone(cone, collision.t, bouncePdf, context.scatterSpread);
            ray = {position, direction};
            continue;
        }
        if (!surface) {
            const Environment& environment = options.environment;
            result.radiance = result.radiance + mul(throughput, skyRadiance(environment, ray.direction)) *
                                                    environmentHitWeight(environment, ray.direction, bouncePdf);
            break;
        }
        if (bounce == 0) result.cameraRayHit = true;
        const SurfacePoint point = surfaceAt(context, hit, ray.direction, cone);
        // Emission, weighted against next-event estimation where it samples this triangle.
        float weight = 1.0f;
        if (options.emitters && bouncePdf > 0.0f) {
            const uint32_t material = context.mesh.materialOf(hit.triangle);
            weight = emitterHitWeight(emitterPick(options),
                                      material < options.emitters->areaDensity.size()
                                          ? options.emitters->areaDensity[material]
                                          : 0.0f,
                                      hit.t, -dot(point.normal, ray.direction), bouncePdf);
        }
        result.radiance = result.radiance + mul(throughput, point.emissive) * weight;
        if (bounce == options.maxDepth) break;
        const Vec3f origin = offsetRayOrigin(point.position, point.normal);
        result.radiance = result.radiance + mul(throughput, directLight(context, &point, ray.direction, 0.0f, origin, key, &counter, rays));
        if (point.glossy) {
            // The metallic-roughness bounce: throughput times f cos / pdf, then roulette.
            Vec3f direction, weight;
            if (!scatterSurface(point, key, options.seed, &direction, &weight, &bouncePdf)) break;
            throughput = mul(throughput, weight);
            if (!surviveRoulette(throughput, bounce, key, options.seed)) break;
            cone = scatterCone(cone, hit.t, bouncePdf, context.scatterSpread);
            ray = {origin, direction};
            continue;
        }
        // Cosine sampling of a Lambertian BRDF: f * cos / pdf = base colour (times the vertex colour).
        throughput = mul(throughput, point.albedo);
        if (!surviveRoulette(throughput, bounce, key, options.seed)) break;
        Vec3f direction;
        if (!bounceDirection(point, key, options.seed, &direction)) break;
        bouncePdf = dot(point.shadingNormal, direction) / kPi;
        cone = scatterCone(cone, hit.t, bouncePdf, context.scatterSpread);
        ray = {origin, direction};
    }
    return result;
}

SampleResult traceAmbientOcclusion(const ShadingContext& context, Ray ray, RandomKey key, uint64_t& rays) {
    SampleResult result;
    SceneHit hit;
    ++rays;
    key.bounce = 0;
    if (!context.scene.intersect(ray, kInfinity, &hit, alphaRayBase(key, false, context.options.seed))) {
        result.radiance = {1, 1, 1};
        return result;
    }
    result.cameraRayHit = true;
    const SurfacePoint point = surfaceAt(context, hit, ray.direction, {0.0f, context.cameraSpread});
    const Vec3f origin = offsetRayOrigin(point.position, point.normal);
    const float range = context.options.aoDistance > 0.0f ? context.options.aoDistance : kInfinity;
    ++rays;
    const bool blocked = context.scene.occluded({origin, cosineDirection(point.normal, key, context.options.seed)}, range,
                                                alphaRayBase(key, true, context.options.seed));
    result.radiance = blocked ? Vec3f{0, 0, 0} : Vec3f{1, 1, 1};
    return result;
}

}  // namespace vastray
