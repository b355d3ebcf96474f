// GPU trace.comp against the CPU reference intersectKdTree: same hit, same t/u/v bits, same
// facing and the same node/triangle counters (the shader mirrors the traversal decision for
// decision). Tolerance: none: lavapipe divides with correct rounding, as the CPU does, and both
// take the same double fallback (Watertight.glsl); a GPU whose division is approximate may differ
// in the last bits.
#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "GpuTestSupport.h"
#include "vastray/core/TriangleIntersect.h"
#include "vastray/gpu/GpuChunkTracer.h"

namespace vastray::gpu::test {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

TraceRay makeRay(Vec3f o, Vec3f d, float tMin = 0.0f, float tMax = kInf) {
    return {o.x, o.y, o.z, tMin, d.x, d.y, d.z, tMax};
}

float maxAbs(Vec3f v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

Vec3f randomDirection(std::mt19937& rng) {
    std::normal_distribution<float> n(0.0f, 1.0f);
    for (;;) {
        const Vec3f d{n(rng), n(rng), n(rng)};
        if (d.x * d.x + d.y * d.y + d.z * d.z > 1e-4f) return d;
    }
}

// Random rays: half from outside the bounds aimed at a point inside, half from inside in any
// direction; a quarter of all get a finite [tMin, tMax] window.
void addRandomRays(const KdTree& tree, uint32_t count, uint32_t seed, std::vector<TraceRay>* rays) {
    std::mt19937 rng(seed);
    const Vec3f lo = tree.bounds.lo, hi = tree.bounds.hi, extent = hi - lo;
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    auto inside = [&] { return Vec3f{lo.x + extent.x * unit(rng), lo.y + extent.y * unit(rng), lo.z + extent.z * unit(rng)}; };
    for (uint32_t i = 0; i < count; ++i) {
        TraceRay r;
        if (i % 2 == 0) {
            const Vec3f target = inside();
            const Vec3f origin = target + randomDirection(rng) * (2.0f * maxAbs(extent));
            r = makeRay(origin, target - origin);
        } else {
            r = makeRay(inside(), randomDirection(rng));
        }
        if (i % 4 == 1) r.tMin = 0.5f * unit(rng), r.tMax = r.tMin + 4.0f * unit(rng);
        rays->push_back(r);
    }
}

// Rays whose origin lies exactly on a split plane of the tree: some cross it, some run inside it.
void addSplitPlaneRays(const KdTree& tree, uint32_t count, uint32_t seed, std::vector<TraceRay>* rays) {
    std::vector<KdNode> interior;
    for (const KdNode& n : tree.nodes)
        if (!n.isLeaf()) interior.push_back(n);
    ASSERT_FALSE(interior.empty());
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const Vec3f lo = tree.bounds.lo, extent = tree.bounds.hi - tree.bounds.lo;
    for (uint32_t i = 0; i < count; ++i) {
        const KdNode n = interior[rng() % interior.size()];
        Vec3f o{lo.x + extent.x * unit(rng), lo.y + extent.y * unit(rng), lo.z + extent.z * unit(rng)};
        o[int(n.axis())] = n.split();
        Vec3f d = randomDirection(rng);
        if (i % 2 == 0) d[int(n.axis())] = 0.0f;  // inside the plane
        rays->push_back(makeRay(o, d));
    }
}

// Rays along +-x, +-y, +-z; snapToGrid puts the origin's other coordinates on integers (the
// axis grid's edges and vertices).
void addAxisRays(const KdTree& tree, uint32_t count, uint32_t seed, bool snapToGrid, std::vector<TraceRay>* rays) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const Vec3f lo = tree.bounds.lo, extent = tree.bounds.hi - tree.bounds.lo;
    for (uint32_t i = 0; i < count; ++i) {
        const int axis = int(i % 3);
        Vec3f o{lo.x + extent.x * unit(rng), lo.y + extent.y * unit(rng), lo.z + extent.z * unit(rng)};
        if (snapToGrid) o = {std::round(o.x), std::round(o.y), std::round(o.z)};
        o[axis] = (i / 3) % 2 ? tree.bounds.hi[axis] + 1.0f : tree.bounds.lo[axis] - 1.0f;
        Vec3f d{0, 0, 0};
        d[axis] = (i / 3) % 2 ? -1.0f : 1.0f;
        rays->push_back(makeRay(o, d));
    }
}

std::string describe(const TraceRay& r) {
    char text[256];
    std::snprintf(text, sizeof(text), "ray o=(%a,%a,%a) d=(%a,%a,%a) t=[%a,%a]", r.originX, r.originY, r.originZ,
                  r.directionX, r.directionY, r.directionZ, r.tMin, r.tMax);
    return text;
}

// Compares every GPU hit with intersectKdTree; returns the number of rays that hit something.
uint32_t expectMatchesCpu(const Mesh& mesh, const KdTree& tree, const std::vector<TraceRay>& rays,
                          const std::vector<TraceHit>& hits) {
    uint32_t mismatches = 0, hitCount = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const TraceRay& r = rays[i];
        const Ray ray{{r.originX, r.originY, r.originZ}, {r.directionX, r.directionY, r.directionZ}};
        KdHit cpu;
        const bool found = intersectKdTree(tree, mesh.positions.data(), mesh.indices.data(),
                                           mesh.singleSided.empty() ? nullptr : mesh.singleSided.data(), ray, r.tMin,
                                           r.tMax, &cpu);
        const TraceHit& g = hits[i];
        const bool gpuFound = (g.flags & kHitFound) != 0;
        bool same = found == gpuFound && cpu.nodesVisited == g.nodesVisited && cpu.trianglesTested == g.trianglesTested;
        if (same && found)
            same = cpu.triangle == g.triangle && std::bit_cast<uint32_t>(cpu.t) == std::bit_cast<uint32_t>(g.t) &&
                   std::bit_cast<uint32_t>(cpu.u) == std::bit_cast<uint32_t>(g.u) &&
                   std::bit_cast<uint32_t>(cpu.v) == std::bit_cast<uint32_t>(g.v) &&
                   cpu.frontFacing == ((g.flags & kHitFrontFacing) != 0);
        hitCount += found;
        if (!same && ++mismatches <= 5)
            ADD_FAILURE() << describe(r) << "\n  cpu: found=" << found << " tri=" << cpu.triangle << " t=" << cpu.t
                          << " u=" << cpu.u << " v=" << cpu.v << " front=" << cpu.frontFacing
                          << " nodes=" << cpu.nodesVisited << " tests=" << cpu.trianglesTested
                          << "\n  gpu: found=" << gpuFound << " tri=" << g.triangle << " t=" << g.t << " u=" << g.u
                          << " v=" << g.v << " flags=" << g.flags << " nodes=" << g.nodesVisited
                          << " tests=" << g.trianglesTested;
    }
    EXPECT_EQ(mismatches, 0u) << "of " << rays.size() << " rays";
    return hitCount;
}

