#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <utility>

#include "Infinity.h"
#include "TestMeshes.h"
#include "vastray/core/KdTree.h"
#include "vastray/core/TriangleIntersect.h"

namespace vastray {
namespace {

using test::kInf;
using test::makeAxisGrid;
using test::makeIcosphere;
using test::makeSoup;
using test::Mesh;
using test::randomVec;

struct RefHit {
    bool found = false;
    TriangleHit hit;
    uint32_t triangle = 0;
};

// Reference: every triangle, same triangle test, same tie rule.
RefHit bruteForce(const Mesh& m, const Ray& ray, float tMin, float tMax) {
    RefHit best;
    WatertightRay wr;
    if (!prepareWatertightRay(ray, &wr)) return best;
    for (uint32_t i = 0; i < m.count(); ++i) {
        TriangleHit h;
        const bool cull = !m.singleSided.empty() && m.singleSided[i];
        if (!intersectTriangle(wr, m.positions[m.indices[3 * i]], m.positions[m.indices[3 * i + 1]],
                               m.positions[m.indices[3 * i + 2]], cull, tMin, tMax, &h))
            continue;
        const bool better = !best.found || h.t < best.hit.t ||
                            (h.t == best.hit.t && (h.frontFacing != best.hit.frontFacing ? h.frontFacing
                                                                                          : i < best.triangle));
        if (better) best = {true, h, i};
    }
    return best;
}

KdHit traceTree(const Mesh& m, const KdTree& tree, const Ray& ray, float tMin, float tMax, bool* found) {
    KdHit hit;
    *found = intersectKdTree(tree, m.positions.data(), m.indices.data(),
                             m.singleSided.empty() ? nullptr : m.singleSided.data(), ray, tMin, tMax, &hit);
    return hit;
}

// Same triangle and bit-identical t: both sides run the same triangle test on the same ray, so
// any difference is a traversal bug (a skipped node or an order-dependent tie).
int countMismatches(const Mesh& m, const KdTree& tree, const std::vector<Ray>& rays, float tMin = 0,
                    float tMax = kInf) {
    int mismatches = 0;
    for (const Ray& ray : rays) {
        bool found;
        const KdHit hit = traceTree(m, tree, ray, tMin, tMax, &found);
        const RefHit ref = bruteForce(m, ray, tMin, tMax);
        const bool same = found == ref.found && (!found || (hit.triangle == ref.triangle && hit.t == ref.hit.t &&
                                                             hit.frontFacing == ref.hit.frontFacing));
        if (!same && mismatches++ < 5)
            ADD_FAILURE() << "ray o=(" << ray.origin.x << "," << ray.origin.y << "," << ray.origin.z << ") d=("
                          << ray.direction.x << "," << ray.direction.y << "," << ray.direction.z << ") tree "
                          << found << " tri " << hit.triangle << " t " << hit.t << " / ref " << ref.found
                          << " tri " << ref.triangle << " t " << ref.hit.t;
    }
    return mismatches;
}

std::vector<Ray> randomRays(std::mt19937& rng, int count, float extent) {
    std::vector<Ray> rays;
    for (int i = 0; i < count; ++i) rays.push_back({randomVec(rng, -extent, extent), randomVec(rng, -1, 1)});
    return rays;
}

// Rays with one or two zero direction components, from random origins.
std::vector<Ray> axisRays(std::mt19937& rng, int count, float extent) {
    std::vector<Ray> rays = randomRays(rng, count, extent);
    for (size_t i = 0; i < rays.size(); ++i) {
        rays[i].direction[int(i % 3)] = 0.0f;
        if (i % 2) rays[i].direction[int((i + 1) % 3)] = 0.0f;
    }
    return rays;
}

// Rays whose origin lies exactly on a split plane of the tree, half of them running inside it.
std::vector<Ray> splitPlaneRays(std::mt19937& rng, const KdTree& tree, int count, float extent) {
    std::vector<Ray> rays = randomRays(rng, count, extent);
    std::vector<std::pair<int, float>> planes;
    for (const KdNode& n : tree.nodes)
        if (!n.isLeaf()) planes.push_back({int(n.axis()), n.split()});
    for (size_t i = 0; i < rays.size() && !planes.empty(); ++i) {
        const auto [axis, split] = planes[rng() % planes.size()];
        rays[i].origin[axis] = split;
        if (i % 2) rays[i].direction[axis] = 0.0f;
    }
    return rays;
}

// Rays aimed at points of triangle edges and at vertices, from random origins.
std::vector<Ray> edgeRays(std::mt19937& rng, const Mesh& m, int count, float extent) {
    std::vector<Ray> rays;
    std::uniform_real_distribution<float> s(0.0f, 1.0f);
    for (int i = 0; i < count; ++i) {
        const uint32_t tri = rng() % m.count();
        const Vec3f a = m.positions[m.indices[3 * tri + i % 3]], b = m.positions[m.indices[3 * tri + (i + 1) % 3]];
        const Vec3f target = (i % 4 == 0) ? a : a + (b - a) * s(rng);
        const Vec3f origin = randomVec(rng, -extent, extent);
        rays.push_back({origin, target - origin});
        if (i % 8 == 1) rays.back() = {a - (b - a) * 0.5f, b - a};  // running along the edge
    }
    return rays;
}

void expectMatchesBruteForce(const Mesh& m, uint32_t seed, float extent) {
    const KdTree tree = m.build();
    std::mt19937 rng(seed);
    EXPECT_EQ(countMismatches(m, tree, randomRays(rng, 6000, extent)), 0);
    EXPECT_EQ(countMismatches(m, tree, axisRays(rng, 3000, extent)), 0);
    EXPECT_EQ(countMismatches(m, tree, splitPlaneRays(rng, tree, 3000, extent)), 0);
    EXPECT_EQ(countMismatches(m, tree, edgeRays(rng, m, 3000, extent)), 0);
}

TEST(KdTree, IcosphereMatchesBruteForce) {
    expectMatchesBruteForce(makeIcosphere(3, {0.25f, -0.5f, 0.125f}, 2.0f), 1, 3.0f);
}

TEST(KdTree, SoupMatchesBruteForce) { expectMatchesBruteForce(makeSoup(2000, 5), 2, 12.0f); }

TEST(KdTree, AxisPlaneGridMatchesBruteForce) {
    const Mesh m = makeAxisGrid(5);
    expectMatchesBruteForce(m, 3, 6.0f);
    // Lattice-aligned rays: origins on lattice planes, directions along axes and diagonals.
    std::mt19937 rng(4);
    std::vector<Ray> rays;
    for (int i = 0; i < 4000; ++i) {
        Vec3f o{float(rng() % 13) * 0.5f - 0.5f, float(rng() % 13) * 0.5f - 0.5f, float(rng() % 13) * 0.5f - 0.5f};
        Vec3f d{float(int(rng() % 3) - 1), float(int(rng() % 3) - 1), float(int(rng() % 3) - 1)};
        if (d == Vec3f{}) d.x = 1;
        rays.push_back({o, d});
    }
    EXPECT_EQ(countMismatches(m, m.build(), rays), 0);
}

TEST(KdTree, RespectsRayInterval) {
    const Mesh m = makeIcosphere(2, {0, 0, 0}, 1.0f);
    const KdTree tree = m.build();
    std::mt19937 rng(9);
    const std::vector<Ray> rays = randomRays(rng, 3000, 2.0f);
    EXPECT_EQ(countMismatches(m, tree, rays, 0.5f, 1.5f), 0);
    EXPECT_EQ(countMismatches(m, tree, rays, 1.0f, 1.0001f), 0);
    // Exact boundaries: a hit exactly at tMin or tMax counts, one ulp outside does not.
    const Ray ray{{0, 0, -3}, {0, 0, 1}};
    bool found;
    const float t = traceTree(m, tree, ray, 0, kInf, &found).t;
    ASSERT_TRUE(found);
    EXPECT_TRUE((traceTree(m, tree, ray, t, t, &found), found));
    EXPECT_FALSE((traceTree(m, tree, ray, std::nextafter(t, kInf), t + 0.2f, &found), found));
    EXPECT_FALSE((traceTree(m, tree, ray, 0, std::nextafter(t, 0.0f), &found), found));
}

TEST(KdTree, OccludedAgreesWithIntersect) {
    const Mesh m = makeSoup(1500, 8);
    const KdTree tree = m.build();
    std::mt19937 rng(10);
    std::uniform_real_distribution<float> len(0.0f, 20.0f);
    int disagreements = 0;
    for (const Ray& ray : randomRays(rng, 5000, 12.0f)) {
        const float tMax = len(rng);
        bool found;
        traceTree(m, tree, ray, 0, tMax, &found);
        disagreements += found != occludedKdTree(tree, m.positions.data(), m.indices.data(), nullptr, ray, 0, tMax);
    }
    EXPECT_EQ(disagreements, 0);
}

// Rays from points inside a closed sphere aimed exactly at its vertices and at points of its
// shared edges must always hit it: a single escape is a crack.
TEST(KdTree, ClosedMeshIsWatertight) {
    const Mesh m = makeIcosphere(4, {0.3f, -0.2f, 0.1f}, 1.0f);
    const KdTree tree = m.build();
    std::mt19937 rng(12);
    std::uniform_real_distribution<float> s(0.0f, 1.0f);
    int escapes = 0;
    for (int i = 0; i < 30000; ++i) {
        const uint32_t tri = rng() % m.count();
        const Vec3f a = m.positions[m.indices[3 * tri + i % 3]], b = m.positions[m.indices[3 * tri + (i + 1) % 3]];
        const Vec3f target = (i % 3 == 0) ? a : (i % 3 == 1 ? (a + b) * 0.5f : a + (b - a) * s(rng));
        const Vec3f origin = Vec3f{0.3f, -0.2f, 0.1f} + randomVec(rng, -0.5f, 0.5f);
        bool found;
        traceTree(m, tree, {origin, target - origin}, 0, kInf, &found);
        escapes += !found;
    }
    EXPECT_EQ(escapes, 0);
}

TEST(KdTree, SingleSidedTrianglesAreInvisibleFromBehind) {
    Mesh m;
    m.positions = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, 1}, {4, 0, 1}, {0, 4, 1}};
    m.indices = {0, 1, 2, 3, 4, 5};  // both counter-clockwise seen from +z
    m.singleSided = {1, 0};          // triangle 0 single-sided, triangle 1 double-sided
    const KdTree tree = m.build();
    bool found;
    KdHit hit = traceTree(m, tree, {{1, 1, -2}, {0, 0, 1}}, 0, kInf, &found);  // from behind
    ASSERT_TRUE(found);
    EXPECT_EQ(hit.triangle, 1u);
    EXPECT_FALSE(hit.frontFacing);
    hit = traceTree(m, tree, {{1, 1, 0.5f}, {0, 0, -1}}, 0, kInf, &found);  // from the front
    ASSERT_TRUE(found);
    EXPECT_EQ(hit.triangle, 0u);
    EXPECT_TRUE(hit.frontFacing);
    hit = traceTree(m, tree, {{1, 1, 3}, {0, 0, -1}}, 0, kInf, &found);
    EXPECT_EQ(hit.triangle, 1u);
    EXPECT_TRUE(hit.frontFacing);
}

