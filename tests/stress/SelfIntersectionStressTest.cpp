// Self-intersection: a ray leaving a surface from the renderer's offset origin (Wächter &
// Binder, core/RayOffset.h) with a cosine direction never re-hits that surface. Many random
// bounces at several scales and distances from the origin, in every ray-level backend, and
// ambient-occlusion renders of a convex sphere through the streaming renderer (every AO ray
// leaving a convex object outward must escape: any occlusion is a self-hit).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "StressSupport.h"
#include "vastray/core/PathShading.h"
#include "vastray/core/RayOffset.h"

namespace vastray::stress {
namespace {

struct Placement {
    const char* name;
    float scale;   // of the radius-2 icosphere
    float offset;  // distance of its centre from the origin, along a fixed unit vector
};

constexpr Placement kPlacements[] = {
    {"radius-2e-3", 1e-3f, 0.0f},        {"radius-2", 1.0f, 0.0f},
    {"radius-2e3", 1e3f, 0.0f},          {"radius-2-at-1e5", 1.0f, 1e5f},
    {"radius-200-at-1e5", 100.0f, 1e5f},
};

Vec3f placementOffset(const Placement& p) { return Vec3f{0.6f, -0.48f, 0.64f} * p.offset; }

struct BounceCount {
    uint64_t bounces = 0;
    uint64_t sameTriangle = 0;   // the next hit is the triangle just left
    uint64_t outsideHits = 0;    // convex only: an outward bounce met the surface again
    uint64_t insideEscapes = 0;  // closed only: an inward bounce found no surface
};

// Rays from outside aimed at the object (one outward bounce each) and from inside (four
// bounces each); each bounce starts at offsetRayOrigin of the barycentric hit point.
BounceCount bounce(RayBackend& backend, const Mesh& mesh, Vec3f centre, float radius, bool convex,
                   uint32_t paths) {
    std::mt19937 rng(21);
    std::normal_distribution<float> normal(0.0f, 1.0f);
    std::vector<Ray> rays;
    std::vector<uint8_t> inside;
    for (uint32_t i = 0; i < paths; ++i) {
        const Vec3f d = test::normalized({normal(rng), normal(rng), normal(rng)});
        if (i % 2 == 0) {
            const Vec3f origin = centre + d * (3.0f * radius);
            rays.push_back(
                {origin, centre + Vec3f{normal(rng), normal(rng), normal(rng)} * (0.3f * radius) - origin});
        } else {
            rays.push_back({centre + Vec3f{normal(rng), normal(rng), normal(rng)} * (0.2f * radius), d});
        }
        inside.push_back(i % 2);
    }
    const Material material;
    BounceCount count;
    std::vector<RayHit> hits = backend.trace(rays);
    for (uint32_t depth = 1; depth <= 4; ++depth) {
        std::vector<Ray> next;
        std::vector<uint32_t> from;  // triangle just left
        std::vector<uint8_t> nextInside;
        for (size_t i = 0; i < rays.size(); ++i) {
            if (!hits[i].found) continue;
            const uint32_t* tri = &mesh.indices[3 * hits[i].triangle];
            const Vec3f v0 = mesh.positions[tri[0]], v1 = mesh.positions[tri[1]], v2 = mesh.positions[tri[2]];
            const SurfacePoint sp =
                makeSurfacePoint(barycentricPosition(v0, v1, v2, hits[i].u, hits[i].v),
                                 geometricNormal(v0, v1, v2), rays[i].direction, material);
            const Vec3f origin = offsetRayOrigin(sp.position, sp.normal);
            next.push_back({origin, cosineDirection(sp.normal, RandomKey{uint32_t(i), 0, depth}, 7)});
            from.push_back(hits[i].triangle);
            nextInside.push_back(inside[i]);
        }
        const std::vector<RayHit> nextHits = backend.trace(next);
        for (size_t k = 0; k < next.size(); ++k) {
            ++count.bounces;
            count.sameTriangle += nextHits[k].found && nextHits[k].triangle == from[k];
            if (convex && !nextInside[k]) count.outsideHits += nextHits[k].found;
            if (nextInside[k]) count.insideEscapes += !nextHits[k].found;
        }
        rays = std::move(next), hits = std::move(nextHits), inside = std::move(nextInside);
    }
    return count;
}

TEST(SelfIntersection, RandomBouncesAtSeveralScales) {
    const Mesh unit = test::makeIcosphere(4, {0, 0, 0}, 2.0f);
    for (const Placement& p : kPlacements) {
        const Mesh mesh = transformed(unit, p.scale, placementOffset(p));
        for (BackendKind kind : kRayBackends) {
            auto backend = makeBackend(kind, mesh);
            const BounceCount c = bounce(*backend, mesh, placementOffset(p), 2.0f * p.scale, true, 10000);
            figure(std::string("self-hit-icosphere-") + p.name, backendName(kind),
                   "bounces=%llu same_triangle=%llu outward_rehits=%llu inward_escapes=%llu",
                   (unsigned long long)c.bounces, (unsigned long long)c.sameTriangle,
                   (unsigned long long)c.outsideHits, (unsigned long long)c.insideEscapes);
            EXPECT_GT(c.bounces, 20000u);
            EXPECT_EQ(c.sameTriangle, 0u) << p.name << " " << backendName(kind);
            EXPECT_EQ(c.outsideHits, 0u) << p.name << " " << backendName(kind);
            // The offset is 256 ulps of each coordinate: 3e-5 of the distance from the origin.
            // Around the origin that is far below the sphere's size, so an inward bounce
            // stays inside; at 1e5 it grows to ~2 units and a radius-2 sphere can be left
            // (reported, asserted only where the offset is < 1% of the radius).
            if (3e-5f * p.offset < 0.01f * 2.0f * p.scale) {
                EXPECT_EQ(c.insideEscapes, 0u) << p.name << " " << backendName(kind);
            }
        }
    }
}

TEST(SelfIntersection, SpotBounces) {
    const std::optional<Mesh> spot = loadSpot();
    if (!spot) GTEST_SKIP() << "shared meshes absent";
    Aabb box;
    for (const Vec3f& q : spot->positions) box.extend(q);
    const Vec3f centre = (box.lo + box.hi) * 0.5f;
    for (float scale : {1e-3f, 1.0f, 1e3f}) {
        const Mesh mesh = transformed(*spot, scale, {0, 0, 0});
        for (BackendKind kind : kRayBackends) {
            auto backend = makeBackend(kind, mesh);
            // Not convex, and "inside" origins may lie outside: only same-triangle re-hits count.
            const BounceCount c =
                bounce(*backend, mesh, centre * scale, 0.5f * maxAbs(box.hi - box.lo) * scale, false, 10000);
            char name[64];
            std::snprintf(name, sizeof(name), "self-hit-spot-scale-%g", double(scale));
            figure(name, backendName(kind), "bounces=%llu same_triangle=%llu", (unsigned long long)c.bounces,
                   (unsigned long long)c.sameTriangle);
            EXPECT_GT(c.bounces, 5000u);
            EXPECT_EQ(c.sameTriangle, 0u) << name << " " << backendName(kind);
        }
    }
}

TEST(SelfIntersection, StreamingAmbientOcclusionOfAConvexSphere) {
    const Mesh unit = test::makeIcosphere(4, {0, 0, 0}, 2.0f);
    for (const Placement& p : kPlacements) {
        const Mesh mesh = transformed(unit, p.scale, placementOffset(p));
        const std::string name = std::string("self-hit-stream-ao-") + p.name;
        const std::string path = packageFromMesh(name, mesh, 16 << 10);
        Aabb box;
        for (const Vec3f& q : mesh.positions) box.extend(q);
        RenderOptions o = aimedRender(48, 36, frameBounds(box, 40.0f, 48.0f / 36.0f), kAovPrimId);
        o.samplesPerPixel = 16;
        const std::optional<StreamingTrio> trio = renderTrio(path, o);
        ASSERT_TRUE(trio);
        // AO radiance per sample is 1 (escaped) or 0 (occluded); a pixel's value is the mean.
        auto occluded = [&](const RenderImage& image) {
            double samples = 0;
            for (size_t i = 0; i < image.rgb.size(); i += 3)
                samples += (1.0 - double(image.rgb[i])) * o.samplesPerPixel;
            return uint64_t(std::llround(samples));
        };
        uint64_t hitPixels = 0;
        for (uint32_t id : trio->reference.primId) hitPixels += id != kMissPrimId;
        const uint64_t aoRays = hitPixels * o.samplesPerPixel;
        figure(name, "embree", "ao_rays=%llu occluded=%llu", (unsigned long long)aoRays,
               (unsigned long long)occluded(trio->reference));
        figure(name, "vulkan-ample", "ao_rays=%llu occluded=%llu", (unsigned long long)aoRays,
               (unsigned long long)occluded(trio->ample));
        figure(name, "vulkan-2slot", "ao_rays=%llu occluded=%llu", (unsigned long long)aoRays,
               (unsigned long long)occluded(trio->tight));
        EXPECT_GT(hitPixels, 200u) << name;  // the framed sphere covers ~16% of the image
        EXPECT_EQ(occluded(trio->reference), 0u) << name;
        EXPECT_EQ(occluded(trio->ample), 0u) << name;
        EXPECT_EQ(occluded(trio->tight), 0u) << name;
    }
}

}  // namespace
}  // namespace vastray::stress
