// Generator throughput in triangles/s (reported as items/s, wall clock: terrain and soup use
// TBB threads): into a sink that only counts (the generator's own cost) and into a PLY file
// under /tmp or $VASTRAY_BENCH_DIR (what `vastray generate` does).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "vastray/streamer/Generate.h"

namespace {

using vastray::GeneratorKind;

struct CountingSink final : vastray::MeshSink {
    uint64_t vertices = 0, faces = 0;
    float checksum = 0;  // keeps the positions observable so the generator cannot be elided
    vastray::Status begin(uint64_t, uint64_t) override { return vastray::Status::ok(); }
    vastray::Status vertex(vastray::Vec3f p) override {
        ++vertices;
        checksum += p.y;
        return vastray::Status::ok();
    }
    vastray::Status face(uint32_t, uint32_t, uint32_t) override {
        ++faces;
        return vastray::Status::ok();
    }
    vastray::Status end() override { return vastray::Status::ok(); }
};

void toCountingSink(benchmark::State& state, GeneratorKind kind) {
    const vastray::GenerateOptions options{kind, static_cast<uint64_t>(state.range(0)), 1};
    uint64_t triangles = 0;
    for (auto _ : state) {
        CountingSink sink;
        if (vastray::Status status = vastray::generate(options, sink); !status) {
            state.SkipWithError(status.message().c_str());
        }
        benchmark::DoNotOptimize(sink.checksum);
        triangles += sink.faces;
    }
    state.SetItemsProcessed(static_cast<int64_t>(triangles));
}

void toPlyFile(benchmark::State& state, GeneratorKind kind) {
    const vastray::GenerateOptions options{kind, static_cast<uint64_t>(state.range(0)), 1};
    const char* dir = std::getenv("VASTRAY_BENCH_DIR");  // e.g. /dev/shm to leave the disk out
    const std::string path = std::string(dir ? dir : "/tmp") + "/vastray_generate_bench_" +
                             vastray::generatorKindName(kind) + ".ply";
    const uint64_t triangles = vastray::generatedCounts(options)->triangles;
    for (auto _ : state) {
        if (vastray::Status status = vastray::generateToPly(options, path); !status) {
            state.SkipWithError(status.message().c_str());
        }
    }
    std::remove(path.c_str());
    state.SetItemsProcessed(static_cast<int64_t>(triangles * state.iterations()));
    const uint64_t vertices = vastray::generatedCounts(options)->vertices;
    state.SetBytesProcessed(static_cast<int64_t>((12 * vertices + 13 * triangles) * state.iterations()));
}

constexpr int64_t kTriangles = 4'000'000;

}  // namespace

BENCHMARK_CAPTURE(toCountingSink, sphere, GeneratorKind::Sphere)
    ->Arg(kTriangles)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(toCountingSink, terrain, GeneratorKind::Terrain)
    ->Arg(kTriangles)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(toCountingSink, soup, GeneratorKind::Soup)
    ->Arg(kTriangles)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(toCountingSink, city, GeneratorKind::City)
    ->Arg(kTriangles)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(toPlyFile, sphere, GeneratorKind::Sphere)
    ->Arg(kTriangles)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(toPlyFile, terrain, GeneratorKind::Terrain)
    ->Arg(kTriangles)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(toPlyFile, soup, GeneratorKind::Soup)
    ->Arg(kTriangles)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(toPlyFile, city, GeneratorKind::City)
    ->Arg(kTriangles)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_MAIN();
