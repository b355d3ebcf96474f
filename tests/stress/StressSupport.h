#pragma once
// Shared by the stress tests: the one Vulkan device, the three ray-level backends behind one
// batch interface (Embree reference, core KD traversal, GPU chunk tracer), small streaming
// renders at ample and tight budgets, and the one-line figure format bench/stress_report.sh reads.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "TestMeshes.h"
#include "StreamTestSupport.h"
#include "TestTmp.h"
#include "vastray/core/KdTree.h"
#include "vastray/core/Mesh.h"
#include "vastray/core/RenderImage.h"
#include "vastray/core/RenderOptions.h"
#include "vastray/cpu/EmbreeRenderer.h"
#include "vastray/cpu/EmbreeScene.h"
#include "vastray/cpu/RenderScene.h"
#include "vastray/gpu/GpuChunkTracer.h"
#include "vastray/gpu/VulkanChunkBackend.h"
#include "vastray/gpu/VulkanDevice.h"
#include "vastray/streamer/Import.h"
#include "vastray/streamer/PackageBuilder.h"
#include "vastray/streamer/ScenePackage.h"
#include "vastray/streamer/StreamingRenderer.h"

namespace vastray::stress {

using test::Mesh;

// One figure line: "STRESS <case> <backend> key=value key=value ...". bench/stress_report.sh
// turns these lines into docs/generated/stress.md; keep the format stable.
inline void figure(const std::string& caseName, const std::string& backend, const char* format, ...) {
    char text[1024];
    va_list args;
    va_start(args, format);
    std::vsnprintf(text, sizeof(text), format, args);
    va_end(args);
    std::printf("STRESS %s %s %s\n", caseName.c_str(), backend.c_str(), text);
    std::fflush(stdout);
}

using test::budgetForSlots;
using test::renderEmbree;
using test::renderVulkan;
using test::renderVulkanColdAndWarm;
inline gpu::VulkanDevice& device() { return test::sharedVulkanDevice(); }

inline TriangleMesh toTriangleMesh(const Mesh& m) {
    TriangleMesh mesh;
    mesh.positions = m.positions;
    mesh.indices = m.indices;
    mesh.materials = {Material{"default"}};
    return mesh;
}

inline Mesh toTestMesh(const TriangleMesh& m) {
    Mesh mesh;
    mesh.positions = m.positions;
    mesh.indices = m.indices;
    return mesh;
}

// p * scale + offset for every vertex (in float, as a user's file would hold the coordinates).
inline Mesh transformed(const Mesh& m, float scale, Vec3f offset) {
    Mesh out = m;
    for (Vec3f& p : out.positions) p = p * scale + offset;
    return out;
}

inline std::string sharedMeshDir() { return std::string(VASTRAY_SHARED_DATA) + "/meshes/"; }

// spot.obj (closed) from the shared data, or nullopt with a printed note when the folder is absent.
inline std::optional<Mesh> loadSpot() {
    const std::string path = sharedMeshDir() + "spot.obj";
    if (!std::filesystem::exists(path)) {
        std::printf("note: %s is absent (a user's clone): spot cases not checked\n", path.c_str());
        return std::nullopt;
    }
    auto imported = importMesh(path);
    EXPECT_TRUE(imported) << imported.message();
    if (!imported) return std::nullopt;
    return toTestMesh(imported->mesh);
}

// What every ray-level backend answers for one ray.
struct RayHit {
    bool found = false;
    float t = 0;
    uint32_t triangle = 0;
    bool frontFacing = false;
    float u = 0, v = 0;  // barycentric weights of the triangle's second and third vertex
};

// A mesh loaded into one backend; traces batches of rays with tMin = 0 (Embree's only start).
class RayBackend {
public:
    virtual ~RayBackend() = default;
    virtual std::vector<RayHit> trace(const std::vector<Ray>& rays) = 0;
};

enum class BackendKind { Embree, Kd, Gpu };
inline const char* backendName(BackendKind kind) {
    return kind == BackendKind::Embree ? "embree" : kind == BackendKind::Kd ? "kd" : "vulkan-chunk";
}
constexpr BackendKind kRayBackends[] = {BackendKind::Embree, BackendKind::Kd, BackendKind::Gpu};

class EmbreeBackend : public RayBackend {
public:
    explicit EmbreeBackend(const Mesh& mesh) {
        auto built = EmbreeScene::build(toTriangleMesh(mesh));
        EXPECT_TRUE(built) << built.message();
        if (built) scene_ = std::move(built).value();
    }
    std::vector<RayHit> trace(const std::vector<Ray>& rays) override {
        std::vector<RayHit> out(rays.size());
        for (size_t i = 0; i < rays.size() && scene_; ++i) {
            SceneHit h;
            if (scene_->intersect(rays[i], INFINITY, &h))
                out[i] = {true, h.t, h.triangle, h.frontFacing, h.u, h.v};
        }
        return out;
    }

private:
    std::unique_ptr<EmbreeScene> scene_;
};

// The KD tree a package builds for a chunk (compact options): the tree the renderer traces.
class KdBackend : public RayBackend {
public:
    explicit KdBackend(const Mesh& mesh)
        : mesh_(mesh),
          tree_(buildKdTree(mesh.positions.data(), mesh.indices.data(), mesh.count(),
                            compactKdBuildOptions(mesh.count()))) {}
    std::vector<RayHit> trace(const std::vector<Ray>& rays) override {
        std::vector<RayHit> out(rays.size());
        for (size_t i = 0; i < rays.size(); ++i) {
            KdHit h;
            if (intersectKdTree(tree_, mesh_.positions.data(), mesh_.indices.data(), nullptr, rays[i], 0,
                                INFINITY, &h))
                out[i] = {true, h.t, h.triangle, h.frontFacing, h.u, h.v};
        }
        return out;
    }
    const KdTree& tree() const { return tree_; }

private:
    const Mesh& mesh_;
    KdTree tree_;
};

// The whole mesh as one chunk on the device: trace.comp, the kernel of the streaming backend.
class GpuBackend : public RayBackend {
public:
    explicit GpuBackend(const Mesh& mesh) : kd_(mesh) {
        auto tracer = gpu::GpuChunkTracer::create(device());
        EXPECT_TRUE(tracer) << tracer.message();
        if (!tracer) return;
        tracer_ = std::move(tracer).value();
        const Status s = tracer_->upload(gpu::ChunkArrays{&kd_.tree(), mesh.positions, mesh.indices, {}});
        EXPECT_TRUE(s.isOk()) << s.message();
    }
    std::vector<RayHit> trace(const std::vector<Ray>& rays) override {
        std::vector<RayHit> out(rays.size());
        constexpr size_t kBatch = 1 << 20;  // bounds the device's ray buffer
        for (size_t first = 0; first < rays.size() && tracer_; first += kBatch) {
            std::vector<gpu::TraceRay> batch;
            for (size_t i = first; i < std::min(rays.size(), first + kBatch); ++i) {
                const Ray& r = rays[i];
                batch.push_back({r.origin.x, r.origin.y, r.origin.z, 0.0f, r.direction.x, r.direction.y,
                                 r.direction.z, INFINITY});
            }
            auto hits = tracer_->trace(batch);
            EXPECT_TRUE(hits) << hits.message();
            if (!hits) return out;
            for (size_t i = 0; i < batch.size(); ++i) {
                const gpu::TraceHit& h = (*hits)[i];
                if (h.flags & gpu::kHitFound)
                    out[first + i] = {true, h.t, h.triangle, (h.flags & gpu::kHitFrontFacing) != 0, h.u, h.v};
            }
        }
        return out;
    }

private:
    KdBackend kd_;
    std::unique_ptr<gpu::GpuChunkTracer> tracer_;
};

inline std::unique_ptr<RayBackend> makeBackend(BackendKind kind, const Mesh& mesh) {
    if (kind == BackendKind::Embree) return std::make_unique<EmbreeBackend>(mesh);
    if (kind == BackendKind::Kd) return std::make_unique<KdBackend>(mesh);
    return std::make_unique<GpuBackend>(mesh);
}

// Same answer: both miss, or both hit the same triangle.
inline bool sameHit(const RayHit& a, const RayHit& b) {
    return a.found == b.found && (!a.found || a.triangle == b.triangle);
}

inline std::string describe(const Ray& r, const RayHit& h) {
    char text[256];
    std::snprintf(text, sizeof(text), "o=(%.9g,%.9g,%.9g) d=(%.9g,%.9g,%.9g) found=%d t=%.9g tri=%u front=%d",
                  r.origin.x, r.origin.y, r.origin.z, r.direction.x, r.direction.y, r.direction.z,
                  int(h.found), h.t, h.triangle, int(h.frontFacing));
    return text;
}

// The first `limit` rays on which `same` fails, with both answers (for failure messages).
template <typename Same>
std::string firstMismatches(const std::vector<Ray>& rays, const std::vector<RayHit>& a,
                            const std::vector<RayHit>& b, Same same, int limit = 3) {
    std::string out;
    for (size_t i = 0; i < rays.size() && limit > 0; ++i)
        if (!same(a[i], b[i]))
            out += "\n  " + describe(rays[i], a[i]) + "\n  reference: " + describe(rays[i], b[i]), --limit;
    return out;
}

inline double agreement(const std::vector<RayHit>& a, const std::vector<RayHit>& b) {
    uint64_t same = 0;
    for (size_t i = 0; i < a.size(); ++i) same += sameHit(a[i], b[i]);
    return a.empty() ? 1.0 : double(same) / double(a.size());
}

// The exact closest hit of the ray on these float triangles: every triangle, in double
// (Möller-Trumbore; edges count as inside). Ground truth for rays on which backends disagree.
inline RayHit exactClosest(const Mesh& mesh, const Ray& ray) {
    RayHit best;
    double bestT = INFINITY;
    const double o[3] = {ray.origin.x, ray.origin.y, ray.origin.z},
                 d[3] = {ray.direction.x, ray.direction.y, ray.direction.z};
    for (uint32_t t = 0; t < mesh.count(); ++t) {
        double v[3][3];
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 3; ++c) v[k][c] = mesh.positions[mesh.indices[3 * t + k]][c];
        const double e1[3] = {v[1][0] - v[0][0], v[1][1] - v[0][1], v[1][2] - v[0][2]};
        const double e2[3] = {v[2][0] - v[0][0], v[2][1] - v[0][1], v[2][2] - v[0][2]};
        const double p[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2],
                             d[0] * e2[1] - d[1] * e2[0]};
        const double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
        if (det == 0) continue;
        const double s[3] = {o[0] - v[0][0], o[1] - v[0][1], o[2] - v[0][2]};
        const double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
        const double q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2],
                             s[0] * e1[1] - s[1] * e1[0]};
        const double w = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
        const double dist = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
        if (u < 0 || w < 0 || u + w > 1 || dist < 0 || dist >= bestT) continue;
        bestT = dist, best = {true, float(dist), t, det < 0};
    }
    return best;
}

