// Ray throughput of the one-chunk GPU trace kernel (gpu/shaders/trace.comp): a generated
// sphere in one chunk, its KD-tree built with the package's compact options and with the
// default (deeper) options, coherent primary rays and incoherent rays. Each figure is the
// median wall time of GpuChunkTracer::trace() for the whole batch, which includes writing
// the rays into and reading the hits out of host-visible memory.
//
//   gpu_trace_bench [--triangles N] [--resolution WxH] [--repeat K] [--device I]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "BenchFlags.h"
#include "vastray/core/Camera.h"
#include "vastray/core/KdTree.h"
#include "vastray/core/RenderOptions.h"
#include "vastray/gpu/GpuChunkTracer.h"
#include "vastray/gpu/VulkanDevice.h"
#include "vastray/streamer/Generate.h"

namespace {

using namespace vastray;
using gpu::TraceHit;
using gpu::TraceRay;

struct Args {
    uint64_t triangles = 1000000;
    uint32_t width = 1920, height = 1080, repeat = 5;
    int device = -1;
};

struct MeshCollector final : MeshSink {
    std::vector<Vec3f> positions;
    std::vector<uint32_t> indices;
    Status begin(uint64_t v, uint64_t f) override {
        positions.reserve(v);
        indices.reserve(3 * f);
        return Status::ok();
    }
    Status vertex(Vec3f p) override {
        positions.push_back(p);
        return Status::ok();
    }
    Status face(uint32_t a, uint32_t b, uint32_t c) override {
        indices.insert(indices.end(), {a, b, c});
        return Status::ok();
    }
    Status end() override { return Status::ok(); }
};

TraceRay toTraceRay(const Ray& ray) {
    return {ray.origin.x, ray.origin.y, ray.origin.z, 0.0f, ray.direction.x, ray.direction.y, ray.direction.z, INFINITY};
}

std::vector<TraceRay> primaryRays(const Args& args) {
    const CameraRays camera(Camera{{0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 45.0f}, args.width, args.height);
    std::vector<TraceRay> rays;
    rays.reserve(size_t(args.width) * args.height);
    for (uint32_t y = 0; y < args.height; ++y)
        for (uint32_t x = 0; x < args.width; ++x) rays.push_back(toTraceRay(camera.primary(x, y, 0.5f, 0.5f)));
    return rays;
}

// Random origins inside the sphere, random directions: every ray hits, neighbours share nothing.
std::vector<TraceRay> incoherentRays(size_t count) {
    uint64_t state = 0x9E3779B97F4A7C15ull;
    auto next = [&state] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return float(state >> 40) / float(1 << 24) * 2.0f - 1.0f;
    };
    std::vector<TraceRay> rays(count);
    for (TraceRay& ray : rays) {
        Vec3f o{next(), next(), next()}, d{next(), next(), next()};
        o = o * 0.5f;
        if (d.x == 0 && d.y == 0 && d.z == 0) d = {1, 0, 0};
        ray = toTraceRay(Ray{o, d});
    }
    return rays;
}

void measure(gpu::GpuChunkTracer& tracer, const std::vector<TraceRay>& rays, const char* label, uint32_t repeat) {
    std::vector<double> seconds;
    std::vector<TraceHit> hits;
    for (uint32_t k = 0; k < repeat + 1; ++k) {
        const auto start = std::chrono::steady_clock::now();
        auto result = tracer.trace(rays);
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (!result) {
            std::fprintf(stderr, "trace failed: %s\n", result.message().c_str());
            std::exit(1);
        }
        if (k > 0) seconds.push_back(s);  // the first call also sizes the ray buffers
        hits = std::move(*result);
    }
    std::sort(seconds.begin(), seconds.end());
    const double median = seconds[seconds.size() / 2];
    uint64_t found = 0, nodes = 0, tests = 0;
    for (const TraceHit& h : hits) {
        found += (h.flags & gpu::kHitFound) != 0;
        nodes += h.nodesVisited;
        tests += h.trianglesTested;
    }
    std::printf("%-28s %9zu rays  hit %5.1f%%  median %8.2f ms  %8.1f M rays/s  nodes/ray %5.1f  tris/ray %5.1f\n",
                label, rays.size(), 100.0 * double(found) / double(hits.size()), median * 1e3,
                double(rays.size()) / median * 1e-6, double(nodes) / double(hits.size()),
                double(tests) / double(hits.size()));
}

// Every flag takes a value. A bad number ends the program with its message; anything else
// wrong returns false (the usage line).
bool parseArgs(int argc, char** argv, Args& args) {
    const bench::FlagNumbers number("gpu_trace_bench", 2);
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string flag = argv[i], value = argv[i + 1];
        if (flag == "--triangles") args.triangles = number.get<uint64_t>(flag, value, 20);
        else if (flag == "--resolution") {
            const auto size = number.list<uint32_t>(flag, value, 'x', 1, kMaxImageSide, 2);
            args.width = size[0], args.height = size[1];
        } else if (flag == "--repeat")  // measure() makes repeat + 1 calls, counted in a uint32_t
            args.repeat = number.get<uint32_t>(flag, value, 1, std::numeric_limits<uint32_t>::max() - 1);
        else if (flag == "--device")  // -1: VulkanDevice picks
            args.device = number.get<int>(flag, value, -1);
        else return false;
    }
    return argc % 2 == 1;
}

}  // namespace

