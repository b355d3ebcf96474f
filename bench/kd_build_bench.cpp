// KD-tree build throughput (triangles/s) and single-core traversal throughput (rays/s).
// Meshes are generated here so the benchmark depends on nothing but core.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <random>
#include <unordered_map>

#include "vastray/core/KdTree.h"

namespace vastray {
namespace {

struct BenchMesh {
    std::vector<Vec3f> positions;
    std::vector<uint32_t> indices;
    uint32_t count() const { return uint32_t(indices.size() / 3); }
};

// UV sphere with shared vertices and about `triangles` triangles.
BenchMesh makeSphere(uint32_t triangles) {
    const uint32_t rings = uint32_t(std::sqrt(triangles / 2.0)), segments = triangles / (2 * rings);
    BenchMesh m;
    for (uint32_t r = 0; r <= rings; ++r)
        for (uint32_t s = 0; s < segments; ++s) {
            const double theta = M_PI * r / rings, phi = 2 * M_PI * s / segments;
            m.positions.push_back({float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                                   float(std::sin(theta) * std::sin(phi))});
        }
    for (uint32_t r = 0; r < rings; ++r)
        for (uint32_t s = 0; s < segments; ++s) {
            const uint32_t a = r * segments + s, b = r * segments + (s + 1) % segments;
            const uint32_t c = a + segments, d = b + segments;
            m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
        }
    return m;
}

// Random triangles of random size and orientation in a cube: many overlaps, no structure.
BenchMesh makeSoup(uint32_t triangles) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> pos(-1.0f, 1.0f);
    const float size = 1.0f / std::cbrt(float(triangles));
    BenchMesh m;
    for (uint32_t i = 0; i < triangles; ++i) {
        const Vec3f c{pos(rng), pos(rng), pos(rng)};
        for (int k = 0; k < 3; ++k) {
            m.positions.push_back(c + Vec3f{pos(rng), pos(rng), pos(rng)} * size);
            m.indices.push_back(uint32_t(m.positions.size() - 1));
        }
    }
    return m;
}

const BenchMesh& cachedMesh(bool soup, uint32_t triangles) {
    static std::unordered_map<uint64_t, BenchMesh> cache;
    const uint64_t key = (uint64_t(soup) << 32) | triangles;
    auto it = cache.find(key);
    if (it == cache.end()) it = cache.emplace(key, soup ? makeSoup(triangles) : makeSphere(triangles)).first;
    return it->second;
}

KdBuildOptions benchOptions(bool import, uint32_t triangles) {
    return import ? compactKdBuildOptions(triangles) : KdBuildOptions{};
}

// SAH cost of the built tree relative to its root box, with the cost model of `options`
// (no empty bonus): sum over interior nodes of P(node) * traversalCost plus sum over leaves of
// P(leaf) * intersectionCost * references. Lower is better; comparable only for equal options.
double treeSahCost(const KdTree& tree, const KdBuildOptions& options) {
    struct Item {
        uint32_t node;
        Aabb box;
    };
    const double rootArea = tree.bounds.surfaceArea();
    if (tree.nodes.empty() || !(rootArea > 0)) return 0;
    std::vector<Item> stack{{0, tree.bounds}};
    double cost = 0;
    while (!stack.empty()) {
        const Item item = stack.back();
        stack.pop_back();
        const KdNode node = tree.nodes[item.node];
        const double p = item.box.surfaceArea() / rootArea;
        if (node.isLeaf()) {
            cost += p * options.intersectionCost * node.primitiveCount();
            continue;
        }
        cost += p * options.traversalCost;
        Aabb below = item.box, above = item.box;
        below.hi[int(node.axis())] = node.split();
        above.lo[int(node.axis())] = node.split();
        stack.push_back({item.node + 1, below});
        stack.push_back({node.aboveChild(), above});
    }
    return cost;
}

// FNV-1a over nodes and references: equal values mean (almost surely) byte-identical trees.
uint32_t treeHash(const KdTree& tree) {
    uint32_t h = 2166136261u;
    auto mix = [&h](uint32_t w) {
        for (int i = 0; i < 4; ++i) h = (h ^ ((w >> (8 * i)) & 0xffu)) * 16777619u;
    };
    for (const KdNode& n : tree.nodes) mix(n.word0), mix(n.word1);
    for (uint32_t r : tree.leafRefs) mix(r);
    return h;
}

void reportTree(benchmark::State& state, const KdTree& tree, const KdBuildOptions& options) {
    const KdTreeStats stats = computeKdTreeStats(tree);
    const double tris = double(state.range(0));
    state.counters["nodes"] = double(stats.nodes);
    state.counters["nodes/tri"] = double(stats.nodes) / tris;
    state.counters["refs/tri"] = double(stats.references) / tris;
    state.counters["depth"] = stats.maxDepth;
    state.counters["leafSize"] = stats.meanLeafSize;
    state.counters["sah"] = treeSahCost(tree, options);
    state.counters["hash"] = double(treeHash(tree));
}

void buildBench(benchmark::State& state, bool soup, bool import) {
    const BenchMesh& m = cachedMesh(soup, uint32_t(state.range(0)));
    const KdBuildOptions options = benchOptions(import, m.count());
    KdTree tree;
    for (auto _ : state) {
        tree = buildKdTree(m.positions.data(), m.indices.data(), m.count(), options);
        benchmark::DoNotOptimize(tree.nodes.data());
    }
    state.counters["Mtri/s"] = benchmark::Counter(double(m.count()) * double(state.iterations()) * 1e-6,
                                                  benchmark::Counter::kIsRate);
    reportTree(state, tree, options);
}

// Random rays from points around the mesh towards random points inside its bounds.
void traceBench(benchmark::State& state, bool soup, bool import) {
    const BenchMesh& m = cachedMesh(soup, uint32_t(state.range(0)));
    const KdTree tree = buildKdTree(m.positions.data(), m.indices.data(), m.count(),
                                    benchOptions(import, m.count()));
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<Ray> rays(1 << 16);
    for (Ray& r : rays) {
        r.origin = Vec3f{u(rng), u(rng), u(rng)} * 2.0f;
        r.direction = Vec3f{u(rng), u(rng), u(rng)} * 0.9f - r.origin;
    }
    size_t next = 0, hits = 0, nodes = 0, tests = 0;
    for (auto _ : state) {
        KdHit hit;
        hits += intersectKdTree(tree, m.positions.data(), m.indices.data(), nullptr, rays[next], 0.0f,
                                INFINITY, &hit);
        nodes += hit.nodesVisited;
        tests += hit.trianglesTested;
        next = (next + 1) & (rays.size() - 1);
    }
    const double n = double(state.iterations());
    state.counters["rays/s"] = benchmark::Counter(n, benchmark::Counter::kIsRate);
    state.counters["hitRate"] = double(hits) / n;
    state.counters["nodes/ray"] = double(nodes) / n;
    state.counters["tests/ray"] = double(tests) / n;
}

void BM_BuildSphere(benchmark::State& state) { buildBench(state, false, false); }
void BM_BuildSoup(benchmark::State& state) { buildBench(state, true, false); }
void BM_TraceSphere(benchmark::State& state) { traceBench(state, false, false); }
void BM_TraceSoup(benchmark::State& state) { traceBench(state, true, false); }
// Import options on chunk-sized meshes (a 2M-triangle sphere gives ~251k-triangle chunks).
void BM_ImportBuildSphere(benchmark::State& state) { buildBench(state, false, true); }
void BM_ImportBuildSoup(benchmark::State& state) { buildBench(state, true, true); }
void BM_ImportTraceSphere(benchmark::State& state) { traceBench(state, false, true); }
void BM_ImportTraceSoup(benchmark::State& state) { traceBench(state, true, true); }

BENCHMARK(BM_BuildSphere)->Arg(100000)->Arg(500000)->Arg(1000000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BuildSoup)->Arg(100000)->Arg(500000)->Arg(1000000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TraceSphere)->Arg(100000)->Arg(1000000);
BENCHMARK(BM_TraceSoup)->Arg(100000)->Arg(1000000);
BENCHMARK(BM_ImportBuildSphere)->Arg(100000)->Arg(250000)->Arg(400000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ImportBuildSoup)->Arg(100000)->Arg(250000)->Arg(400000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ImportTraceSphere)->Arg(250000);
BENCHMARK(BM_ImportTraceSoup)->Arg(250000);

}  // namespace
}  // namespace vastray

BENCHMARK_MAIN();
