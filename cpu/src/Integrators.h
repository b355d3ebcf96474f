#pragma once
#include <span>
// Per-sample estimators of the reference renderer. docs/RENDERING.md defines both; a GPU
// backend reproduces them with the same random keys.
#include <cstdint>

#include "vastray/core/Mesh.h"
#include "vastray/core/PathShading.h"
#include "vastray/core/Random.h"
#include "vastray/core/Ray.h"
#include "vastray/core/RenderOptions.h"
#include "vastray/cpu/EmbreeScene.h"

namespace vastray {

struct ShadingContext {
    const TriangleMesh& mesh;
    const EmbreeScene& scene;
    const RenderOptions& options;
    Vec3f sunDirection;  // unit, towards the sun
    std::span<const DecodedTexture> textures;  // the materials' maps' textures (RenderScene::textures)
    // Ray cones (core/RayCone.h): a camera ray's spread (CameraRays::coneSpread) and the most a
    // scattering event adds (kConeScatterSpread); both 0 with --texture-lod finest (level 0).
    float cameraSpread = 0.0f, scatterSpread = 0.0f;
};

// The surface at a hit of a ray whose cone is `cone`: its material's maps sampled at the hit's
// UV, at the level the cone's footprint there asks for (docs/RENDERING.md, "Texture level of
// detail"), when the mesh has UVs.
SurfacePoint surfaceAt(const ShadingContext& context, const SceneHit& hit, Vec3f rayDirection, RayCone cone);

struct SampleResult {
    Vec3f radiance;
    bool cameraRayHit = false;
};

// Rays traced are added to `rays`.
SampleResult tracePath(const ShadingContext& context, Ray ray, RandomKey key, uint64_t& rays);
SampleResult traceAmbientOcclusion(const ShadingContext& context, Ray ray, RandomKey key, uint64_t& rays);

}  // namespace vastray