// Coincident opposite-facing triangles hit at the bit-identical t: the front-facing one wins
// from both sides, whatever the index order and whichever leaves reference them.
TEST(KdTree, CoincidentTrianglesFrontFacingWins) {
    Mesh m = makeSoup(300, 13);
    const uint32_t first = m.count();
    const uint32_t base = uint32_t(m.positions.size());
    m.positions.insert(m.positions.end(), {{-8, -8, 0.5f}, {8, -8, 0.5f}, {-8, 8, 0.5f}});
    m.indices.insert(m.indices.end(), {base, base + 2, base + 1, base, base + 1, base + 2});
    const KdTree tree = m.build();
    std::mt19937 rng(14);
    int wrong = 0;
    for (int i = 0; i < 2000; ++i) {
        const float x = float(int(rng() % 64) - 40) * 0.125f, y = float(int(rng() % 64) - 40) * 0.125f;
        const bool fromAbove = i % 2;
        const Ray ray{{x, y, fromAbove ? 20.0f : -20.0f}, {0, 0, fromAbove ? -1.0f : 1.0f}};
        bool found;
        const KdHit hit = traceTree(m, tree, ray, 0, kInf, &found);
        const RefHit ref = bruteForce(m, ray, 0, kInf);
        if (ref.found && ref.hit.t == 19.5f) wrong += !(hit.triangle == (fromAbove ? first + 1 : first));
        wrong += !(found == ref.found && hit.triangle == ref.triangle);
    }
    EXPECT_EQ(wrong, 0);
}

