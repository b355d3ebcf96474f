#pragma once
// Ray cones (Akenine-Moeller et al., "Improved Shader and Texture Level of Detail Using Ray
// Cones", JCGT 2021): the footprint a path's ray stands for, which picks the texture level its
// maps are sampled at (docs/RENDERING.md, "Texture level of detail"). Every backend takes these
// steps; the GLSL twins are common/Texture.glsl's coneLod and common/MaterialMaps.glsl.
// A cone is its width where its ray starts and its spread angle (small angles: the width at
// distance t is width + spread * t). A camera ray's cone starts at the eye with the angle of a
// pixel (CameraRays::coneSpread); a scattering event keeps the width it had at the event and
// adds a spread that the sampled direction's density sets (scatterSpread), after the OptiX
// Toolkit's demand-texturing heuristic: diffuse scattering (density <= 1/pi) adds
// kConeScatterSpread, a sharper lobe less. Surface curvature is not modelled.
#include <array>

#include "vastray/core/MaterialTextures.h"
#include "vastray/core/Texture.h"
#include "vastray/core/Vec3.h"

namespace vastray {

// The spread (radians) a diffuse scattering event adds to a cone.
constexpr float kConeScatterSpread = 0.25f;

// How a render picks its maps' level of detail (--texture-lod).
enum class TextureLodMode : uint32_t {
    Cone = 0,    // the ray cone's footprint (trilinear between the two levels around it)
    Finest = 1,  // level 0 everywhere (the pixel samples alone filter the texture, as Mitsuba 3 does)
};
const char* textureLodModeName(TextureLodMode mode);

struct RayCone {
    float width = 0.0f;   // where the ray starts
    float spread = 0.0f;  // radians
};

// The cone's width at distance t along its ray: width + spread * t.
inline float coneWidthAt(RayCone cone, float t) { return cone.width + cone.spread * t; }

// The spread a scattering event adds for a sampled direction of solid-angle density `pdf`:
// maxSpread * min(1, 1 / (pi * pdf)); maxSpread when pdf is not a positive finite number.
float scatterSpread(float pdf, float maxSpread);

// The cone after a scattering event at distance t: width coneWidthAt(cone, t), spread plus
// scatterSpread(pdf, maxSpread).
RayCone scatterCone(RayCone cone, float t, float pdf, float maxSpread);

// A hit's footprint as the maps' levels need it: the triangle's world area per unit of UV area
// (|e1 x e2| / |duv1 x duv2| of its stored UVs; 0: the UVs span no area or a value is not
// finite), the cone's width at the hit and the cosine between the ray and the geometric normal.
struct MapFootprint {
    float worldPerUv = 0.0f;
    float coneWidth = 0.0f;
    float cosTheta = 1.0f;
};
float worldPerUvArea(Vec3f p0, Vec3f p1, Vec3f p2, std::array<float, 2> t0, std::array<float, 2> t1,
                     std::array<float, 2> t2);

// The level of a width x height map under UV transform `transform` at `footprint`: textureLod
// with texelArea |det(transform's 2 x 2)| * width * height and worldArea footprint.worldPerUv
// (the ratio of the two areas is what the level needs). 0 for a degenerate footprint.
float mapLod(const UvTransform& transform, uint32_t width, uint32_t height, const MapFootprint& footprint);

}  // namespace vastray
