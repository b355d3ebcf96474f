#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "Bvh4Walk.h"
#include "TestMeshes.h"
#include "vastray/core/Bvh4.h"

namespace vastray {
namespace {

using test::makeAxisGrid;
using test::makeIcosphere;
using test::makeSoup;
using test::Mesh;

Bvh4 build(const Mesh& m, const Bvh4BuildOptions& o = {}) {
    return buildBvh4(m.positions.data(), m.indices.data(), m.count(), o);
}

// Well formed (tests/Bvh4Walk.h), the order a permutation of the input, and maxDepth the
// deepest node, within the limit.
void expectWellFormed(const Mesh& m, const Bvh4& t) {
    ASSERT_EQ(t.order.size(), m.count());
    EXPECT_EQ(test::expectBvhHoldsItsTriangles(t, m.positions, m.indices, &t.order), t.maxDepth);
    EXPECT_LE(t.maxDepth, kBvh4MaxDepth);
}

TEST(Bvh4Test, EveryTriangleLiesInExactlyOneLeafInsideItsBoxes) {
    expectWellFormed(makeIcosphere(5, {1, 2, 3}, 4), build(makeIcosphere(5, {1, 2, 3}, 4)));
    expectWellFormed(makeSoup(5000, 7), build(makeSoup(5000, 7)));
    expectWellFormed(makeAxisGrid(40), build(makeAxisGrid(40)));
}

TEST(Bvh4Test, FarFromTheOriginTheBoxesStillEncloseTheirTriangles) {
    Mesh m = makeIcosphere(4, {0, 0, 0}, 0.01f);
    for (Vec3f& p : m.positions) p = p + Vec3f{1e6f, -3e5f, 2e7f};
    expectWellFormed(m, build(m));
}

TEST(Bvh4Test, IdenticalTrianglesStayWithinTheDepthLimit) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    for (int i = 0; i < 100000; ++i) m.indices.insert(m.indices.end(), {0, 1, 2});
    const Bvh4 t = build(m);
    expectWellFormed(m, t);
}

TEST(Bvh4Test, OneTriangleIsARootWithOneLeaf) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.indices = {0, 1, 2};
    const Bvh4 t = build(m);
    ASSERT_EQ(t.nodes.size(), 1u);
    EXPECT_EQ(t.nodes[0].child[0], bvh4LeafWord(0, 1));
    EXPECT_EQ(t.nodes[0].child[1], kBvh4EmptyChild);
    expectWellFormed(m, t);
    EXPECT_TRUE(buildBvh4(nullptr, nullptr, 0).nodes.empty());
}

TEST(Bvh4Test, BuildIsDeterministic) {
    const Mesh m = makeSoup(3000, 11, true);
    const Bvh4 a = build(m), b = build(m);
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    EXPECT_EQ(std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(Bvh4Node)), 0);
    EXPECT_EQ(a.order, b.order);
}

// The point of the format: at leaves of about five triangles the nodes cost about 5 bytes per
// triangle (a KD-tree's references alone cost 4 or more), and cheaper leaves buy larger ones.
TEST(Bvh4Test, NodesCostFewBytesPerTriangle) {
    const Mesh m = makeIcosphere(6, {0, 0, 0}, 1);
    auto bytesPerTriangle = [&](float intersectionCost, uint32_t maxLeaf) {
        const Bvh4 t = build(m, {1.0f, intersectionCost, maxLeaf, 16});
        expectWellFormed(m, t);
        return double(t.nodes.size() * sizeof(Bvh4Node)) / m.count();
    };
    const double fine = bytesPerTriangle(1.0f, 4), coarse = bytesPerTriangle(0.3f, 8);
    EXPECT_LT(coarse, 6.0);
    EXPECT_LT(coarse, 0.5 * fine);
}

TEST(Bvh4Test, ValidationNamesTheBadNode) {
    const Mesh m = makeIcosphere(3, {0, 0, 0}, 1);
    const Bvh4 good = build(m);
    ASSERT_GT(good.nodes.size(), 2u);
    auto broken = [&](auto&& change) {
        std::vector<Bvh4Node> nodes = good.nodes;
        change(nodes);
        return validateBvh4Nodes(nodes, m.count());
    };
    EXPECT_NE(broken([](auto& n) { n[1].child[0] = 0; }).find("BVH node 1: child 0 is not a later node"),
              std::string::npos);
    EXPECT_NE(broken([](auto& n) { n[0].child[0] = 100000; }).find("not a later node"), std::string::npos);
    EXPECT_NE(broken([&](auto& n) { n[0].child[0] = bvh4LeafWord(m.count() - 1, 2); }).find("leaf triangles past"),
              std::string::npos);
    EXPECT_NE(broken([](auto& n) { n[0].exponents = 0; }).find("exponent byte 0"), std::string::npos);
    EXPECT_NE(broken([](auto& n) { n[0].origin[1] = NAN; }).find("origin is not finite"), std::string::npos);
    // A chain deeper than the limit.
    std::vector<Bvh4Node> chain(kBvh4MaxDepth + 2, good.nodes[0]);
    for (size_t i = 0; i < chain.size(); ++i) {
        chain[i].child[0] = i + 1 < chain.size() ? uint32_t(i + 1) : kBvh4EmptyChild;
        chain[i].child[1] = chain[i].child[2] = chain[i].child[3] = kBvh4EmptyChild;
    }
    EXPECT_NE(validateBvh4Nodes(chain, m.count()).find("deeper than the limit"), std::string::npos);
}

}  // namespace
}  // namespace vastray