TEST(KdTree, BuildIsDeterministic) {
    const Mesh m = makeSoup(5000, 21);
    const KdTree a = m.build(), b = m.build();
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    ASSERT_EQ(a.leafRefs, b.leafRefs);
    EXPECT_EQ(std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(KdNode)), 0);
    EXPECT_EQ(a.maxDepth, b.maxDepth);
}

TEST(KdTree, EmptyAndSingleTriangle) {
    const KdTree empty = buildKdTree(nullptr, nullptr, 0);
    EXPECT_TRUE(empty.bounds.isEmpty());
    KdHit hit;
    EXPECT_FALSE(intersectKdTree(empty, nullptr, nullptr, nullptr, {{0, 0, 0}, {1, 0, 0}}, 0, kInf, &hit));
    EXPECT_FALSE(occludedKdTree(empty, nullptr, nullptr, nullptr, {{0, 0, 0}, {1, 0, 0}}, 0, kInf));
    Mesh one;
    one.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    one.indices = {0, 1, 2};
    const KdTree tree = one.build();
    ASSERT_EQ(tree.nodes.size(), 1u);
    EXPECT_TRUE(tree.nodes[0].isLeaf());
    bool found;
    EXPECT_EQ(traceTree(one, tree, {{0.25f, 0.25f, 1}, {0, 0, -1}}, 0, kInf, &found).t, 1.0f);
    EXPECT_TRUE(found);
    EXPECT_FALSE((traceTree(one, tree, {{0.25f, 0.25f, 1}, {0, 0, 0}}, 0, kInf, &found), found));
    EXPECT_FALSE((traceTree(one, tree, {{0.25f, 0.25f, 1}, {0, NAN, -1}}, 0, kInf, &found), found));
}

