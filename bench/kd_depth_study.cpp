// Chunk KD-tree size against traversal work (docs/PERF_NOTES.md, streaming item 10): one
// generated chunk-sized mesh, the chunk builder's options with the depth cap, intersection
// cost, empty-space bonus and leaf size varied; per variant the nodes, empty leaves and
// references per triangle, the resident bytes per triangle (positions, indices, nodes, refs;
// no primitive ids) and, over 200,000 random rays through the box, the mean KD nodes visited
// and triangles tested (intersectKdTree's counters).
//
//   kd_depth_study [KIND] [TRIANGLES]      (defaults: city 100000)
#include <algorithm>
#include <bit>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "BenchFlags.h"
#include "vastray/core/KdTree.h"
#include "vastray/streamer/Generate.h"

using namespace vastray;

int main(int argc, char** argv) {
    const std::string kindName = argc > 1 ? argv[1] : "city";
    const bench::FlagNumbers number("kd_depth_study", 2);
    const uint64_t triangles = argc > 2 ? number.get<uint64_t>("TRIANGLES", argv[2]) : 100000;
    auto kind = parseGeneratorKind(kindName);
    if (!kind) {
        std::fprintf(stderr, "kd_depth_study: %s\n", kind.message().c_str());
        return 2;
    }
    auto generated = generateMesh({*kind, triangles, 1});
    if (!generated) {
        std::fprintf(stderr, "kd_depth_study: %s\n", generated.message().c_str());
        return 1;
    }
    const TriangleMesh& mesh = *generated;
    const uint32_t count = uint32_t(mesh.triangleCount());
    Aabb bounds;
    for (const Vec3f& p : mesh.positions) bounds.extend(p);

    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(0, 1);
    std::vector<Ray> rays;
    for (int i = 0; i < 200000; ++i) {
        Ray r;
        r.origin = {bounds.lo.x + u(rng) * (bounds.hi.x - bounds.lo.x),
                    bounds.lo.y + u(rng) * (bounds.hi.y - bounds.lo.y) * 1.5f,
                    bounds.lo.z + u(rng) * (bounds.hi.z - bounds.lo.z)};
        r.direction = {u(rng) - 0.5f, u(rng) - 0.7f, u(rng) - 0.5f};
        rays.push_back(r);
    }

    struct Variant {
        const char* name;
        float intersectionCost, emptyBonus;
        uint32_t maxLeafSize;
        int depthOverLog2;  // depth cap = log2(N) + this
    };
    const Variant variants[] = {
        {"package (log2 N + 3)", 2.0f, 0.2f, 4, 3}, {"empty bonus 0", 2.0f, 0.0f, 4, 3},
        {"intersection cost 3", 3.0f, 0.2f, 4, 3},  {"cap log2 N + 1", 2.0f, 0.2f, 4, 1},
        {"cap log2 N", 2.0f, 0.2f, 4, 0},           {"cap log2 N - 1", 2.0f, 0.2f, 4, -1},
        {"cap log2 N - 2", 2.0f, 0.2f, 4, -2},      {"cap log2 N - 3", 2.0f, 0.2f, 4, -3},
    };
    std::printf("%s, %u triangles, %.2f vertices per triangle, %zu rays\n\n", kindName.c_str(), count,
                double(mesh.positions.size()) / count, rays.size());
    std::printf("| variant | nodes/tri | empty leaves/tri | refs/tri | resident B/tri | nodes per ray | triangles per ray |\n");
    std::printf("|---|---|---|---|---|---|---|\n");
    for (const Variant& v : variants) {
        KdBuildOptions options = compactKdBuildOptions(count);
        options.intersectionCost = v.intersectionCost;
        options.emptyBonus = v.emptyBonus;
        options.maxLeafSize = v.maxLeafSize;
        options.maxDepth = uint32_t(std::clamp(int(std::bit_width(count)) + v.depthOverLog2, 8, int(kMaxKdDepth)));
        const KdTree tree = buildKdTree(mesh.positions.data(), mesh.indices.data(), count, options);
        const KdTreeStats stats = computeKdTreeStats(tree);
        double nodes = 0, tested = 0;
        for (const Ray& r : rays) {
            KdHit hit;
            intersectKdTree(tree, mesh.positions.data(), mesh.indices.data(), nullptr, r, 0, 1e30f, &hit);
            nodes += hit.nodesVisited;
            tested += hit.trianglesTested;
        }
        const double bytes = 12.0 * double(mesh.positions.size()) / count + 12 + 8.0 * double(stats.nodes) / count +
                             4.0 * double(stats.references) / count;
        std::printf("| %s | %.2f | %.2f | %.2f | %.1f | %.1f | %.1f |\n", v.name, double(stats.nodes) / count,
                    double(stats.emptyLeaves) / count, double(stats.references) / count, bytes,
                    nodes / double(rays.size()), tested / double(rays.size()));
    }
    return 0;
}