int main(int argc, char** argv) {
    Args args;
    if (!parseArgs(argc, argv, args)) {
        std::fprintf(stderr, "usage: gpu_trace_bench [--triangles N] [--resolution WxH] [--repeat K] [--device I]\n");
        return 2;
    }
    gpu::VulkanDeviceOptions deviceOptions;
    if (args.device >= 0) deviceOptions.deviceIndex = args.device;
    auto device = gpu::VulkanDevice::create(deviceOptions);
    if (!device) {
        std::fprintf(stderr, "%s\n", device.message().c_str());
        return 1;
    }
    MeshCollector mesh;
    if (Status s = generate({GeneratorKind::Sphere, args.triangles, 1}, mesh); !s) {
        std::fprintf(stderr, "%s\n", s.message().c_str());
        return 1;
    }
    const uint32_t count = uint32_t(mesh.indices.size() / 3);
    std::printf("gpu_trace_bench: %s, sphere of %u triangles, %ux%u primary rays, median of %u\n",
                (*device)->info().name.c_str(), count, args.width, args.height, args.repeat);
    const std::vector<TraceRay> primary = primaryRays(args), incoherent = incoherentRays(primary.size());
    const struct {
        const char* name;
        KdBuildOptions options;
    } trees[] = {{"compact", compactKdBuildOptions(count)}, {"default", KdBuildOptions{}}};
    for (const auto& tree : trees) {
        const KdTree kd = buildKdTree(mesh.positions.data(), mesh.indices.data(), count, tree.options);
        auto tracer = gpu::GpuChunkTracer::create(**device);
        if (!tracer) {
            std::fprintf(stderr, "%s\n", tracer.message().c_str());
            return 1;
        }
        if (Status s = (*tracer)->upload({&kd, mesh.positions, mesh.indices, {}}); !s) {
            std::fprintf(stderr, "%s\n", s.message().c_str());
            return 1;
        }
        std::printf("tree %s: %zu nodes, %zu refs, depth %u, chunk %.1f MiB on the device\n", tree.name,
                    kd.nodes.size(), kd.leafRefs.size(), kd.maxDepth, double((*tracer)->residentChunkBytes()) / (1 << 20));
        measure(**tracer, primary, (std::string("primary, ") + tree.name).c_str(), args.repeat);
        measure(**tracer, incoherent, (std::string("incoherent, ") + tree.name).c_str(), args.repeat);
    }
    return 0;
}
