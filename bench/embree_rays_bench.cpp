// Reference ray throughput of the Embree backend: camera (primary, coherent) rays and
// diffuse (cosine-sampled from the primary hits, incoherent) closest-hit rays per second.
// Usage: embree_rays_bench [--threads N] [--resolution WxH] SCENE...
//   SCENE is a mesh file, a .vast package, or gen:KIND:TRIANGLES (generated to a temp PLY).
//   Exit status 2 for a bad flag, 1 when a scene cannot be loaded or built (it is named; the
//   other scenes still run).
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "BenchFlags.h"
#include "vastray/core/Camera.h"
#include "vastray/core/Random.h"
#include "vastray/core/RayOffset.h"
#include "vastray/core/RenderOptions.h"
#include "vastray/core/RenderStats.h"
#include "vastray/core/Sampling.h"
#include "vastray/cpu/EmbreeScene.h"
#include "vastray/cpu/RenderScene.h"
#include "vastray/streamer/Generate.h"

namespace vastray {
namespace {

using Clock = std::chrono::steady_clock;
constexpr float kInf = 1e30f;
constexpr double kMinSeconds = 2.0;  // repeat passes until at least this long

struct Bench {
    uint32_t width = 1024, height = 768;
};

Result<RenderScene> loadScene(const std::string& spec) {
    if (spec.rfind("gen:", 0) != 0) return loadRenderScene(spec);
    const size_t colon = spec.find(':', 4);
    auto kind = parseGeneratorKind(spec.substr(4, colon - 4));
    if (!kind || colon == std::string::npos) return Status::error(spec + ": expected gen:KIND:TRIANGLES");
    GenerateOptions options;
    options.kind = *kind;
    auto triangles = bench::parseFlagNumber<uint64_t>(spec, spec.substr(colon + 1), 0, UINT64_MAX);
    if (!triangles) return triangles.status();
    options.triangles = *triangles;
    const std::string path =
        (std::filesystem::temp_directory_path() / ("vastray-bench-" + spec.substr(4) + ".ply")).string();
    VASTRAY_TRY(generateToPly(options, path));
    auto scene = loadRenderScene(path);
    std::filesystem::remove(path);
    return scene;
}

// Runs `pass` (which returns the rays it traced) until kMinSeconds; returns rays/s.
template <typename Pass>
double throughput(Pass pass) {
    uint64_t rays = 0;
    const Clock::time_point start = Clock::now();
    double seconds = 0;
    do {
        rays += pass();
        seconds = std::chrono::duration<double>(Clock::now() - start).count();
    } while (seconds < kMinSeconds);
    return double(rays) / seconds;
}

struct PrimaryHit {
    Vec3f origin, normal;
    bool valid = false;
};

struct Scene {
    const TriangleMesh& mesh;
    const EmbreeScene& tracer;
};

// Pixel-centre camera rays (the renderer's camera, framing the scene); keeps each hit's
// offset origin and facing normal for the diffuse pass.
double measurePrimary(const Scene& scene, const Bench& bench, std::vector<PrimaryHit>& hits) {
    const CameraRays camera(frameBounds(scene.mesh.bounds(), 45, float(bench.width) / bench.height),
                            bench.width, bench.height);
    hits.assign(uint64_t(bench.width) * bench.height, PrimaryHit{});
    return throughput([&] {
        tbb::parallel_for(
            tbb::blocked_range<uint64_t>(0, hits.size(), 4096), [&](const tbb::blocked_range<uint64_t>& r) {
                for (uint64_t p = r.begin(); p != r.end(); ++p) {
                    const Ray ray =
                        camera.primary(uint32_t(p % bench.width), uint32_t(p / bench.width), 0.5f, 0.5f);
                    SceneHit hit;
                    PrimaryHit& out = hits[p];
                    out.valid = scene.tracer.intersect(ray, kInf, &hit);
                    if (!out.valid) continue;
                    const auto corner = [&](int i) {
                        return scene.mesh.positions[scene.mesh.indices[3 * hit.triangle + i]];
                    };
                    const Vec3f v0 = corner(0), v1 = corner(1), v2 = corner(2);
                    out.normal = normalize(cross(v1 - v0, v2 - v0));
                    if (dot(out.normal, ray.direction) > 0) out.normal = out.normal * -1.0f;
                    out.origin = offsetRayOrigin(v0 + (v1 - v0) * hit.u + (v2 - v0) * hit.v, out.normal);
                }
            });
        return uint64_t(hits.size());
    });
}

// One cosine-sampled closest-hit ray per primary hit, a new sample index every pass.
double measureDiffuse(const Scene& scene, const std::vector<PrimaryHit>& hits, uint64_t hitCount) {
    uint32_t sample = 0;
    return throughput([&] {
        const uint32_t pass = sample++;
        tbb::parallel_for(
            tbb::blocked_range<uint64_t>(0, hits.size(), 4096), [&](const tbb::blocked_range<uint64_t>& r) {
                for (uint64_t p = r.begin(); p != r.end(); ++p) {
                    if (!hits[p].valid) continue;
                    const RandomKey key{uint32_t(p), pass, 1};
                    const Vec3f local = cosineHemisphere(randomFloat(key, kDimDirectionU, 0),
                                                         randomFloat(key, kDimDirectionV, 0));
                    SceneHit hit;
                    scene.tracer.intersect(
                        {hits[p].origin, normalize(frameAround(hits[p].normal).toWorld(local))}, kInf, &hit);
                }
            });
        return hitCount;
    });
}

// False when the scene could not be loaded or built (the message is on stderr).
bool runScene(const std::string& spec, const Bench& bench) {
    auto loaded = loadScene(spec);
    if (!loaded) {
        std::fprintf(stderr, "embree_rays_bench: %s\n", loaded.message().c_str());
        return false;
    }
    const Clock::time_point buildStart = Clock::now();
    auto embree = EmbreeScene::build(loaded->mesh);
    if (!embree) {
        std::fprintf(stderr, "embree_rays_bench: %s: %s\n", spec.c_str(), embree.message().c_str());
        return false;
    }
    const double buildSeconds = std::chrono::duration<double>(Clock::now() - buildStart).count();
    const Scene scene{loaded->mesh, **embree};
    std::vector<PrimaryHit> hits;
    const double primary = measurePrimary(scene, bench, hits);
    uint64_t hitCount = 0;
    for (const PrimaryHit& h : hits) hitCount += h.valid;
    const double diffuse = measureDiffuse(scene, hits, hitCount);
    std::printf(
        "%-40s %11llu tris  build %6.2f s  primary %7.2f Mrays/s  diffuse %7.2f Mrays/s  (%.0f%% of pixels "
        "hit)  peak %.0f MiB\n",
        spec.c_str(), (unsigned long long)scene.mesh.triangleCount(), buildSeconds, primary / 1e6,
        diffuse / 1e6, 100.0 * double(hitCount) / double(hits.size()), double(peakHostBytes()) / (1 << 20));
    std::fflush(stdout);
    return true;
}

}  // namespace
}  // namespace vastray