// Walks the tree: every node is reached once, child links point forward, leaf ranges are
// in bounds, the recorded depth is the real one and within the cap.
uint32_t checkStructure(const KdTree& tree, uint32_t triangleCount) {
    std::vector<std::pair<uint32_t, uint32_t>> stack = {{0, 0}};
    uint32_t visited = 0, depth = 0;
    while (!stack.empty()) {
        const auto [index, d] = stack.back();
        stack.pop_back();
        ++visited;
        depth = std::max(depth, d);
        const KdNode& n = tree.nodes.at(index);
        if (n.isLeaf()) {
            EXPECT_LE(size_t(n.firstRef()) + n.primitiveCount(), tree.leafRefs.size());
            for (uint32_t i = 0; i < n.primitiveCount(); ++i) EXPECT_LT(tree.leafRefs[n.firstRef() + i], triangleCount);
            continue;
        }
        EXPECT_GT(n.aboveChild(), index + 1);
        stack.push_back({index + 1, d + 1});
        stack.push_back({n.aboveChild(), d + 1});
    }
    EXPECT_EQ(visited, tree.nodes.size());
    EXPECT_EQ(depth, tree.maxDepth);
    return depth;
}

TEST(KdTree, DepthNeverExceedsCap) {
    Mesh pile;  // 3000 copies of one triangle plus a few others: SAH can never separate them
    for (int i = 0; i < 3000; ++i) {
        pile.positions.insert(pile.positions.end(), {{0, 0, 0}, {1, 0, 0}, {0, 1, 1}});
        pile.indices.insert(pile.indices.end(), {uint32_t(3 * i), uint32_t(3 * i + 1), uint32_t(3 * i + 2)});
    }
    KdBuildOptions deep;
    deep.maxDepth = 1000;  // clamped to kMaxKdDepth
    deep.maxLeafSize = 0;
    EXPECT_LE(checkStructure(pile.build(deep), pile.count()), kMaxKdDepth);
    const Mesh soup = makeSoup(20000, 3);
    EXPECT_LE(checkStructure(soup.build(deep), soup.count()), kMaxKdDepth);
    const KdTree normal = soup.build();
    EXPECT_LE(checkStructure(normal, soup.count()), uint32_t(8 + 1.3 * std::log2(20000.0)));
    const KdTreeStats stats = computeKdTreeStats(normal);
    EXPECT_EQ(stats.nodes, normal.nodes.size());
    EXPECT_EQ(stats.references, normal.leafRefs.size());
}