// The same answer: both miss, or the same triangle, or the same t to 1e-5 relative (another
// triangle through the same point: an edge, a vertex or a coincident face).
inline bool sameAnswer(const RayHit& a, const RayHit& b) {
    return a.found == b.found && (!a.found || a.triangle == b.triangle ||
                                  std::abs(a.t - b.t) <= 1e-5f * std::max(1.0f, std::abs(b.t)));
}

// ---- streaming renders ----

inline std::string tmpPath(const std::string& name) {
    const std::filesystem::path dir = test::testTmpDir("stress");
    std::filesystem::create_directories(dir);
    return (dir / name).string();
}

// Lossless positions (quantizeBits 0): the package holds the very floats the ray-level cases
// trace, so the streaming figures measure the tracer, not the codec. Rebuilt on every run.
inline std::string packageFromMesh(const std::string& name, const Mesh& mesh,
                                   uint64_t chunkBytes = 32 << 10) {
    const std::string path = tmpPath(name + ".vast");
    PackageBuildOptions options;
    options.chunkSizeBytes = chunkBytes;
    options.quantizeBits = 0;
    options.progress = Progress::Mode::None;
    auto report = buildPackage(toTriangleMesh(mesh), path, options);
    EXPECT_TRUE(report) << report.message();
    return path;
}

