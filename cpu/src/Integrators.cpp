#include "Integrators.h"

#include <cmath>
#include <limits>

#include "vastray/core/RayOffset.h"
#include "vastray/core/Sampling.h"
#include "vastray/core/VecMath.h"

namespace vastray {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
// Russian roulette starts after this many scattering events; before it every path
// continues, so shallow --max-depth renders carry no roulette noise.
constexpr uint32_t kRouletteStartBounce = 3;
constexpr float kMaxSurvival = 0.95f;

Vec3f toVec(const std::array<float, 3>& c) { return {c[0], c[1], c[2]}; }

Vec3f skyRadiance(const Environment& env, Vec3f direction) {
    if (direction.y < 0.0f) return toVec(env.ground);
    const Vec3f horizon = toVec(env.horizon);
    return horizon + (toVec(env.zenith) - horizon) * direction.y;
}

// Lambertian reflection of the sun at `point` (zero when it faces away or is shadowed).
Vec3f sunLight(const ShadingContext& context, const SurfacePoint& point, Vec3f origin, uint64_t& rays) {
    const Vec3f irradiance = toVec(context.options.environment.sunIrradiance);
    const float cosine = dot(point.normal, context.sunDirection);
    if (maxComponent(irradiance) <= 0.0f || cosine <= 0.0f) return {};
    ++rays;
    if (context.scene.occluded({origin, context.sunDirection}, kInfinity)) return {};
    const auto& base = point.material->baseColor;
    return mul(Vec3f{base[0], base[1], base[2]}, irradiance) * (cosine / kPi);
}

Vec3f cosineDirection(Vec3f normal, RandomKey key, uint32_t seed) {
    const float u1 = randomFloat(key, kDimDirectionU, seed);
    const float u2 = randomFloat(key, kDimDirectionV, seed);
    return normalize(frameAround(normal).toWorld(cosineHemisphere(u1, u2)));
}

}  // namespace

SurfacePoint surfaceAt(const TriangleMesh& mesh, const SceneHit& hit, Vec3f rayDirection) {
    const Vec3f v0 = mesh.positions[mesh.indices[3 * hit.triangle]];
    const Vec3f v1 = mesh.positions[mesh.indices[3 * hit.triangle + 1]];
    const Vec3f v2 = mesh.positions[mesh.indices[3 * hit.triangle + 2]];
    SurfacePoint point;
    point.position = v0 + (v1 - v0) * hit.u + (v2 - v0) * hit.v;
    point.normal = normalize(cross(v1 - v0, v2 - v0));
    if (dot(point.normal, rayDirection) > 0.0f) point.normal = point.normal * -1.0f;
    uint32_t material = mesh.materialOf(hit.triangle);
    if (material >= mesh.materials.size()) material = 0;
    point.material = &mesh.materials[material];
    return point;
}

SampleResult tracePath(const ShadingContext& context, Ray ray, RandomKey key, uint64_t& rays) {
    const RenderOptions& options = context.options;
    SampleResult result;
    Vec3f throughput{1, 1, 1};
    for (uint32_t bounce = 0;; ++bounce) {
        key.bounce = bounce;
        SceneHit hit;
        ++rays;
        if (!context.scene.intersect(ray, kInfinity, &hit)) {
            result.radiance =
                result.radiance + mul(throughput, skyRadiance(options.environment, ray.direction));
            break;
        }
        if (bounce == 0) result.cameraRayHit = true;
        const SurfacePoint point = surfaceAt(context.mesh, hit, ray.direction);
        const auto& e = point.material->emissive;
        result.radiance = result.radiance + mul(throughput, Vec3f{e[0], e[1], e[2]});
        if (bounce == options.maxDepth) break;
        const Vec3f origin = offsetRayOrigin(point.position, point.normal);
        result.radiance = result.radiance + mul(throughput, sunLight(context, point, origin, rays));
        // Cosine sampling of a Lambertian BRDF: f * cos / pdf = base colour.
        const auto& base = point.material->baseColor;
        throughput = mul(throughput, Vec3f{base[0], base[1], base[2]});
        if (bounce + 1 >= kRouletteStartBounce) {
            const float survival = std::fmin(kMaxSurvival, maxComponent(throughput));
            if (!(randomFloat(key, kDimRoulette, options.seed) < survival)) break;
            throughput = throughput * (1.0f / survival);
        }
        ray = {origin, cosineDirection(point.normal, key, options.seed)};
    }
    return result;
}

SampleResult traceAmbientOcclusion(const ShadingContext& context, Ray ray, RandomKey key, uint64_t& rays) {
    SampleResult result;
    SceneHit hit;
    ++rays;
    key.bounce = 0;
    if (!context.scene.intersect(ray, kInfinity, &hit)) {
        result.radiance = {1, 1, 1};
        return result;
    }
    result.cameraRayHit = true;
    const SurfacePoint point = surfaceAt(context.mesh, hit, ray.direction);
    const Vec3f origin = offsetRayOrigin(point.position, point.normal);
    const float range = context.options.aoDistance > 0.0f ? context.options.aoDistance : kInfinity;
    ++rays;
    const bool blocked =
        context.scene.occluded({origin, cosineDirection(point.normal, key, context.options.seed)}, range);
    result.radiance = blocked ? Vec3f{0, 0, 0} : Vec3f{1, 1, 1};
    return result;
}

}  // namespace vastray