// A tree cut at any depth still finds every hit brute force finds (same triangle, same t), holds
// fewer nodes and no more references, and each cut leaf holds its subtree's triangles once,
// ascending; cutting below the tree's depth changes nothing.
TEST(KdTree, TruncatedTreesFindTheSameHits) {
    for (const Mesh& m : {makeIcosphere(3, {0.25f, -0.5f, 0.125f}, 2.0f), makeSoup(2000, 5)}) {
        const KdTree full = m.build();
        const KdTree same = truncateKdTree(full, full.maxDepth);
        ASSERT_EQ(same.nodes.size(), full.nodes.size());
        EXPECT_EQ(std::memcmp(same.nodes.data(), full.nodes.data(), full.nodes.size() * sizeof(KdNode)), 0);
        EXPECT_EQ(same.leafRefs, full.leafRefs);
        std::mt19937 rng(7);
        const std::vector<Ray> rays = randomRays(rng, 3000, 6.0f), planes = splitPlaneRays(rng, full, 2000, 6.0f);
        for (uint32_t depth : {0u, 2u, full.maxDepth / 2, full.maxDepth - 1}) {
            const KdTree cut = truncateKdTree(full, depth);
            EXPECT_EQ(checkStructure(cut, m.count()), std::min(depth, full.maxDepth));
            EXPECT_LT(cut.nodes.size(), full.nodes.size()) << depth;
            EXPECT_LE(cut.leafRefs.size(), full.leafRefs.size()) << depth;
            for (const KdNode& n : cut.nodes) {
                if (!n.isLeaf()) continue;
                const uint32_t* refs = cut.leafRefs.data() + n.firstRef();
                for (uint32_t i = 1; i < n.primitiveCount(); ++i) EXPECT_NE(refs[i - 1], refs[i]);
            }
            EXPECT_EQ(countMismatches(m, cut, rays), 0) << depth;
            EXPECT_EQ(countMismatches(m, cut, planes), 0) << depth;
        }
        const KdTree root = truncateKdTree(full, 0);
        ASSERT_EQ(root.nodes.size(), 1u);
        EXPECT_EQ(root.leafRefs.size(), m.count()) << "the root leaf holds every triangle once";
        EXPECT_TRUE(std::is_sorted(root.leafRefs.begin(), root.leafRefs.end()));
    }
}

}  // namespace
}  // namespace vastray
