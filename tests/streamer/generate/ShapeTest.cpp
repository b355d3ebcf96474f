// Shape properties of terrain, soup and city that the partitioner and renderer tests rely on.
#include <gtest/gtest.h>

#include <map>
#include <utility>

#include "streamer/generate/RecordingSink.h"

namespace vastray::test {
namespace {

TEST(Terrain, NormalsPointUpAndHeightsStayInRange) {
    RecordingSink mesh = record(GeneratorKind::Terrain, 20000, 3);
    for (const auto& f : mesh.faces) ASSERT_GT(faceNormal(mesh, f).y, 0.0);
    float lo = 1, hi = -1;
    for (Vec3f p : mesh.vertices) {
        ASSERT_GE(p.x, -1.0f);
        ASSERT_LE(p.x, 1.0f);
        ASSERT_GE(p.z, -1.0f);
        ASSERT_LE(p.z, 1.0f);
        lo = std::min(lo, p.y);
        hi = std::max(hi, p.y);
    }
    EXPECT_GE(lo, 0.0f);
    EXPECT_LE(hi, 0.4f);
    EXPECT_GT(hi - lo, 0.1f) << "the terrain should not be flat";
}

TEST(Soup, StaysInsideTheCubeWithUnsharedVertices) {
    RecordingSink mesh = record(GeneratorKind::Soup, 20000, 5);
    for (Vec3f p : mesh.vertices) {
        for (int axis = 0; axis < 3; ++axis) {
            ASSERT_GE(p[axis], -1.0f);
            ASSERT_LE(p[axis], 1.0f);
        }
    }
    for (size_t t = 0; t < mesh.faces.size(); ++t) {
        auto first = static_cast<uint32_t>(3 * t);
        ASSERT_EQ(mesh.faces[t], (std::array<uint32_t, 3>{first, first + 1, first + 2}));
    }
}

TEST(Soup, SizesAreHeavyTailed) {
    RecordingSink mesh = record(GeneratorKind::Soup, 20000, 5);
    int tiny = 0, large = 0;
    for (const auto& f : mesh.faces) {
        DVec a = toDouble(mesh.vertices[f[0]]), b = toDouble(mesh.vertices[f[1]]),
             c = toDouble(mesh.vertices[f[2]]);
        double extent = std::max({std::sqrt(dot(sub(b, a), sub(b, a))), std::sqrt(dot(sub(c, a), sub(c, a))),
                                  std::sqrt(dot(sub(c, b), sub(c, b)))});
        tiny += extent < 0.02;
        large += extent > 0.5;
    }
    EXPECT_GT(tiny, 20000 * 8 / 10) << "most triangles are tiny";
    EXPECT_GT(large, 5) << "a few span a large part of the cube";
    EXPECT_LT(large, 20000 / 100);
}

// Per box: 4 + 8b .. 4 + 8b + 7; faces 2 + 10b .. 2 + 10b + 9.
TEST(City, BoxesAreClosedExceptTheFloorAndWoundOutward) {
    RecordingSink mesh = record(GeneratorKind::City, 5000, 9);
    const size_t boxes = (mesh.faces.size() - 2) / 10;
    ASSERT_EQ(mesh.faces.size(), 2 + 10 * boxes);
    ASSERT_EQ(mesh.vertices.size(), 4 + 8 * boxes);
    for (size_t b = 0; b < boxes; ++b) {
        const auto base = static_cast<uint32_t>(4 + 8 * b);
        DVec center{0, 0, 0};
        for (uint32_t k = 0; k < 8; ++k) {
            DVec p = toDouble(mesh.vertices[base + k]);
            center = {center.x + p.x / 8, center.y + p.y / 8, center.z + p.z / 8};
        }
        std::map<std::pair<uint32_t, uint32_t>, int> directed;
        for (size_t t = 2 + 10 * b; t < 12 + 10 * b; ++t) {
            const auto& f = mesh.faces[t];
            for (uint32_t i : f)
                ASSERT_TRUE(i >= base && i < base + 8) << "box " << b << " uses a foreign vertex";
            ASSERT_GT(dot(faceNormal(mesh, f), sub(faceCentroid(mesh, f), center)), 0.0) << "box " << b;
            for (int k = 0; k < 3; ++k) ++directed[{f[k], f[(k + 1) % 3]}];
        }
        // Boundary edges: those whose reverse is missing. Exactly the 4 floor edges at y = 0.
        int open = 0;
        for (const auto& [edge, count] : directed) {
            ASSERT_EQ(count, 1);
            if (directed.count({edge.second, edge.first})) continue;
            ++open;
            EXPECT_EQ(mesh.vertices[edge.first].y, 0.0f);
            EXPECT_EQ(mesh.vertices[edge.second].y, 0.0f);
        }
        ASSERT_EQ(open, 4) << "box " << b;
    }
}

TEST(City, GroundQuadFacesUpAndBuildingsStandOnIt) {
    RecordingSink mesh = record(GeneratorKind::City, 5000, 9);
    for (int t = 0; t < 2; ++t) EXPECT_GT(faceNormal(mesh, mesh.faces[t]).y, 0.0);
    for (size_t i = 0; i < 4; ++i) EXPECT_EQ(mesh.vertices[i].y, 0.0f);
    float minHeight = 1, maxHeight = 0;
    for (size_t i = 4; i < mesh.vertices.size(); ++i) {
        ASSERT_GE(mesh.vertices[i].y, 0.0f);
        if ((i - 4) % 8 == 4) {
            minHeight = std::min(minHeight, mesh.vertices[i].y);
            maxHeight = std::max(maxHeight, mesh.vertices[i].y);
        }
    }
    EXPECT_GT(maxHeight, 4 * minHeight) << "heights should vary";
}

}  // namespace
}  // namespace vastray::test
