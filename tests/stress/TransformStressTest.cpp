// The same scenes translated 1e3, 1e5 and 1e6 units from the origin and scaled by 1e-3 and 1e3:
// each backend must keep agreeing with the reference on the same (transformed) floats, and the
// figures show how far the transformed geometry itself still agrees with the untransformed scene.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <random>

#include "StressSupport.h"

namespace vastray::stress {
namespace {

struct Transform {
    const char* name;
    float scale;
    float distance;  // of the offset from the origin, along a fixed unit vector
    Vec3f offset() const { return Vec3f{0.6f, -0.48f, 0.64f} * distance; }
    Vec3f apply(Vec3f p) const { return p * scale + offset(); }
};

constexpr Transform kTransforms[] = {
    {"identity", 1.0f, 0.0f},      {"translate-1e3", 1.0f, 1e3f}, {"translate-1e5", 1.0f, 1e5f},
    {"translate-1e6", 1.0f, 1e6f}, {"scale-1e-3", 1e-3f, 0.0f},   {"scale-1e3", 1e3f, 0.0f},
};

// Random rays in the mesh's own frame: half from outside aimed at a point inside the bounds,
// half from inside in any direction.
std::vector<Ray> randomRays(const Mesh& mesh, uint32_t count, uint32_t seed) {
    Aabb box;
    for (const Vec3f& p : mesh.positions) box.extend(p);
    const Vec3f e = box.hi - box.lo;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::normal_distribution<float> normal(0.0f, 1.0f);
    auto inside = [&] {
        return Vec3f{box.lo.x + e.x * unit(rng), box.lo.y + e.y * unit(rng), box.lo.z + e.z * unit(rng)};
    };
    std::vector<Ray> rays;
    for (uint32_t i = 0; i < count; ++i) {
        const Vec3f d{normal(rng), normal(rng), normal(rng)};
        if (i % 2 == 0) {
            const Vec3f target = inside();
            const Vec3f origin = target + d * (2.0f * maxAbs(e) / maxAbs(d));
            rays.push_back({origin, target - origin});
        } else {
            rays.push_back({inside(), d});
        }
    }
    return rays;
}

// Agreement with the reference on the same transformed floats must stay this high at every
// transform: both run watertight tests on the same triangles, so they can only disagree on rays
// within rounding of an edge, a vanishing fraction of random rays (measured: see the figures).
constexpr double kMinAgreementWithReference = 0.999;
// Against the untransformed scene: where a float's spacing at the offset stays below 1e-5 of
// the object (translate-1e3 and both scales) the geometry is essentially unchanged, so 99% of
// hits must survive; at 1e5 and 1e6 rounding moves vertices by up to 0.004 and 0.03 units (half
// the float spacing there) on a 4-unit object, so that figure is reported, not asserted.
constexpr double kMinFidelityWhereExact = 0.99;

void transformedRays(const std::string& name, const Mesh& mesh) {
    // 10^4 rays: far from the origin the traversal slows down sharply (see trace_ms), and the
    // suite must stay within CI's few minutes.
    const std::vector<Ray> rays = randomRays(mesh, 10000, 7);
    const std::vector<RayHit> baseline = EmbreeBackend(mesh).trace(rays);
    for (const Transform& tf : kTransforms) {
        const Mesh moved = transformed(mesh, tf.scale, tf.offset());
        std::vector<Ray> movedRays;
        for (const Ray& r : rays) movedRays.push_back({tf.apply(r.origin), r.direction * tf.scale});
        const auto referenceStart = std::chrono::steady_clock::now();
        const std::vector<RayHit> reference = EmbreeBackend(moved).trace(movedRays);
        const double referenceMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - referenceStart)
                .count();
        for (BackendKind kind : kRayBackends) {
            const auto start = std::chrono::steady_clock::now();
            const std::vector<RayHit> hits =
                kind == BackendKind::Embree ? reference : makeBackend(kind, moved)->trace(movedRays);
            // Build and trace (the GPU's includes creating the tracer and uploading the chunk).
            const double ms =
                kind == BackendKind::Embree
                    ? referenceMs
                    : std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                          .count();
            // Same answer as the reference: the same triangle, or another one at the same t (vertices
            // snapped together far from the origin make many coincident and degenerate triangles).
            uint64_t same = 0, backendWrong = 0, referenceWrong = 0, startOnSurface = 0;
            for (size_t i = 0; i < hits.size(); ++i) {
                if (sameHit(hits[i], reference[i]) || sameAnswer(hits[i], reference[i])) {
                    ++same;
                    continue;
                }
                // Where they disagree, which one has the exact answer.
                const RayHit exact = exactClosest(moved, movedRays[i]);
                // An origin exactly on a triangle (rounded onto the coarse float grid far out): t = 0,
                // where the answer is a convention (SplitPlaneStressTest.cpp); counted apart.
                if (exact.found && exact.t == 0.0f) {
                    ++startOnSurface;
                    continue;
                }
                backendWrong += !sameAnswer(hits[i], exact),
                    referenceWrong += !sameAnswer(reference[i], exact);
                if (std::getenv("VASTRAY_STRESS_VERBOSE") && !sameAnswer(hits[i], exact))  // debugging aid
                    std::printf("note: %s %s %s wrong: %s; exact: %s\n", name.c_str(), tf.name,
                                backendName(kind), describe(movedRays[i], hits[i]).c_str(),
                                describe(movedRays[i], exact).c_str());
            }
            const double withReference = double(same) / double(hits.size()),
                         fidelity = agreement(hits, baseline);
            figure(name + "-" + tf.name, backendName(kind),
                   "rays=%zu agreement_with_reference=%.6f fidelity=%.6f start_on_surface=%llu "
                   "backend_wrong=%llu "
                   "reference_wrong=%llu trace_ms=%.0f",
                   rays.size(), withReference, fidelity, (unsigned long long)startOnSurface,
                   (unsigned long long)backendWrong, (unsigned long long)referenceWrong, ms);
            // Measured: apart from t = 0 starts, neither side is ever wrong where they disagree.
            EXPECT_EQ(backendWrong, 0u) << name << " " << tf.name << " " << backendName(kind);
            EXPECT_EQ(referenceWrong, 0u) << name << " " << tf.name << " (reference)";
            EXPECT_GE(withReference, kMinAgreementWithReference)
                << name << " " << tf.name << " " << backendName(kind)
                << firstMismatches(movedRays, hits, reference, sameAnswer);
            if (tf.distance <= 1e3f) {
                EXPECT_GE(fidelity, kMinFidelityWhereExact)
                    << name << " " << tf.name << " " << backendName(kind);
            }
        }
    }
}

TEST(FarAndScaled, IcosphereRays) {
    transformedRays("transform-icosphere", test::makeIcosphere(4, {0.25f, -0.5f, 0.125f}, 2.0f));
}

TEST(FarAndScaled, SpotRays) {
    const std::optional<Mesh> spot = loadSpot();
    if (!spot) GTEST_SKIP() << "shared meshes absent";
    transformedRays("transform-spot", *spot);
}

// Streaming renders of the transformed package with the transformed camera: primid agreement of
// the Vulkan backend (ample and two slots) with Embree on the same package, and fidelity against
// the untransformed render.
void transformedRenders(const std::string& name, const Mesh& mesh) {
    Aabb box;
    for (const Vec3f& p : mesh.positions) box.extend(p);
    const Camera base = frameBounds(box, 40.0f, 4.0f / 3.0f);
    std::vector<uint32_t> untransformed;
    for (const Transform& tf : kTransforms) {
        Camera camera = base;
        camera.eye = tf.apply(base.eye), camera.target = tf.apply(base.target);
        const std::string path =
            packageFromMesh(name + "-" + tf.name, transformed(mesh, tf.scale, tf.offset()));
        const std::optional<StreamingTrio> trio = renderTrio(path, aimedRender(64, 48, camera, kAovPrimId));
        ASSERT_TRUE(trio);
        if (untransformed.empty()) untransformed = trio->reference.primId;
        RenderImage baseline;
        baseline.primId = untransformed;
        const double ample = primIdAgreement(trio->ample, trio->reference);
        const double tight = primIdAgreement(trio->tight, trio->reference);
        figure(name + "-" + tf.name, "vulkan-ample",
               "rays=%zu agreement_with_reference=%.6f fidelity=%.6f chunks=%llu", untransformed.size(),
               ample, primIdAgreement(trio->ample, baseline),
               (unsigned long long)trio->ampleStats.chunksTotal);
        figure(name + "-" + tf.name, "vulkan-2slot",
               "rays=%zu agreement_with_reference=%.6f fidelity=%.6f loads=%llu", untransformed.size(), tight,
               primIdAgreement(trio->tight, baseline), (unsigned long long)trio->tightStats.chunkLoads);
        // 3072 pixel-centre rays: at the 0.999 ray-level bound at most 3 may differ.
        EXPECT_GE(ample, kMinAgreementWithReference) << name << " " << tf.name;
        EXPECT_EQ(primIdAgreement(trio->ample, trio->tight), 1.0) << name << " " << tf.name;
        if (tf.distance <= 1e3f) {
            EXPECT_GE(primIdAgreement(trio->ample, baseline), kMinFidelityWhereExact);
        }
    }
}

TEST(FarAndScaled, IcosphereStreaming) {
    transformedRenders("transform-stream-icosphere", test::makeIcosphere(4, {0.25f, -0.5f, 0.125f}, 2.0f));
}

TEST(FarAndScaled, SpotStreaming) {
    const std::optional<Mesh> spot = loadSpot();
    if (!spot) GTEST_SKIP() << "shared meshes absent";
    transformedRenders("transform-stream-spot", *spot);
}

}  // namespace
}  // namespace vastray::stress
