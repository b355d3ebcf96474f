#pragma once
// One Embree scene over every triangle of a mesh, in robust (watertight) mode, with the
// geometry semantics of docs/GEOMETRY.md: single-sided triangles are invisible from
// behind; where a front face and a back face lie at the same distance the front face wins.
// A material's alpha cut-out (Material::alphaCutoff) makes the hits its map's alpha cuts no hits
// for every query; a blended material's hits are hits with the probability of its alpha, by a coin
// per ray and triangle (docs/RENDERING.md, "Blending"). Embree types stay inside cpu/src.
#include <cstdint>
#include <memory>
#include <span>

#include "vastray/core/Mesh.h"
#include "vastray/core/Ray.h"
#include "vastray/core/Result.h"
#include "vastray/core/Texture.h"

namespace vastray {

struct SceneHit {
    float t = 0;               // along the ray, in units of |direction|
    uint32_t triangle = 0;     // index into the mesh the scene was built from
    float u = 0, v = 0;        // barycentric weights of the triangle's 2nd and 3rd vertex
    bool frontFacing = false;  // dot(direction, cross(v1 - v0, v2 - v0)) < 0
};

class EmbreeScene {
public:
    // Copies positions and indices (and, when a material cuts out or blends, the UVs, materials
    // and primitive ids: RenderScene::primitiveIds, empty for the identity); `mesh` need not
    // outlive the scene, `textures` (the maps' textures, RenderScene::textures) must.
    static Result<std::unique_ptr<EmbreeScene>> build(const TriangleMesh& mesh,
                                                      std::span<const DecodedTexture> textures = {},
                                                      std::span<const uint32_t> primitiveIds = {});
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    // Closest visible hit with t in [0, tMax]; thread-safe. alphaBase: the ray's key for the coins
    // of blended materials (core/PathShading.h alphaRayBase).
    bool intersect(const Ray& ray, float tMax, SceneHit* hit, uint32_t alphaBase = 0) const;
    // Whether any visible triangle lies at t in [0, tMax]; thread-safe.
    bool occluded(const Ray& ray, float tMax, uint32_t alphaBase = 0) const;

private:
    EmbreeScene();
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace vastray
