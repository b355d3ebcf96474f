#pragma once
// The glTF 2.0 metallic-roughness BSDF (docs/RENDERING.md, "Materials"), shared by every
// backend (gpu/shaders/common/Microfacet.glsl does the same steps): a GGX microfacet lobe
// (Trowbridge-Reitz distribution, height-correlated Smith masking, Schlick's Fresnel), made
// energy conserving in two ways, both from tables of directional albedo computed once:
// - the lost multiple scattering is added back as a scale of the single-scattering lobe,
//   1 + F0 (1 / E(mu_o) - 1) (Turquin 2019), so a white metal reflects all it receives;
// - the Lambertian base of a dielectric gets what its specular layer does not reflect,
//   base (1 - s Ed(mu_o)) (1 - s Ed(mu_i)) / (pi (1 - s Ed_avg)) (Kulla and Conty 2017's
//   form), so a white dielectric reflects all it receives whatever its roughness.
// f = (1 - metallic) (s Fresnel(F0) specular + diffuse) + metallic Fresnel(base) specular,
// where s is KHR_materials_specular's factor (0: no specular layer, a Lambertian surface) and
// F0 = min(0.04 specularColor, 1) per channel (its specularColorFactor; 0.04 by default).
// A clear coat (KHR_materials_clearcoat, weight k, its own roughness) lies over all of it:
// f = (1 - k Ec(mu_o)) f_base + k Fresnel(0.04) specular_coat (1 + 0.04 (1 / E - 1)), Ec the
// coat's directional albedo (the Ed table at the coat's roughness): the base gets what the coat
// does not reflect towards the viewer, so a white base under any coat reflects all it receives.
// The coat has a normal of its own (Bsdf::coatNormal): where a normal map bends the base's, the
// coat keeps the unbent one (glTF: a base normal map does not apply to the clear coat). Its lobe,
// albedo and pick are then taken in the coat normal's frame, with the coat lobe's cosine to that
// normal (its f is scaled by cos_coat / cos_base, so that f cos is the coat's own).
// Directions are local: +z is the shading normal, wo points away from the surface (towards
// the viewer), both unit.
#include <cstdint>
#include <string>
#include <vector>

#include "vastray/core/Mesh.h"
#include "vastray/core/Vec3.h"

