// Triangle soup: N independent triangles (3 unshared vertices each) in [-1, 1]^3 with a
// Pareto (alpha = 1) size distribution and random orientations. Most triangles are tiny, a
// few span much of the cube: the worst case for a KD-tree's split choices and for
// straddling references. Triangle t draws from its own stream hash(seed, t), so the
// triangles are drawn in parallel batches (BatchPipeline.h) and the faces (3t, 3t+1, 3t+2)
// follow the vertices without anything stored.
#include <algorithm>

#include "generate/BatchPipeline.h"
#include "generate/Generators.h"
#include "generate/Random.h"

namespace vastray::gen {
namespace {

constexpr float kMinSize = 1e-3f;  // offsets of vertices from the centre are in [-size, size]^3
constexpr float kMaxSize = 1.0f;   // the largest can span the whole cube
// Redraw when area < kMinAreaRatio * size^2 (a sliver) or when clamping to the cube
// flattened it; a typical triangle of this size has an area of order size^2.
constexpr double kMinAreaRatio = 0.01;
constexpr uint64_t kBatch = 1 << 16;  // triangles per parallel batch (768 KiB, two in flight)

struct Triangle {
    Vec3f p[3];
};

Vec3f clampToCube(Vec3f p) {
    return {std::clamp(p.x, -1.0f, 1.0f), std::clamp(p.y, -1.0f, 1.0f), std::clamp(p.z, -1.0f, 1.0f)};
}

double area2(const Triangle& t) {
    double ax = double(t.p[1].x) - t.p[0].x, ay = double(t.p[1].y) - t.p[0].y,
           az = double(t.p[1].z) - t.p[0].z;
    double bx = double(t.p[2].x) - t.p[0].x, by = double(t.p[2].y) - t.p[0].y,
           bz = double(t.p[2].z) - t.p[0].z;
    double cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
    return cx * cx + cy * cy + cz * cz;  // (2 * area)^2
}

Triangle soupTriangle(uint64_t seed, uint64_t index) {
    Rng rng(hashCombine(seed, index));
    for (;;) {
        // P(size > s) = kMinSize / s: heavy tail, capped at kMaxSize.
        float size = std::min(kMaxSize, kMinSize / rng.uniformOpen01());
        Vec3f center = rng.cubePoint();
        // Offsets uniform in the cube: not isotropic, but orientations are random and no
        // rejection loop means no mispredicted branch; near-zero offsets end as slivers below.
        Triangle t;
        for (Vec3f& p : t.p) p = clampToCube(center + rng.cubePoint() * size);
        double minArea = kMinAreaRatio * double(size) * double(size);
        if (area2(t) >= 4.0 * minArea * minArea) return t;
    }
}

}  // namespace

GeneratedCounts soupCounts(uint64_t triangles) { return {3 * triangles, triangles}; }

Status generateSoup(const GenerateOptions& options, MeshSink& sink) {
    const uint64_t n = options.triangles;
    VASTRAY_TRY(sink.begin(3 * n, n));
    auto fill = [seed = options.seed](uint64_t first, uint64_t count, Triangle* out) {
        for (uint64_t t = 0; t < count; ++t) out[t] = soupTriangle(seed, first + t);
    };
    auto emit = [&sink](const Triangle* batch, uint64_t count) {
        for (uint64_t t = 0; t < count; ++t) {
            for (const Vec3f& p : batch[t].p) VASTRAY_TRY(sink.vertex(p));
        }
        return Status::ok();
    };
    VASTRAY_TRY(runBatchPipeline<Triangle>(n, kBatch, fill, emit));
    for (uint64_t t = 0; t < n; ++t) {
        auto first = static_cast<uint32_t>(3 * t);
        VASTRAY_TRY(sink.face(first, first + 1, first + 2));
    }
    return sink.end();
}

}  // namespace vastray::gen