// A render of the streaming renderer at an ample and at a two-slot budget, and the Embree
// reference of the same package. The ample budget renders twice in one open scene: the second
// finds every chunk resident (one walk pass per stream) and must equal the first, which paged
// chunks in between passes, bit for bit.
struct StreamingTrio {
    RenderImage reference, ample, tight;
    StreamingStats ampleStats, warmStats, tightStats;
};

inline std::optional<StreamingTrio> renderTrio(const std::string& path, const RenderOptions& o) {
    StreamingTrio trio;
    auto reference = renderEmbree(path, o);
    EXPECT_TRUE(reference) << reference.message();
    auto renders = renderVulkanColdAndWarm(path, o, 256ull << 20, &trio.ampleStats, &trio.warmStats);
    EXPECT_TRUE(renders) << renders.message();
    std::optional<RenderImage> ample;
    if (renders) {
        const RenderImage &cold = renders->first, &warm = renders->second;
        auto same = [](const auto& a, const auto& b) {
            return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0;
        };
        EXPECT_TRUE(same(cold.rgb, warm.rgb) && same(cold.alpha, warm.alpha) && same(cold.depth, warm.depth) &&
                    same(cold.normal, warm.normal) && same(cold.primId, warm.primId) &&
                    same(cold.chunkId, warm.chunkId) && same(cold.cost, warm.cost))
            << path << ": the warm render differs from the cold one";
        EXPECT_GT(trio.warmStats.walkedRays, 0u) << path;
        EXPECT_EQ(trio.warmStats.chunkLoads, 0u) << path << ": the warm render loaded chunks";
        ample = std::move(renders->first);
    }
    const uint64_t tight = budgetForSlots(path, 2, o.aovs);
    EXPECT_GT(tight, 0u) << path;
    auto small = renderVulkan(path, o, tight, &trio.tightStats);
    EXPECT_TRUE(small) << small.message();
    if (!reference || !ample || !small) return std::nullopt;
    trio.reference = std::move(*reference), trio.ample = std::move(*ample), trio.tight = std::move(*small);
    EXPECT_EQ(trio.tightStats.slots, 2u);
    EXPECT_LE(trio.tightStats.peakDeviceBytes, tight);
    return trio;
}

// AOV-only renders: pixel-centre rays (the primid/depth AOVs), one sample, no bounces to speak of.
inline RenderOptions aimedRender(uint32_t width, uint32_t height, const Camera& camera,
                                 uint32_t aovs = kAovPrimId | kAovDepth) {
    RenderOptions o;
    o.width = width, o.height = height;
    o.samplesPerPixel = 1;
    o.maxDepth = 1;
    o.integrator = IntegratorKind::AmbientOcclusion;
    o.aovs = aovs;
    o.frameScene = false;
    o.camera = camera;
    o.threads = 0;
    return o;
}

inline double primIdAgreement(const RenderImage& a, const RenderImage& b) {
    uint64_t same = 0;
    for (size_t i = 0; i < a.primId.size(); ++i) same += a.primId[i] == b.primId[i];
    return a.primId.empty() ? 1.0 : double(same) / double(a.primId.size());
}

inline uint64_t missCount(const RenderImage& image) {
    uint64_t misses = 0;
    for (uint32_t id : image.primId) misses += id == kMissPrimId;
    return misses;
}

inline float maxAbs(Vec3f v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

}  // namespace vastray::stress
