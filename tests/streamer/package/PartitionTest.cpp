// Partition invariants, checked with geometry code of the test's own (not the partitioner's).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "PackageTestUtil.h"

namespace vastray::test {
namespace {

double volume(const Aabb& b) {
    if (b.isEmpty()) return 0;
    const Vec3f e = b.extent();
    return double(e.x) * e.y * e.z;
}

// Separating-axis test of a triangle against a closed box (Akenine-Möller 2001), in double,
// with a tolerance of `eps` on every axis for the float rounding of clipped coordinates.
bool triangleTouchesBox(const Vec3f tri[3], const Aabb& box, double eps) {
    double c[3], h[3], v[3][3];
    for (int a = 0; a < 3; ++a) {
        c[a] = 0.5 * (double(box.lo[a]) + box.hi[a]);
        h[a] = 0.5 * (double(box.hi[a]) - box.lo[a]) + eps;
    }
    for (int k = 0; k < 3; ++k)
        for (int a = 0; a < 3; ++a) v[k][a] = tri[k][a] - c[a];
    auto separated = [&](const double axis[3]) {
        double lo = 1e300, hi = -1e300, r = 0;
        for (int k = 0; k < 3; ++k) {
            const double p = v[k][0] * axis[0] + v[k][1] * axis[1] + v[k][2] * axis[2];
            lo = std::min(lo, p);
            hi = std::max(hi, p);
        }
        for (int a = 0; a < 3; ++a) r += h[a] * std::abs(axis[a]);
        return lo > r || hi < -r;
    };
    double e[3][3];
    for (int k = 0; k < 3; ++k)
        for (int a = 0; a < 3; ++a) e[k][a] = v[(k + 1) % 3][a] - v[k][a];
    for (int a = 0; a < 3; ++a) {
        const double axis[3] = {double(a == 0), double(a == 1), double(a == 2)};
        if (separated(axis)) return false;
    }
    const double n[3] = {e[0][1] * e[1][2] - e[0][2] * e[1][1], e[0][2] * e[1][0] - e[0][0] * e[1][2],
                         e[0][0] * e[1][1] - e[0][1] * e[1][0]};
    if (separated(n)) return false;
    for (int k = 0; k < 3; ++k)
        for (int a = 0; a < 3; ++a) {
            const double u[3] = {double(a == 0), double(a == 1), double(a == 2)};
            const double axis[3] = {u[1] * e[k][2] - u[2] * e[k][1], u[2] * e[k][0] - u[0] * e[k][2],
                                    u[0] * e[k][1] - u[1] * e[k][0]};
            if ((axis[0] != 0 || axis[1] != 0 || axis[2] != 0) && separated(axis)) return false;
        }
    return true;
}

bool strictlyInside(const Aabb& box, Vec3f p) {
    for (int a = 0; a < 3; ++a)
        if (!(p[a] > box.lo[a] && p[a] < box.hi[a])) return false;
    return true;
}

struct PartitionCase {
    GeneratorKind kind;
    uint64_t triangles;
    uint64_t chunkSize;
};

class PartitionInvariants : public ::testing::TestWithParam<PartitionCase> {};

TEST_P(PartitionInvariants, Hold) {
    const PartitionCase param = GetParam();
    const TriangleMesh mesh = generatedMesh(param.kind, param.triangles, 7);
    PackageBuildOptions options;
    options.chunkSizeBytes = param.chunkSize;
    auto reader = buildAndOpen(mesh, tempPath(std::string("partition-") + generatorKindName(param.kind) + ".vast"), options);
    ASSERT_TRUE(reader);
    const PackageInfo& info = reader->info();
    ASSERT_GT(info.chunks.size(), 4u) << "the case must produce several chunks";

    // Cells are disjoint and cover the scene bounds.
    const std::vector<Cell> cells = topLevelCells(info);
    double total = 0;
    for (size_t i = 0; i < cells.size(); ++i) {
        total += volume(cells[i].box);
        for (size_t j = i + 1; j < cells.size(); ++j)
            EXPECT_EQ(volume(cells[i].box.intersect(cells[j].box)), 0.0) << "cells " << i << " and " << j;
        if (cells[i].chunk != kEmptyCell) {
            EXPECT_EQ(cells[i].box, info.chunks[cells[i].chunk].cell);
        }
    }
    EXPECT_NEAR(total, volume(info.bounds), volume(info.bounds) * 1e-5);

    // Every chunk within its size, and the directory's footprint is the decoded one.
    std::vector<std::set<uint32_t>> members(info.chunks.size());
    std::map<uint32_t, std::array<Vec3f, 3>> triangles;
    const double eps = 1e-6 * std::max({info.bounds.extent().x, info.bounds.extent().y, info.bounds.extent().z});
    for (const ChunkInfo& c : info.chunks) {
        EXPECT_LE(c.residentBytes, info.chunkSizeBytes) << "chunk " << c.id;
        auto chunk = reader->readChunk(c.id);
        ASSERT_TRUE(chunk.isOk()) << chunk.message();
        EXPECT_EQ(chunk->residentBytes(), c.residentBytes);
        for (size_t t = 0; t < chunk->primitiveIds.size(); ++t) {
            const uint32_t* i = &chunk->indices[3 * t];
            const Vec3f tri[3] = {chunk->positions[i[0]], chunk->positions[i[1]], chunk->positions[i[2]]};
            // No other: a referenced triangle touches the cell.
            EXPECT_TRUE(triangleTouchesBox(tri, c.cell, eps)) << "chunk " << c.id << " triangle " << chunk->primitiveIds[t];
            members[c.id].insert(chunk->primitiveIds[t]);
            triangles[chunk->primitiveIds[t]] = {tri[0], tri[1], tri[2]};
        }
    }
    EXPECT_EQ(triangles.size(), info.triangleCount);

    // Every cell it overlaps: points of the triangle strictly inside a cell are in that cell's chunk.
    const float weights[4][3] = {{1 / 3.f, 1 / 3.f, 1 / 3.f}, {0.8f, 0.1f, 0.1f}, {0.1f, 0.8f, 0.1f}, {0.1f, 0.1f, 0.8f}};
    size_t missing = 0;
    for (const auto& [id, tri] : triangles)
        for (const auto& w : weights) {
            const Vec3f p = tri[0] * w[0] + tri[1] * w[1] + tri[2] * w[2];
            for (const Cell& cell : cells)
                if (strictlyInside(cell.box, p) && (cell.chunk == kEmptyCell || !members[cell.chunk].count(id)))
                    ++missing;
        }
    EXPECT_EQ(missing, 0u);
}

INSTANTIATE_TEST_SUITE_P(Generated, PartitionInvariants,
                         ::testing::Values(PartitionCase{GeneratorKind::Sphere, 20000, 64 << 10},
                                           PartitionCase{GeneratorKind::Terrain, 20000, 64 << 10},
                                           PartitionCase{GeneratorKind::Soup, 8000, 64 << 10},
                                           PartitionCase{GeneratorKind::City, 8000, 32 << 10}),
                         [](const auto& info) { return std::string(generatorKindName(info.param.kind)); });

TEST(Partition, TrianglesLyingInSplitPlanesAreKept) {
    // A flat grid in z = 0 plus a wall in x = 0: planes the partitioner will choose.
    TriangleMesh mesh;
    const int n = 60;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x) mesh.positions.push_back({float(x) / n * 2 - 1, float(y) / n * 2 - 1, 0.0f});
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const uint32_t a = y * (n + 1) + x, b = a + 1, c = a + n + 1, d = c + 1;
            mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
        }
    const uint32_t base = uint32_t(mesh.positions.size());
    for (int z = 0; z <= n; ++z)
        for (int y = 0; y <= n; ++y) mesh.positions.push_back({0.0f, float(y) / n * 2 - 1, float(z) / n});
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y) {
            const uint32_t a = base + z * (n + 1) + y, b = a + 1, c = a + n + 1, d = c + 1;
            mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
        }
    mesh.materials.push_back({});
    PackageBuildOptions options;
    options.chunkSizeBytes = 32 << 10;
    auto reader = buildAndOpen(mesh, tempPath("planes.vast"), options);
    ASSERT_TRUE(reader);
    std::set<uint32_t> seen;
    for (const ChunkInfo& c : reader->info().chunks) {
        auto chunk = reader->readChunk(c.id);
        ASSERT_TRUE(chunk.isOk()) << chunk.message();
        seen.insert(chunk->primitiveIds.begin(), chunk->primitiveIds.end());
    }
    EXPECT_EQ(seen.size(), mesh.triangleCount());
}

}  // namespace
}  // namespace vastray::test
