// The icosphere is the scene whose exact answers we know: a closed, outward-wound unit sphere.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <utility>

#include "streamer/generate/RecordingSink.h"

namespace vastray::test {
namespace {

// Directed edge counts, keyed by (from, to).
std::map<std::pair<uint32_t, uint32_t>, int> directedEdges(const RecordingSink& mesh) {
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (const auto& f : mesh.faces) {
        for (int k = 0; k < 3; ++k) ++edges[{f[k], f[(k + 1) % 3]}];
    }
    return edges;
}

class SphereSizes : public ::testing::TestWithParam<uint64_t> {};

TEST_P(SphereSizes, IsAClosedConsistentlyOrientedManifold) {
    RecordingSink mesh = record(GeneratorKind::Sphere, GetParam());
    auto edges = directedEdges(mesh);
    // Each undirected edge used exactly twice, once in each direction <=> every directed edge
    // occurs once and its reverse occurs too.
    for (const auto& [edge, count] : edges) {
        ASSERT_EQ(count, 1) << "directed edge " << edge.first << "->" << edge.second;
        ASSERT_TRUE(edges.count({edge.second, edge.first}))
            << "open edge " << edge.first << "-" << edge.second;
    }
    const auto v = static_cast<int64_t>(mesh.vertices.size()), f = static_cast<int64_t>(mesh.faces.size());
    const auto e = static_cast<int64_t>(edges.size() / 2);
    EXPECT_EQ(v - e + f, 2) << "Euler characteristic of a sphere";
}

TEST_P(SphereSizes, VerticesLieOnTheUnitSphere) {
    RecordingSink mesh = record(GeneratorKind::Sphere, GetParam());
    // Normalized in double then rounded to float: each coordinate is off by at most half a
    // float ulp (6e-8), so the norm is within ~1e-7; 1e-6 leaves margin.
    for (Vec3f p : mesh.vertices) {
        DVec d = toDouble(p);
        ASSERT_NEAR(std::sqrt(dot(d, d)), 1.0, 1e-6);
    }
}

TEST_P(SphereSizes, EveryTriangleFacesOutward) {
    RecordingSink mesh = record(GeneratorKind::Sphere, GetParam());
    for (const auto& f : mesh.faces) ASSERT_GT(dot(faceNormal(mesh, f), faceCentroid(mesh, f)), 0.0);
}

TEST_P(SphereSizes, NoVertexIsDuplicated) {
    RecordingSink mesh = record(GeneratorKind::Sphere, GetParam());
    std::map<std::array<float, 3>, uint32_t> seen;
    for (Vec3f p : mesh.vertices) ASSERT_TRUE(seen.emplace(std::array<float, 3>{p.x, p.y, p.z}, 0).second);
}

INSTANTIATE_TEST_SUITE_P(Sphere, SphereSizes, ::testing::Values(20, 80, 1000, 20000));

TEST(Sphere, TriangleCountIsCloseToRequestedForAnyN) {
    // f = round(sqrt(N/20)) is off by at most 1/2, so 20 f^2 is off by about N/f relative to
    // N, i.e. sqrt(20/N): 3% at 20000, 0.45% at 1M. 10% on top covers the second-order term.
    for (uint64_t n : {20u, 21u, 1000u, 20000u, 1'000'000u, 123'456'789u}) {
        Result<GeneratedCounts> counts = generatedCounts({GeneratorKind::Sphere, n, 1});
        ASSERT_TRUE(counts);
        const double tolerance = 1.1 * std::sqrt(20.0 / static_cast<double>(n));
        EXPECT_NEAR(static_cast<double>(counts->triangles), static_cast<double>(n), tolerance * n) << n;
        EXPECT_EQ(counts->vertices, counts->triangles / 2 + 2) << "closed triangle mesh of genus 0";
    }
    EXPECT_EQ(generatedCounts({GeneratorKind::Sphere, 20, 1})->triangles, 20u);
    EXPECT_EQ(generatedCounts({GeneratorKind::Sphere, 20 * 4 * 4, 1})->triangles, 320u);
}

}  // namespace
}  // namespace vastray::test