int main(int argc, char** argv) {
    vastray::Bench bench;
    unsigned threads = 0;
    std::vector<std::string> scenes;
    bool help = false;
    const vastray::bench::FlagNumbers number("embree_rays_bench", 2);
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
            help = true;
        } else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) {
            threads = number.get<unsigned>("--threads", argv[++i]);
        } else if (!std::strcmp(argv[i], "--resolution") && i + 1 < argc) {
            const auto size =
                number.list<uint32_t>("--resolution", argv[++i], 'x', 1, vastray::kMaxImageSide, 2);
            bench.width = size[0], bench.height = size[1];
        } else {
            scenes.push_back(argv[i]);
        }
    }
    if (scenes.empty() || help) {
        std::fprintf(stderr,
                     "usage: embree_rays_bench [--threads N] [--resolution WxH] SCENE... (mesh, .vast, "
                     "gen:KIND:TRIANGLES)\n");
        return help ? 0 : 2;
    }
    std::optional<tbb::global_control> limit;
    if (threads) limit.emplace(tbb::global_control::max_allowed_parallelism, threads);
    std::printf("embree_rays_bench: %ux%u, %u threads (0 = all), closest-hit rays, >= %.0f s per figure\n",
                bench.width, bench.height, threads, vastray::kMinSeconds);
    // A scene that fails is named and skipped; the others still run, and the exit status is 1.
    int status = 0;
    for (const std::string& s : scenes)
        if (!vastray::runScene(s, bench)) status = 1;
    return status;
}