// Uploads the mesh, traces the rays on the device and checks every hit against the CPU.
void traceAndCompare(const Mesh& mesh, const std::vector<TraceRay>& rays) {
    VASTRAY_REQUIRE_DEVICE(device);
    const KdTree tree = mesh.build();
    auto tracer = GpuChunkTracer::create(device);
    ASSERT_TRUE(tracer.isOk()) << tracer.message();
    const Status uploaded = (*tracer)->upload(ChunkArrays{&tree, mesh.positions, mesh.indices, mesh.singleSided});
    ASSERT_TRUE(uploaded.isOk()) << uploaded.message();
    auto hits = (*tracer)->trace(rays);
    ASSERT_TRUE(hits.isOk()) << hits.message();
    ASSERT_EQ(hits->size(), rays.size());
    const uint32_t hitCount = expectMatchesCpu(mesh, tree, rays, *hits);
    // The ray sets are built to hit often; a tracer that never hits would pass vacuously.
    EXPECT_GT(hitCount, rays.size() / 10);
}

std::vector<TraceRay> standardRays(const KdTree& tree, uint32_t seed) {
    std::vector<TraceRay> rays;
    addRandomRays(tree, 10000, seed, &rays);
    addSplitPlaneRays(tree, 2000, seed + 1, &rays);
    addAxisRays(tree, 1500, seed + 2, false, &rays);
    return rays;
}

TEST(GpuChunkTracer, IcosphereMatchesCpu) {
    const Mesh mesh = makeIcosphere(4, {0.25f, -0.5f, 0.125f}, 2.0f);
    traceAndCompare(mesh, standardRays(mesh.build(), 1));
}

