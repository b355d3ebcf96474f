#pragma once
// Punctual lights (glTF KHR_lights_punctual): directional, point and spot lights in world
// space, and the table next-event estimation picks them from (docs/RENDERING.md, "Lights").
// Units: a directional light's intensity is its irradiance (lux in glTF) on a surface facing
// it, exactly as the sun's (--sun DIR,I has irradiance I * kSunTint); a point or spot light's is
// its radiant intensity (candela in glTF): irradiance I / d^2 at distance d, facing it.
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "vastray/core/Aabb.h"
#include "vastray/core/Result.h"
#include "vastray/core/Vec3.h"

namespace vastray {

enum class LightType : uint32_t { Directional = 0, Point = 1, Spot = 2 };

// Limits every importer and the package reader enforce (validateLight).
constexpr uint32_t kMaxLights = 4096;
constexpr float kMaxLightIntensity = 1e9f;  // lux or candela
constexpr size_t kMaxLightNameBytes = 64;   // as a package stores it (format::kLightNameBytes)

struct PunctualLight {
    std::string name;
    LightType type = LightType::Point;
    std::array<float, 3> color{1.0f, 1.0f, 1.0f};  // linear RGB, each in [0, 1]
    float intensity = 1.0f;                        // [0, kMaxLightIntensity]
    float range = 0.0f;                            // glTF's cut-off distance; 0: none. Not rendered.
    float innerConeAngle = 0.0f;                   // spot only, radians: 0 <= inner < outer <= pi/2
    float outerConeAngle = 0.78539816f;
    Vec3f position{0, 0, 0};   // world space (point, spot)
    Vec3f direction{0, 0, -1}; // world space, unit: where the light shines (directional, spot)
};

const char* lightTypeName(LightType type);

// Every field within its limits (finite, unit direction, cone angles ordered); the message
// names the field and the limit ("intensity 1e+12 is outside [0, 1e9]").
Status validateLight(const PunctualLight& light);

// One light as next-event estimation uses it (the CPU reference reads these floats; the device
// gets the same floats in WavefrontLight): colour times intensity, the spot's cone as glTF's
// smooth falloff (clamp(cos * scale + offset, 0, 1)^2), and its pick probability and the running
// sum of those up to and including it.
struct LightEntry {
    LightType type = LightType::Point;
    Vec3f position{0, 0, 0};
    Vec3f direction{0, 0, -1};
    Vec3f radiant{0, 0, 0};  // color * intensity
    float coneScale = 0.0f, coneOffset = 1.0f;  // spot: 1 / max(1e-3, cos inner - cos outer), -cos outer * scale
    float pick = 0.0f;  // probability of being picked among the lights
    float cdf = 0.0f;   // pick of this light and the lights before it; the last is 1
};

// The lights' table: each picked in proportion to its power (point 4 pi I, spot 2 pi (1 - cos
// outer) I, directional pi R^2 E with R the radius of `bounds`' bounding sphere; the largest
// colour component stands for the colour). Lights of zero power are left out.
std::vector<LightEntry> makeLightTable(std::span<const PunctualLight> lights, const Aabb& bounds);

// The light whose cdf interval holds u in [0, 1): the first entry whose cdf exceeds u (the last
// when rounding leaves none).
uint32_t pickLight(std::span<const LightEntry> table, float u);

// The light of `entry` at `point`: the unit direction towards it, its distance (infinite for a
// directional light) and the irradiance it brings to a surface facing it. false: none (outside
// a spot's cone, or at the light's own position).
bool lightAt(const LightEntry& entry, Vec3f point, Vec3f* direction, float* distance, Vec3f* irradiance);

}  // namespace vastray
