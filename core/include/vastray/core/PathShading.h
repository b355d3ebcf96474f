#pragma once
// The shading steps of the `path` and `ao` integrators (docs/RENDERING.md), shared by every
// backend: the Embree reference calls them per sample, the streaming renderer per wavefront.
// Given the same hits, both therefore produce the same floats.
#include <array>
#include <cstdint>
#include <span>

#include "vastray/core/Emitters.h"
#include "vastray/core/Light.h"
#include "vastray/core/Mesh.h"
#include "vastray/core/NormalMap.h"
#include "vastray/core/Random.h"
#include "vastray/core/RayCone.h"
#include "vastray/core/RenderOptions.h"
#include "vastray/core/Texture.h"
#include "vastray/core/Vec3.h"
#include "vastray/core/VertexAttributes.h"

namespace vastray {

// Russian roulette starts after this many scattering events; before it every path
// continues, so shallow --max-depth renders carry no roulette noise.
constexpr uint32_t kRouletteStartBounce = 3;
constexpr float kMaxSurvival = 0.95f;

struct SurfacePoint {
    Vec3f position;  // from barycentrics (more exact than origin + t * direction)
    Vec3f normal;    // unit geometric normal, on the side the ray came from
    // Unit shading normal on the same side (the geometric one without vertex normals; bent by
    // the material's normal map where it has one): the Lambertian cosines and the bounce use it;
    // light and bounces below `normal` are cut.
    Vec3f shadingNormal;
    // The clear coat's normal: the shading normal before the normal map bent it (glTF: a base
    // normal map does not apply to the coat); shadingNormal itself where no map bends it.
    Vec3f coatNormal;
    Vec3f albedo;    // base colour (times its map) times the vertex colour
    // The material's factors times their maps where it has them (MaterialSample).
    float metallic = 0.0f, roughness = 1.0f;
    float clearcoat = 0.0f, clearcoatRoughness = 0.0f;
    Vec3f emissive;  // radiance
    Vec3f outgoing;  // unit, towards where the ray came from
    // Not the Lambertian base alone (core/Microfacet.h): the metallic-roughness BSDF's steps
    // replace the Lambertian ones (docs/RENDERING.md, "Materials").
    bool glossy = false;
    const Material* material = nullptr;
};

// A hit's interpolated attributes as the hit record keeps them (core/VertexAttributes.h):
// kNoNormal and white (every 10-bit channel 1023) when the scene has none.
constexpr uint32_t kWhiteHitColor = 0x3FFFFFFFu;
struct HitAttributes {
    uint32_t normal = kNoNormal;
    uint32_t color = kWhiteHitColor;
};
// The attributes at barycentrics (u, v) of a triangle whose corners are vertices i0, i1, i2
// of per-vertex `normals` and `colors` (either may be empty).
HitAttributes hitAttributes(std::span<const uint32_t> normals, std::span<const uint32_t> colors, uint32_t i0,
                            uint32_t i1, uint32_t i2, float u, float v);

// What a material's maps give at a hit (docs/RENDERING.md, "Textures", glTF 2.0's
// metallic-roughness model): the base colour factor times the base colour map (sRGB decoded,
// linear RGB), the metallic and roughness factors times the metallic-roughness map's B and G
// channels, the emissive factor times the emissive map, and the normal map's tangent-space
// normal (linear texels, decodeNormalTexel with the material's normal scale; makeSurfacePoint
// bends the shading normal with it: "Normal maps"). `uv` is the hit's; each map's
// KHR_texture_transform applies to it. Each map is sampled at the level the hit's `footprint`
// asks for (mapLod: "Texture level of detail"), or at level 0 when footprint is null. A material without maps gives its factors. Occlusion
// maps are stored but not applied, by design: a path tracer finds the occlusion itself, and a
// baked map would count it twice (as Mitsuba 3 and Cycles do, they are ignored).
struct MaterialSample {
    Vec3f baseColor;
    float metallic = 0.0f, roughness = 1.0f;
    Vec3f emissive;
    // KHR_materials_clearcoat: the coat's weight times its map's R, its roughness times its
    // roughness map's G (the factors without maps).
    float clearcoat = 0.0f, clearcoatRoughness = 0.0f;
    bool normalMapped = false;        // the material has a normal map
    Vec3f tangentNormal{0, 0, 1};     // its decoded texel, when normalMapped
};
MaterialSample sampleMaterial(const Material& material, std::span<const DecodedTexture> textures,
                              std::array<float, 2> uv, const MapFootprint* footprint);
// The factors alone.
MaterialSample materialFactors(const Material& material);
// Whether `material` is a cut-out: an alphaCutoff above 0 and a base colour map among the scene's
// `textureCount` textures (docs/RENDERING.md, "Cut-outs").
bool isCutout(const Material& material, uint64_t textureCount);
// Cut-outs (docs/RENDERING.md, "Cut-outs"): whether a hit at `uv` on a triangle of `material`
// is no hit: its alphaCutoff is above 0, it has a base colour map, and baseColor[3] times the
// map's alpha at level 0 (the map's UV transform applied) is below the cutoff.
bool cutOut(const Material& material, std::span<const DecodedTexture> textures, std::array<float, 2> uv);

// Blending (docs/RENDERING.md, "Blending"): whether `material` blends, with some
// alpha below 1 (its factor's, or a base colour map among `textureCount` textures).
bool isBlended(const Material& material, uint64_t textureCount);
// Whether the walk must test hits on `material` at all: a cut-out or a blend.
bool isAlphaTested(const Material& material, uint64_t textureCount);
// A ray's key for its coins: randomBits(key, kDimAlpha, seed), with a shadow ray's bits flipped by
// kShadowAlphaSalt (a path's shadow ray and its bounce at one event draw different coins).
constexpr uint32_t kShadowAlphaSalt = 0x9E3779B9u;
uint32_t alphaRayBase(RandomKey key, bool shadow, uint32_t seed);
// The coin of the ray keyed `rayBase` for the triangle of primitive id `primitive`:
// float(pcgHash(rayBase ^ primitive) >> 8) * 2^-24, in [0, 1).
float alphaCoin(uint32_t rayBase, uint32_t primitive);
// Whether the hit at `uv` on primitive `primitive` of `material` is no hit: cut out (cutOut), or
// blended with the coin at or above its alpha (baseColor[3] times the base colour map's alpha at
// level 0).
bool alphaDiscards(const Material& material, std::span<const DecodedTexture> textures, std::array<float, 2> uv,
                   uint32_t rayBase, uint32_t primitive);

// v0 + (v1 - v0) * u + (v2 - v0) * v, evaluated in exactly this order (the GPU kernel too).
Vec3f barycentricPosition(Vec3f v0, Vec3f v1, Vec3f v2, float u, float v);
// cross(v1 - v0, v2 - v0), not normalized.
Vec3f geometricNormal(Vec3f v0, Vec3f v1, Vec3f v2);
// The material a triangle's id names; out-of-range ids fall back to material 0.
const Material& materialAt(std::span<const Material> materials, uint32_t id);
// Normalizes `geometricNormal` and turns it towards the side `rayDirection` came from; the
// shading normal is the hit's (turned to that side too) or the geometric one.
// `sample` (sampleMaterial; the factors alone when null) gives the point's base colour, metallic,
// roughness and emission. With a normal-mapped sample and valid `uvDerivatives` (the hit
// triangle's, core/NormalMap.h), the front-side shading normal is first bent by the map
// (perturbNormal), then turned to the ray's side exactly when the unbent one is.
SurfacePoint makeSurfacePoint(Vec3f position, Vec3f geometricNormal, Vec3f rayDirection,
                              const Material& material, HitAttributes attributes = {},
                              const MaterialSample* sample = nullptr,
                              const UvDerivatives* uvDerivatives = nullptr);

// The environment's radiance towards unit `direction`: the map's, or the sky's.
Vec3f skyRadiance(const Environment& environment, Vec3f direction);
Vec3f emission(const Material& material);
Vec3f baseColor(const Material& material);

// The sun's unshadowed Lambertian reflection at `point` in *light. Returns false (no shadow
// ray needed, no light) when there is no sun or the surface faces away from it. sunDirection: unit.
bool unshadowedSunLight(const Environment& environment, Vec3f sunDirection, const SurfacePoint& point,
                        Vec3f* light);

// The light reflected at `point` from unit `direction` (towards the light) by `irradiance` arriving
// on a surface facing it (Lambertian, or the metallic-roughness BSDF). false: none (the light lies
// below either normal).
bool reflectedLight(const SurfacePoint& point, Vec3f direction, Vec3f irradiance, Vec3f* light);
// The light reflected at `point` from `radiance` arriving along unit `direction`, which a light
// sampler drew with solid-angle density `lightPdf` (> 0), weighted by the power heuristic against
// the bounce's density there (cos / pi, or the glossy BSDF's): f cos radiance w / lightPdf. false:
// none (below either normal). The environment map's and the emitters' next-event estimation.
bool lightSampleReflection(const SurfacePoint& point, Vec3f direction, Vec3f radiance, float lightPdf, Vec3f* light);

// The probability with which next-event estimation picks a punctual light rather than the sun or
// the environment map: 0 without lights, 1 when neither the sun nor a map brings light, else 1/2
// (docs/RENDERING.md, "Lights").
float punctualPickProbability(const Environment& environment, std::span<const LightEntry> lights);

// Next-event estimation's first choice at `origin` (kDimPunctual): Environment (the sun or the
// map, as unshadowedDirectLight and unshadowedMediumLight pick them, their light then divided by
// 1 - punctualPick), Punctual (a light of `lights` by its pick probability: *direction, *distance
// and *irradiance at origin, the irradiance divided by both probabilities), or None (a punctual
// light was picked and brings nothing here).
enum class LightChoice { Environment, Punctual, None };
LightChoice choosePunctualLight(std::span<const LightEntry> lights, float punctualPick, Vec3f origin, RandomKey key,
                                uint32_t seed, Vec3f* direction, float* distance, Vec3f* irradiance);

// The probability with which next-event estimation picks the sun: 1 without an environment
// map that has light, 0 without a sun, else 1/2 (docs/RENDERING.md, "Lights").
float sunPickProbability(const Environment& environment);

// Next-event estimation at `point`: picks the sun or the environment map (kDimLightPick, only
// when both shine) and returns the light it brings if its shadow ray, towards *direction, is
// unblocked: the sun's divided by its pick probability; the map's (a direction drawn from its
// density, kDimLightU/V) weighted against the Lambertian bounce by the power heuristic. false:
// no shadow ray (no light, or the direction lies below the surface). sunDirection: unit.
bool unshadowedDirectLight(const Environment& environment, Vec3f sunDirection, const SurfacePoint& point,
                           RandomKey key, uint32_t seed, Vec3f* light, Vec3f* direction);
// Next-event estimation at a point inside a volume, for light arriving along unit `travel` and
// scattered by a Henyey-Greenstein phase function of anisotropy g: as unshadowedDirectLight,
// with the phase function in place of the Lambertian reflection (and its density in the power
// heuristic). The volume's albedo is not applied. false: no light to send a shadow ray for.
bool unshadowedMediumLight(const Environment& environment, Vec3f sunDirection, Vec3f travel, float g, RandomKey key,
                           uint32_t seed, Vec3f* light, Vec3f* direction);
// The weight of the environment's radiance reached by a bounce of solid-angle density
// `bouncePdf` (0: a camera ray, weight 1): with a map that next-event estimation samples, the
// power heuristic against it; else 1.
float environmentHitWeight(const Environment& environment, Vec3f direction, float bouncePdf);

// Emissive triangles (docs/RENDERING.md, "Emissive triangles"). The probability with which
// next-event estimation picks one, before any other choice (kDimEmitter): 0 without `emitters`
// or with an empty table; 1 when nothing else brings light (no sun, no map to sample, no
// punctual lights); else 1/2. The other choices' light is then divided by 1 - it.
float emitterPickProbability(const Environment& environment, std::span<const LightEntry> lights,
                             const EmitterTable* emitters);

// A point next-event estimation drew on an emissive triangle, seen from a shadow ray's origin.
struct EmitterSample {
    Vec3f direction;     // unit, from the origin to the point moved off its triangle towards the origin
    float distance = 0;  // to that point: the shadow ray's tMax
    Vec3f radiance;      // its material's emission there (with an emissive map: the factor times the map)
    float pdf = 0;       // the solid-angle density of the direction, emitterPick included
};
// Picks a triangle (kDimEmitterPick, kDimEmitterKeep) and a point on it (kDimEmitterU/V); a
// material with an emissive map (among `textures`) reads it at the point's UV, level 0. false:
// the point brings nothing to `origin` (its triangle seen edge on, from behind when its material
// is single-sided, or the point at the origin).
bool sampleEmitter(const EmitterTable& table, std::span<const Material> materials,
                   std::span<const DecodedTexture> textures, float emitterPick, Vec3f origin, RandomKey key,
                   uint32_t seed, EmitterSample* sample);
// The light `point` reflects from the sample towards its outgoing direction, weighted by the power
// heuristic against the bounce's density in that direction. false: none (below either normal).
bool emitterSurfaceLight(const SurfacePoint& point, const EmitterSample& sample, Vec3f* light);
// The light a point in a volume scatters from the sample (Henyey-Greenstein g, light travelling
// along `travel` before), weighted as above against the phase function's density.
Vec3f emitterMediumLight(const EmitterSample& sample, Vec3f travel, float g);
// The weight of the emission a bounce of solid-angle density `bouncePdf` (0: a camera ray, weight
// 1) finds at distance t on a triangle whose material has `areaDensity` (EmitterTable; 0: not
// sampled, weight 1), `cosine` its |cos| with the ray: the power heuristic against next-event
// estimation's density emitterPick x areaDensity x t^2 / cosine.
float emitterHitWeight(float emitterPick, float areaDensity, float t, float cosine, float bouncePdf);

// A cosine-distributed direction about `normal`, from the key's direction dimensions.
Vec3f cosineDirection(Vec3f normal, RandomKey key, uint32_t seed);
// The Lambertian bounce at `point`: cosine-distributed about the shading normal; false (the
// path ends) when that direction lies below the geometric surface.
bool bounceDirection(const SurfacePoint& point, RandomKey key, uint32_t seed, Vec3f* direction);

// The metallic-roughness BSDF's reflection of light arriving along unit wi at a glossy point:
// f(wo, wi) cos(shading normal, wi), and in *pdf the density with which scatterSurface draws wi
// (0 and 0 below either normal).
Vec3f glossyReflection(const SurfacePoint& point, Vec3f wi, float* pdf);
// The metallic-roughness bounce at a glossy point (kDimLobe, kDimDirectionU/V): *weight =
// f cos / pdf; false (the path ends) when the drawn direction lies below either normal.
bool scatterSurface(const SurfacePoint& point, RandomKey key, uint32_t seed, Vec3f* direction, Vec3f* weight,
                    float* pdf);

// After scattering event `bounce` (throughput already multiplied by the base colour): from
// kRouletteStartBounce on, ends the path with probability 1 - min(0.95, max throughput) and
// rescales the survivors. Returns whether the path goes on.
bool surviveRoulette(Vec3f& throughput, uint32_t bounce, RandomKey key, uint32_t seed);

}  // namespace vastray