TEST(GpuChunkTracer, SoupWithTiesAndSingleSidedMatchesCpu) {
    Mesh mesh = makeSoup(3000, 7, true);
    std::mt19937 rng(9);
    for (uint32_t i = 0; i < mesh.count(); ++i) mesh.singleSided.push_back(uint8_t(rng() % 3 == 0));
    traceAndCompare(mesh, standardRays(mesh.build(), 11));
}

TEST(GpuChunkTracer, AxisPlaneGridMatchesCpu) {
    const Mesh mesh = makeAxisGrid(6);
    const KdTree tree = mesh.build();
    std::vector<TraceRay> rays = standardRays(tree, 21);
    addAxisRays(tree, 3000, 24, true, &rays);  // through edges and vertices of the grid
    traceAndCompare(mesh, rays);
}

TEST(GpuChunkTracer, FarFromOriginMatchesCpu) {
    // Large coordinates: the absolute part of the t-margin dominates.
    const Mesh mesh = makeIcosphere(3, {1000.0f, -2000.0f, 500.0f}, 3.0f);
    traceAndCompare(mesh, standardRays(mesh.build(), 31));
}

TEST(GpuChunkTracer, DegenerateRaysMissLikeCpu) {
    const Mesh mesh = makeIcosphere(2, {0, 0, 0}, 1.0f);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<TraceRay> rays = {
        makeRay({0, 0, -5}, {0, 0, 0}),         // zero direction
        makeRay({0, 0, -5}, {nan, 0, 1}),       // NaN direction
        makeRay({0, 0, -5}, {0, kInf, 1}),      // infinite direction
        makeRay({0, 0, -5}, {0, 0, 1}, 2, 1),   // empty window
        makeRay({0, 0, -5}, {0, 0, 1}, 0, 3.5f), // window ends before the sphere
        makeRay({0, 0, -5}, {0, 0, 1}),         // a plain hit, for contrast
    };
    VASTRAY_REQUIRE_DEVICE(device);
    const KdTree tree = mesh.build();
    auto tracer = GpuChunkTracer::create(device);
    ASSERT_TRUE(tracer.isOk()) << tracer.message();
    ASSERT_TRUE((*tracer)->upload(ChunkArrays{&tree, mesh.positions, mesh.indices, {}}).isOk());
    auto hits = (*tracer)->trace(rays);
    ASSERT_TRUE(hits.isOk()) << hits.message();
    for (size_t i = 0; i + 1 < rays.size(); ++i) EXPECT_EQ((*hits)[i].flags & kHitFound, 0u) << "ray " << i;
    EXPECT_NE(hits->back().flags & kHitFound, 0u);
    expectMatchesCpu(mesh, tree, rays, *hits);
}

// The ray along z passes outside edge bc by about 2^-46: in float the edge function
// cx*by - cy*bx rounds to exactly 0 (an edge hit), so only the exact fp32 recomputation
// (detail::zeroEdgeFunctionExact in TriangleIntersect.h, mirrored in Watertight.glsl) sees the
// miss. A GPU without it, or one whose compiler fused or reordered its steps, hits triangle 0 here.
TEST(GpuChunkTracer, ZeroEdgeFunctionFallbackMatchesCpu) {
    const float e = std::ldexp(1.0f, -23);  // one ulp of 1
    Mesh mesh;
    mesh.positions = {{1, -1, 0}, {1 + e, 1, 0}, {-(1 + 2 * e), -(1 + e), 0},   // origin just outside bc
                      {-1, 1, 1}, {1 + e, 1, 1}, {-(1 + 2 * e), -(1 + e), 1}};  // origin just inside bc
    mesh.indices = {0, 1, 2, 3, 4, 5};
    const std::vector<TraceRay> rays = {makeRay({0, 0, -1}, {0, 0, 1}), makeRay({0, 0, 2}, {0, 0, -1}),
                                        makeRay({0, 0, -1}, {0, 0, 1}, 0, 1.5f)};
    VASTRAY_REQUIRE_DEVICE(device);
    const KdTree tree = mesh.build();
    auto tracer = GpuChunkTracer::create(device);
    ASSERT_TRUE(tracer.isOk()) << tracer.message();
    ASSERT_TRUE((*tracer)->upload(ChunkArrays{&tree, mesh.positions, mesh.indices, {}}).isOk());
    auto hits = (*tracer)->trace(rays);
    ASSERT_TRUE(hits.isOk()) << hits.message();
    expectMatchesCpu(mesh, tree, rays, *hits);
    EXPECT_EQ((*hits)[0].triangle, 1u) << "triangle 0 is missed, triangle 1 behind it is hit";
    EXPECT_EQ((*hits)[1].triangle, 1u);
    EXPECT_EQ((*hits)[2].flags & kHitFound, 0u) << "only triangle 0 lies in [0, 1.5]";
}

