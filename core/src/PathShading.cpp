#include "vastray/core/PathShading.h"

#include <cmath>

#include "vastray/core/EnvironmentMap.h"
#include "vastray/core/Microfacet.h"
#include "vastray/core/RayOffset.h"
#include "vastray/core/Sampling.h"
#include "vastray/core/VecMath.h"
#include "vastray/core/Volume.h"

namespace vastray {
namespace {
Vec3f toVec(const std::array<float, 3>& c) { return {c[0], c[1], c[2]}; }

// The BSDF at `point`, its directions local to `frame` (the shading normal's): the coat's normal
// in that frame, exactly +z unless a normal map bent the shading normal away from it.
Bsdf bsdfOf(const SurfacePoint& point, const Frame& frame) {
    const Material& m = *point.material;
    Bsdf b{point.albedo,    point.metallic,        point.roughness,          m.specular, toVec(m.specularColor),
           point.clearcoat, point.clearcoatRoughness, iorF0(m.ior)};
    if (point.clearcoat > 0.0f && !(point.coatNormal == point.shadingNormal))
        b.coatNormal = normalize(frame.toLocal(point.coatNormal));
    return b;
}

// wo in the shading normal's frame, lifted to a grazing 1e-4 when a shading normal turns it
// below the surface.
Vec3f localOutgoing(const Frame& frame, Vec3f wo) {
    Vec3f local = frame.toLocal(wo);
    if (local.z < 1e-4f) local = normalize(Vec3f{local.x, local.y, 1e-4f});
    return local;
}
}  // namespace

Vec3f barycentricPosition(Vec3f v0, Vec3f v1, Vec3f v2, float u, float v) {
    return v0 + (v1 - v0) * u + (v2 - v0) * v;
}

Vec3f geometricNormal(Vec3f v0, Vec3f v1, Vec3f v2) { return cross(v1 - v0, v2 - v0); }

const Material& materialAt(std::span<const Material> materials, uint32_t id) {
    return id < materials.size() ? materials[id] : materials[0];
}

HitAttributes hitAttributes(std::span<const uint32_t> normals, std::span<const uint32_t> colors, uint32_t i0,
                            uint32_t i1, uint32_t i2, float u, float v) {
    HitAttributes a;
    if (!normals.empty()) a.normal = interpolateNormal(normals[i0], normals[i1], normals[i2], u, v);
    if (!colors.empty()) a.color = interpolateColor(colors[i0], colors[i1], colors[i2], u, v);
    return a;
}

MaterialSample materialFactors(const Material& m) {
    MaterialSample s{baseColor(m), m.metallic, m.roughness, toVec(m.emissive)};
    s.clearcoat = m.clearcoat, s.clearcoatRoughness = m.clearcoatRoughness;
    return s;
}

MaterialSample sampleMaterial(const Material& m, std::span<const DecodedTexture> textures, std::array<float, 2> uv,
                              const MapFootprint* footprint) {
    MaterialSample s = materialFactors(m);
    auto map = [&](TextureSlot slot, TextureSample* out) {
        const TextureBinding& b = m.textures.slots[uint32_t(slot)];
        if (b.texture == kNoTexture || b.texture >= textures.size()) return false;
        float u = 0.0f, v = 0.0f;
        applyUvTransform(b.transform, uv[0], uv[1], u, v);
        const DecodedTexture& texture = textures[b.texture];
        const float lod =
            footprint ? mapLod(b.transform, texture.layout.width, texture.layout.height, *footprint) : 0.0f;
        *out = sampleTexture(texture, u, v, lod);
        return true;
    };
    TextureSample t;
    if (map(TextureSlot::BaseColor, &t)) s.baseColor = mul(s.baseColor, Vec3f{t.r, t.g, t.b});
    if (map(TextureSlot::MetallicRoughness, &t)) {
        s.roughness *= t.g;
        s.metallic *= t.b;
    }
    if (map(TextureSlot::Emissive, &t)) s.emissive = mul(s.emissive, Vec3f{t.r, t.g, t.b});
    // A coat weight of 0 stays 0: no coat, its maps are not read (the device's material records drop them).
    if (s.clearcoat > 0.0f && map(TextureSlot::Clearcoat, &t)) s.clearcoat *= t.r;
    if (s.clearcoat > 0.0f && map(TextureSlot::ClearcoatRoughness, &t)) s.clearcoatRoughness *= t.g;
    if (map(TextureSlot::Normal, &t)) {
        s.normalMapped = true;
        s.tangentNormal = decodeNormalTexel(t.r, t.g, t.b, m.textures.normalScale);
    }
    return s;
}

bool isCutout(const Material& m, uint64_t textureCount) {
    const uint32_t map = m.textures.slots[uint32_t(TextureSlot::BaseColor)].texture;
    return m.alphaCutoff > 0.0f && map != kNoTexture && map < textureCount;
}

bool cutOut(const Material& m, std::span<const DecodedTexture> textures, std::array<float, 2> uv) {
    if (!isCutout(m, textures.size())) return false;
    const TextureBinding& b = m.textures.slots[uint32_t(TextureSlot::BaseColor)];
    float u = 0.0f, v = 0.0f;
    applyUvTransform(b.transform, uv[0], uv[1], u, v);
    return m.baseColor[3] * sampleTexture(textures[b.texture], u, v, 0.0f).a < m.alphaCutoff;
}

bool isBlended(const Material& m, uint64_t textureCount) {
    const uint32_t map = m.textures.slots[uint32_t(TextureSlot::BaseColor)].texture;
    return m.alphaBlend && (m.baseColor[3] < 1.0f || (map != kNoTexture && map < textureCount));
}

bool isAlphaTested(const Material& m, uint64_t textureCount) {
    return isCutout(m, textureCount) || isBlended(m, textureCount);
}

uint32_t alphaRayBase(RandomKey key, bool shadow, uint32_t seed) {
    return randomBits(key, kDimAlpha, seed) ^ (shadow ? kShadowAlphaSalt : 0u);
}

float alphaCoin(uint32_t rayBase, uint32_t primitive) {
    return float(pcgHash(rayBase ^ primitive) >> 8u) * (1.0f / 16777216.0f);
}

bool alphaDiscards(const Material& m, std::span<const DecodedTexture> textures, std::array<float, 2> uv,
                   uint32_t rayBase, uint32_t primitive) {
    if (!isBlended(m, textures.size())) return cutOut(m, textures, uv);
    float alpha = m.baseColor[3];
    const TextureBinding& b = m.textures.slots[uint32_t(TextureSlot::BaseColor)];
    if (b.texture != kNoTexture && b.texture < textures.size()) {
        float u = 0.0f, v = 0.0f;
        applyUvTransform(b.transform, uv[0], uv[1], u, v);
        alpha *= sampleTexture(textures[b.texture], u, v, 0.0f).a;
    }
    return !(alphaCoin(rayBase, primitive) < alpha);
}

SurfacePoint makeSurfacePoint(Vec3f position, Vec3f geometric, Vec3f rayDirection, const Material& material,
                              HitAttributes attributes, const MaterialSample* sample,
                              const UvDerivatives* uvDerivatives) {
    SurfacePoint point;
    point.position = position;
    const Vec3f front = normalize(geometric);
    point.normal = dot(front, rayDirection) > 0.0f ? front * -1.0f : front;
    point.shadingNormal = point.coatNormal = point.normal;
    const bool interpolated = attributes.normal != kNoNormal;
    const bool bent = sample && sample->normalMapped && uvDerivatives && uvDerivatives->valid;
    if (interpolated || bent) {
        // The map bends the front side's normal; the turn to the ray's side is the unbent one's.
        Vec3f n = interpolated ? decodeOctahedral(attributes.normal) : front;
        const bool turn = dot(n, point.normal) < 0.0f;
        point.coatNormal = turn ? n * -1.0f : n;
        if (bent) n = perturbNormal(n, *uvDerivatives, sample->tangentNormal);
        point.shadingNormal = turn ? n * -1.0f : n;
    }
    const MaterialSample factors = sample ? *sample : materialFactors(material);
    point.albedo = mul(factors.baseColor, unpackHitColor(attributes.color));
    point.metallic = factors.metallic;
    point.roughness = factors.roughness;
    point.clearcoat = factors.clearcoat, point.clearcoatRoughness = factors.clearcoatRoughness;
    point.emissive = factors.emissive;
    point.outgoing = rayDirection * -1.0f;
    point.glossy = !isLambertian(material);
    point.material = &material;
    return point;
}

Vec3f skyRadiance(const Environment& env, Vec3f direction) {
    if (env.map) return environmentRadiance(*env.map, environmentFrame(env.up, env.mapRotationDegrees), direction);
    const float height = dot(direction, env.up);
    if (height < 0.0f) return toVec(env.ground);
    const Vec3f horizon = toVec(env.horizon);
    return horizon + (toVec(env.zenith) - horizon) * height;
}

Vec3f emission(const Material& m) { return toVec(m.emissive); }
Vec3f baseColor(const Material& m) { return {m.baseColor[0], m.baseColor[1], m.baseColor[2]}; }

bool reflectedLight(const SurfacePoint& point, Vec3f direction, Vec3f irradiance, Vec3f* light) {
    const float cosine = dot(point.shadingNormal, direction);
    if (maxComponent(irradiance) <= 0.0f || cosine <= 0.0f || dot(point.normal, direction) <= 0.0f) return false;
    if (point.glossy) {
        float pdf;
        *light = mul(glossyReflection(point, direction, &pdf), irradiance);
        return maxComponent(*light) > 0.0f;
    }
    *light = mul(point.albedo, irradiance) * (cosine / kPi);
    return true;
}

bool lightSampleReflection(const SurfacePoint& point, Vec3f direction, Vec3f radiance, float lightPdf, Vec3f* light) {
    const float cosine = dot(point.shadingNormal, direction);
    if (cosine <= 0.0f || dot(point.normal, direction) <= 0.0f) return false;
    if (point.glossy) {
        float bsdfPdf;
        const Vec3f reflection = glossyReflection(point, direction, &bsdfPdf);
        *light = mul(reflection, radiance) * (powerHeuristic(lightPdf, bsdfPdf) / lightPdf);
        return maxComponent(*light) > 0.0f;
    }
    const float weight = powerHeuristic(lightPdf, cosine / kPi) / lightPdf;
    *light = mul(point.albedo, radiance) * ((cosine / kPi) * weight);
    return true;
}

bool unshadowedSunLight(const Environment& env, Vec3f sunDirection, const SurfacePoint& point, Vec3f* light) {
    return reflectedLight(point, sunDirection, toVec(env.sunIrradiance), light);
}

float punctualPickProbability(const Environment& env, std::span<const LightEntry> lights) {
    if (lights.empty()) return 0.0f;
    const bool sun = maxComponent(toVec(env.sunIrradiance)) > 0.0f;
    return sun || (env.map && env.map->sampleable) ? 0.5f : 1.0f;
}

LightChoice choosePunctualLight(std::span<const LightEntry> lights, float punctualPick, Vec3f origin, RandomKey key,
                                uint32_t seed, Vec3f* direction, float* distance, Vec3f* irradiance) {
    if (!(punctualPick > 0.0f)) return LightChoice::Environment;
    const float u = randomFloat(key, kDimPunctual, seed);
    if (!(u < punctualPick)) return LightChoice::Environment;
    const LightEntry& light = lights[pickLight(lights, u / punctualPick)];
    if (!lightAt(light, origin, direction, distance, irradiance)) return LightChoice::None;
    *irradiance = *irradiance * (1.0f / (punctualPick * light.pick));
    return LightChoice::Punctual;
}

float sunPickProbability(const Environment& env) {
    if (!env.map || !env.map->sampleable) return 1.0f;
    return maxComponent(toVec(env.sunIrradiance)) > 0.0f ? 0.5f : 0.0f;
}

bool unshadowedDirectLight(const Environment& env, Vec3f sunDirection, const SurfacePoint& point, RandomKey key,
                           uint32_t seed, Vec3f* light, Vec3f* direction) {
    const float pickSun = sunPickProbability(env);
    if (pickSun >= 1.0f || (pickSun > 0.0f && randomFloat(key, kDimLightPick, seed) < pickSun)) {
        if (!unshadowedSunLight(env, sunDirection, point, light)) return false;
        if (pickSun < 1.0f) *light = *light * (1.0f / pickSun);
        *direction = sunDirection;
        return true;
    }
    const EnvironmentSample s = sampleEnvironment(*env.map, environmentFrame(env.up, env.mapRotationDegrees),
                                                  randomFloat(key, kDimLightU, seed), randomFloat(key, kDimLightV, seed));
    if (!(s.pdf > 0.0f)) return false;
    *direction = s.direction;
    return lightSampleReflection(point, s.direction, s.radiance, (1.0f - pickSun) * s.pdf, light);
}

bool unshadowedMediumLight(const Environment& env, Vec3f sunDirection, Vec3f travel, float g, RandomKey key,
                           uint32_t seed, Vec3f* light, Vec3f* direction) {
    const float pickSun = sunPickProbability(env);
    if (pickSun >= 1.0f || (pickSun > 0.0f && randomFloat(key, kDimLightPick, seed) < pickSun)) {
        const Vec3f irradiance = toVec(env.sunIrradiance);
        if (!(maxComponent(irradiance) > 0.0f)) return false;
        *light = irradiance * (henyeyGreenstein(g, travel, sunDirection) / pickSun);
        *direction = sunDirection;
        return true;
    }
    const EnvironmentSample s = sampleEnvironment(*env.map, environmentFrame(env.up, env.mapRotationDegrees),
                                                  randomFloat(key, kDimLightU, seed), randomFloat(key, kDimLightV, seed));
    if (!(s.pdf > 0.0f)) return false;
    const float phase = henyeyGreenstein(g, travel, s.direction);
    const float lightPdf = (1.0f - pickSun) * s.pdf;
    *light = s.radiance * (phase * powerHeuristic(lightPdf, phase) / lightPdf);
    *direction = s.direction;
    return true;
}

float environmentHitWeight(const Environment& env, Vec3f direction, float bouncePdf) {
    if (bouncePdf <= 0.0f || !env.map || !env.map->sampleable) return 1.0f;
    const Frame frame = environmentFrame(env.up, env.mapRotationDegrees);
    return powerHeuristic(bouncePdf, (1.0f - sunPickProbability(env)) * environmentPdf(*env.map, frame, direction));
}

float emitterPickProbability(const Environment& env, std::span<const LightEntry> lights, const EmitterTable* emitters) {
    if (!emitters || emitters->entries.empty()) return 0.0f;
    const bool sun = maxComponent(toVec(env.sunIrradiance)) > 0.0f;
    return sun || (env.map && env.map->sampleable) || !lights.empty() ? 0.5f : 1.0f;
}

bool sampleEmitter(const EmitterTable& table, std::span<const Material> materials,
                   std::span<const DecodedTexture> textures, float emitterPick, Vec3f origin, RandomKey key,
                   uint32_t seed, EmitterSample* sample) {
    const EmitterEntry& e = table.entries[pickEmitter(table, randomBits(key, kDimEmitterPick, seed),
                                                      randomFloat(key, kDimEmitterKeep, seed))];
    const float u1 = randomFloat(key, kDimEmitterU, seed), u2 = randomFloat(key, kDimEmitterV, seed);
    const Vec3f y = emitterPoint(e, u1, u2);
    const Material& m = materialAt(materials, e.material);
    const Vec3f front = normalize(geometricNormal(e.v0, e.v1, e.v2));
    const bool frontSeen = dot(front, origin - y) > 0.0f;
    if (!frontSeen && !m.doubleSided) return false;
    const Vec3f facing = frontSeen ? front : front * -1.0f;
    const Vec3f toPoint = offsetRayOrigin(y, facing) - origin;
    const float squared = dot(toPoint, toPoint);
    if (!(squared > 0.0f)) return false;
    sample->distance = std::sqrt(squared);
    sample->direction = toPoint * (1.0f / sample->distance);
    const float cosine = -dot(facing, sample->direction);
    if (!(cosine > 0.0f)) return false;
    sample->radiance = emission(m);
    const TextureBinding& map = m.textures.slots[uint32_t(TextureSlot::Emissive)];
    if (map.texture != kNoTexture && map.texture < textures.size()) {
        const std::array<float, 2> uv = emitterUv(e, u1, u2);
        float u = 0.0f, v = 0.0f;
        applyUvTransform(map.transform, uv[0], uv[1], u, v);
        const TextureSample t = sampleTexture(textures[map.texture], u, v, 0.0f);
        sample->radiance = mul(sample->radiance, Vec3f{t.r, t.g, t.b});
    }
    sample->pdf = emitterPick * table.areaDensity[e.material] * (squared / cosine);
    return sample->pdf > 0.0f;
}

bool emitterSurfaceLight(const SurfacePoint& point, const EmitterSample& s, Vec3f* light) {
    return lightSampleReflection(point, s.direction, s.radiance, s.pdf, light);
}

Vec3f emitterMediumLight(const EmitterSample& s, Vec3f travel, float g) {
    const float phase = henyeyGreenstein(g, travel, s.direction);
    return s.radiance * (phase * powerHeuristic(s.pdf, phase) / s.pdf);
}

float emitterHitWeight(float emitterPick, float areaDensity, float t, float cosine, float bouncePdf) {
    if (bouncePdf <= 0.0f || !(areaDensity > 0.0f) || !(emitterPick > 0.0f)) return 1.0f;
    return powerHeuristic(bouncePdf, emitterPick * areaDensity * (t * t / cosine));
}

Vec3f cosineDirection(Vec3f normal, RandomKey key, uint32_t seed) {
    const float u1 = randomFloat(key, kDimDirectionU, seed);
    const float u2 = randomFloat(key, kDimDirectionV, seed);
    return normalize(frameAround(normal).toWorld(cosineHemisphere(u1, u2)));
}

bool bounceDirection(const SurfacePoint& point, RandomKey key, uint32_t seed, Vec3f* direction) {
    *direction = cosineDirection(point.shadingNormal, key, seed);
    return dot(*direction, point.normal) > 0.0f;
}

Vec3f glossyReflection(const SurfacePoint& point, Vec3f wi, float* pdf) {
    *pdf = 0.0f;
    if (dot(point.shadingNormal, wi) <= 0.0f || dot(point.normal, wi) <= 0.0f) return {0, 0, 0};
    const Frame frame = frameAround(point.shadingNormal);
    const Vec3f wo = localOutgoing(frame, point.outgoing);
    const Vec3f local = frame.toLocal(wi);
    const BsdfValue v = evalBsdf(bsdfOf(point, frame), wo, local, microfacetTables().data());
    *pdf = v.pdf;
    return v.f * local.z;
}

bool scatterSurface(const SurfacePoint& point, RandomKey key, uint32_t seed, Vec3f* direction, Vec3f* weight,
                    float* pdf) {
    const Frame frame = frameAround(point.shadingNormal);
    Vec3f local;
    if (!sampleBsdf(bsdfOf(point, frame), localOutgoing(frame, point.outgoing), randomFloat(key, kDimLobe, seed),
                    randomFloat(key, kDimDirectionU, seed), randomFloat(key, kDimDirectionV, seed),
                    microfacetTables().data(), &local, weight, pdf))
        return false;
    *direction = normalize(frame.toWorld(local));
    return dot(*direction, point.normal) > 0.0f;
}

bool surviveRoulette(Vec3f& throughput, uint32_t bounce, RandomKey key, uint32_t seed) {
    if (bounce + 1 < kRouletteStartBounce) return true;
    const float survival = std::fmin(kMaxSurvival, maxComponent(throughput));
    if (!(randomFloat(key, kDimRoulette, seed) < survival)) return false;
    throughput = throughput * (1.0f / survival);
    return true;
}

}  // namespace vastray
