#pragma once
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
};

SurfacePoint surfaceAt(const TriangleMesh& mesh, const SceneHit& hit, Vec3f rayDirection);

struct SampleResult {
    Vec3f radiance;
    bool cameraRayHit = false;
};

// Rays traced are added to `rays`.
SampleResult tracePath(const ShadingContext& context, Ray ray, RandomKey key, uint64_t& rays);
SampleResult traceAmbientOcclusion(const ShadingContext& context, Ray ray, RandomKey key, uint64_t& rays);

}  // namespace vastray