TEST(GpuChunkTracer, TracesAChunkInSeveralBatches) {
    VASTRAY_REQUIRE_DEVICE(device);
    const Mesh mesh = makeIcosphere(3, {0, 0, 0}, 1.0f);
    const KdTree tree = mesh.build();
    auto tracer = GpuChunkTracer::create(device);
    ASSERT_TRUE(tracer.isOk()) << tracer.message();
    ASSERT_TRUE((*tracer)->upload(ChunkArrays{&tree, mesh.positions, mesh.indices, {}}).isOk());
    std::vector<TraceRay> small, large;
    addRandomRays(tree, 100, 41, &small);
    addRandomRays(tree, 3000, 42, &large);
    // A smaller batch after a larger one reuses the buffers; every batch must still match.
    for (const auto* rays : {&small, &large, &small}) {
        auto hits = (*tracer)->trace(*rays);
        ASSERT_TRUE(hits.isOk()) << hits.message();
        expectMatchesCpu(mesh, tree, *rays, *hits);
    }
}

TEST(GpuChunkTracer, RejectsOutOfRangeChunkData) {
    VASTRAY_REQUIRE_DEVICE(device);
    Mesh mesh = makeIcosphere(1, {0, 0, 0}, 1.0f);
    const KdTree tree = mesh.build();
    mesh.indices[4] = uint32_t(mesh.positions.size());
    auto tracer = GpuChunkTracer::create(device);
    ASSERT_TRUE(tracer.isOk()) << tracer.message();
    const Status status = (*tracer)->upload(ChunkArrays{&tree, mesh.positions, mesh.indices, {}});
    ASSERT_FALSE(status.isOk());
    EXPECT_NE(status.message().find("index 4"), std::string::npos) << status.message();
    EXPECT_FALSE((*tracer)->trace(std::vector<TraceRay>(1)).isOk()) << "nothing is resident after a failed upload";
}

// A device that does not finish a submission in time fails the trace with a message instead of
// hanging the render, and takes no more work. Stood in for by a limit of one nanosecond on a
// trace that takes far longer (lavapipe: ~0.1 s); its own device, so the shared one stays usable.
TEST(GpuChunkTracer, ASubmissionPastTheTimeoutFailsAndTheDeviceTakesNoMoreWork) {
    VulkanDeviceOptions options;
    options.submitTimeoutSeconds = 1e-9;
    auto device = VulkanDevice::create(options);
    ASSERT_TRUE(device.isOk()) << device.message();
    const Mesh mesh = makeIcosphere(5, {0, 0, 0}, 1.0f);
    const KdTree tree = mesh.build();
    auto tracer = GpuChunkTracer::create(**device);
    ASSERT_TRUE(tracer.isOk()) << tracer.message();
    const Status uploaded = (*tracer)->upload({&tree, mesh.positions, mesh.indices, {}});
    ASSERT_TRUE(uploaded.isOk()) << uploaded.message();  // copies through mapped memory: no submission
    std::vector<TraceRay> rays;
    addRandomRays(tree, 200000, 7, &rays);
    auto hits = (*tracer)->trace(rays);
    ASSERT_FALSE(hits.isOk()) << "a 1 ns limit cannot hold a 200k-ray trace";
    EXPECT_NE(hits.message().find("did not finish a submission within 1e-09 s (hung device?)"), std::string::npos)
        << hits.message();
    auto again = (*tracer)->trace(std::vector<TraceRay>(1));
    ASSERT_FALSE(again.isOk());
    EXPECT_NE(again.message().find("takes no more work"), std::string::npos) << again.message();
}

}  // namespace
}  // namespace vastray::gpu::test