namespace vastray {

// Entries per side of the albedo tables: cosines 0, 1/31, ..., 1 by roughness 0, 1/31, ..., 1.
constexpr uint32_t kMicrofacetTableSide = 32;
// The tables as one array (what the device reads too): E(mu, roughness), the single-scattering
// lobe's albedo with Fresnel 1; Ed(mu, roughness), the compensated dielectric lobe's albedo
// (F0 0.04, s 1); and per roughness Ed_avg = 2 * integral of Ed(mu) mu dmu over the lookup's
// piecewise-linear Ed, so the diffuse share integrates exactly to what the layer leaves.
constexpr uint32_t kMicrofacetMetalTable = 0;
constexpr uint32_t kMicrofacetDielectricTable = kMicrofacetTableSide * kMicrofacetTableSide;
constexpr uint32_t kMicrofacetAverageTable = 2 * kMicrofacetTableSide * kMicrofacetTableSide;
// Per roughness, 2 * integral of W(mu) mu and of (E + W / E)(mu) mu over the piecewise-linear
// node values, W = the single-scattering albedo of Schlick's weight (1 - cos)^5 alone (derived
// from E and Ed): the average of a layer of any F0 is F0^2 + (1 - F0)^2 W_avg + F0 (1 - F0) M_avg.
constexpr uint32_t kMicrofacetFresnelAverageTable = kMicrofacetAverageTable + kMicrofacetTableSide;
constexpr uint32_t kMicrofacetMixAverageTable = kMicrofacetFresnelAverageTable + kMicrofacetTableSide;
constexpr uint32_t kMicrofacetTableFloats = kMicrofacetMixAverageTable + kMicrofacetTableSide;
// The dielectric layer's normal-incidence reflectance (index of refraction 1.5).
constexpr float kDielectricF0 = 0.04f;
// GGX alpha = roughness^2, at least this (a mirror would need a delta lobe).
constexpr float kMinMicrofacetAlpha = 1e-3f;

// Computed on first use (deterministic quadrature, ~0.1 s), shared by all callers.
const std::vector<float>& microfacetTables();

// Bilinear lookup of a table at cosine mu and roughness, both clamped to [0, 1].
float microfacetTableLookup(const float* table, float mu, float roughness);
// Ed_avg at roughness, linear between the table's rows (exact for the bilinear Ed); with
// `table`, another per-roughness table (kMicrofacetFresnelAverageTable, ...).
float microfacetAverageLookup(const float* tables, float roughness, uint32_t table = kMicrofacetAverageTable);
// The largest KHR_materials_specular specularColorFactor a material may have: F0 saturates at
// 1 from 25 on (0.04 x 25); beyond 1,000 a value is taken for an error in the file.
constexpr float kMaxSpecularColor = 1000.0f;

// KHR_materials_ior's largest index of refraction (F0 0.996); beyond it a value is taken for an
// error in the file.
constexpr float kMaxIor = 1000.0f;
// The dielectric layer's F0 for index of refraction `ior` (Material::ior): ((ior - 1) / (ior + 1))^2,
// exactly kDielectricF0 at 1.5 (so that the default material's steps are the ones before the
// extension), 1 at 0.
float iorF0(float ior);

struct Bsdf {
    Vec3f base;          // base colour times the vertex colour
    float metallic = 0;  // [0, 1]
    float roughness = 1; // [0, 1], perceptual (alpha = roughness^2)
    float specular = 0;  // [0, 1], the dielectric layer's weight
    Vec3f specularColor{1, 1, 1};  // [0, kMaxSpecularColor]: the layer's F0 is min(dielectricF0 this, 1)
    float clearcoat = 0;           // [0, 1], the coat's weight (0: none)
    float clearcoatRoughness = 0;  // [0, 1], perceptual
    float dielectricF0 = kDielectricF0;  // the layer's, iorF0(Material::ior); the coat's is kDielectricF0
    // The coat's normal in the same local frame, unit: exactly +z unless the coat's normal differs
    // from the shading normal (a base normal map; then every step is the one before coat normals).
    Vec3f coatNormal{0, 0, 1};
};

// "metallic 1.5 is outside [0, 1]" for the first factor that is not a fraction (or a specular
// colour channel outside [0, kMaxSpecularColor]); empty when all are.
std::string materialFactorProblem(const Material& m);

// Whether the material is the Lambertian base alone (no specular layer, not metallic): such
// surfaces take the cosine-sampled Lambertian steps of core/PathShading.h unchanged.
inline bool isLambertian(const Material& m) {
    return m.metallic <= 0.0f && m.specular <= 0.0f && m.clearcoat <= 0.0f;
}

// f(wo, wi) (without the cosine) and the solid-angle density with which sampleBsdf draws wi.
struct BsdfValue {
    Vec3f f{0, 0, 0};
    float pdf = 0;
};
// Both from one evaluation of the lobe and one lookup of each table (next-event estimation
// needs both); 0 when either direction lies below the surface.
BsdfValue evalBsdf(const Bsdf& bsdf, Vec3f wo, Vec3f wi, const float* tables);
// Draws wi: with a coat, the coat's lobe with probability k Ec / (k Ec + (1 - k Ec) a_base)
// (uLobe below it), else uLobe rescaled picks as without a coat: the specular lobe (GGX visible
// normals, Dupuy and Benyoub 2023's spherical caps) with a probability from the lobes' albedos,
// else the cosine-weighted diffuse one;
// *weight = f cos / pdf, *pdf the mixture's density (evalBsdf's, from the same lookups).
// false: no direction (below the surface).
bool sampleBsdf(const Bsdf& bsdf, Vec3f wo, float uLobe, float u1, float u2, const float* tables, Vec3f* wi,
                Vec3f* weight, float* pdf);

}  // namespace vastray
