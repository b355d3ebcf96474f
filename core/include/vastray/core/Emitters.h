#pragma once
// Emissive triangles as lights that next-event estimation samples (docs/RENDERING.md, "Emissive
// triangles"). A package stores its emissive triangles (the positions the renderer sees, and the
// material); every backend makes the same table from them: a triangle is picked with
// probability in proportion to its area times its emission's largest component, by Vose's alias
// method (one 32-bit random word picks the column, a float decides between it and its alias),
// then a uniform point on it. The density of a point so drawn, per unit area, depends only on
// its material: areaDensity[material] = max(emissive) / sum over the table of area x
// max(emissive); a hit on an emitter therefore finds next-event estimation's density from its
// material, its distance and its cosine alone (no table lookup), for multiple importance sampling.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "vastray/core/Mesh.h"
#include "vastray/core/Vec3.h"

namespace vastray {

// The most emissive triangles a package samples; a scene with more keeps them all as geometry,
// hit by chance only (import says so).
constexpr uint32_t kMaxEmitters = 1u << 22;

struct EmissiveTriangle {
    Vec3f v0, v1, v2;  // world space, exactly as the renderer's triangle
    uint32_t material = 0;
    // The corners' UVs (the mesh's; (0, 0) without any): where a point drawn on the triangle reads
    // its material's emissive map.
    std::array<float, 2> t0{}, t1{}, t2{};
};

// Whether next-event estimation samples triangles of `material` (among a scene's `textureCount`
// textures): it emits (a channel of its emissive factor above 0) and it is neither a cut-out
// (whose holes would shine) nor a blend (which rays meet only with its alpha). A triangle with an
// emissive map is picked by its factor's largest channel, as one without; the point drawn on it
// reads the map (level 0) at its UV.
bool isSampledEmitter(const Material& material, uint64_t textureCount);

// The sampled emitters among `triangles` of `mesh` (all of them when empty), in that order;
// triangles of zero area are left out. Positions are the mesh's.
std::vector<EmissiveTriangle> collectEmitters(const TriangleMesh& mesh, uint64_t textureCount,
                                              std::span<const uint32_t> triangles = {});

// One triangle as the table (and the device's WavefrontEmitter) keeps it: its corners and
// material, and its alias column: kept when u < keep, else `alias` is picked.
struct EmitterEntry {
    Vec3f v0, v1, v2;
    uint32_t material = 0;
    float keep = 1.0f;
    uint32_t alias = 0;
    std::array<float, 2> t0{}, t1{}, t2{};  // the corners' UVs
};

struct EmitterTable {
    std::vector<EmitterEntry> entries;
    // Per material of the scene: the density per unit area of a point next-event estimation
    // draws on one of its triangles, once the emitter branch is chosen; 0 for a material no
    // entry has.
    std::vector<float> areaDensity;
};

// The table of `triangles` (each material index below materials.size(), each material a sampled
// emitter). Triangles of zero weight are left out; no triangle left: an empty table.
EmitterTable makeEmitterTable(std::span<const EmissiveTriangle> triangles, std::span<const Material> materials);

// The entry the alias method picks: column floor(bits x n / 2^32), kept when u < its keep.
uint32_t pickEmitter(const EmitterTable& table, uint32_t bits, float u);

// A uniform point on the entry's triangle from u1, u2 in [0, 1): with s = sqrt(u1), the point
// at barycentrics (u2 s, s - u2 s) (core barycentricPosition), and its UV at those barycentrics
// (core interpolateUv).
Vec3f emitterPoint(const EmitterEntry& entry, float u1, float u2);
std::array<float, 2> emitterUv(const EmitterEntry& entry, float u1, float u2);

}  // namespace vastray
