#pragma once
// One Embree scene over every triangle of a mesh, in robust (watertight) mode, with the
// geometry semantics of docs/GEOMETRY.md: single-sided triangles are invisible from
// behind; where a front face and a back face lie at the same distance the front face wins.
// Embree types stay inside cpu/src.
#include <cstdint>
#include <memory>

#include "vastray/core/Mesh.h"
#include "vastray/core/Ray.h"
#include "vastray/core/Result.h"

namespace vastray {

struct SceneHit {
    float t = 0;               // along the ray, in units of |direction|
    uint32_t triangle = 0;     // index into the mesh the scene was built from
    float u = 0, v = 0;        // barycentric weights of the triangle's 2nd and 3rd vertex
    bool frontFacing = false;  // dot(direction, cross(v1 - v0, v2 - v0)) < 0
};

class EmbreeScene {
public:
    // Copies positions and indices; `mesh` need not outlive the scene.
    static Result<std::unique_ptr<EmbreeScene>> build(const TriangleMesh& mesh);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    // Closest visible hit with t in [0, tMax]; thread-safe.
    bool intersect(const Ray& ray, float tMax, SceneHit* hit) const;
    // Whether any visible triangle lies at t in [0, tMax]; thread-safe.
    bool occluded(const Ray& ray, float tMax) const;

private:
    EmbreeScene();
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace vastray
