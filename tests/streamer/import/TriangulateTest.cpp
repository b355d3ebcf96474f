// Ear clipping of OBJ/PLY polygons (streamer/src/import/Triangulate.h): shape kept, winding
// kept, limits named.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "import/Triangulate.h"

namespace vastray::test {
namespace {

using import::PolygonTriangulator;

// Twice the signed area in the XY plane.
double area2(Vec3f a, Vec3f b, Vec3f c) {
    return (double(b.x) - a.x) * (double(c.y) - a.y) - (double(b.y) - a.y) * (double(c.x) - a.x);
}

double shoelace2(const std::vector<Vec3f>& ring) {
    double sum = 0;
    for (size_t i = 0; i < ring.size(); ++i) {
        const Vec3f a = ring[i], b = ring[(i + 1) % ring.size()];
        sum += double(a.x) * b.y - double(b.x) * a.y;
    }
    return sum;
}

std::vector<uint32_t> identity(size_t n) {
    std::vector<uint32_t> corners(n);
    std::iota(corners.begin(), corners.end(), 0u);
    return corners;
}

// Every triangle winds as the polygon does and the triangles tile its area exactly once.
void expectTiles(const std::vector<Vec3f>& ring, const std::vector<uint32_t>& tris, double tolerance = 1e-9) {
    const double polygon = shoelace2(ring);
    double sum = 0;
    for (size_t t = 0; t < tris.size(); t += 3) {
        const double a = area2(ring[tris[t]], ring[tris[t + 1]], ring[tris[t + 2]]);
        EXPECT_GE(a * polygon, -tolerance * std::fabs(polygon)) << "triangle " << t / 3 << " is wound backwards";
        sum += a;
    }
    EXPECT_NEAR(sum, polygon, tolerance * std::fabs(polygon) + 1e-12);
}

bool covers(const std::vector<Vec3f>& ring, const std::vector<uint32_t>& tris, Vec3f p) {
    for (size_t t = 0; t < tris.size(); t += 3) {
        const Vec3f a = ring[tris[t]], b = ring[tris[t + 1]], c = ring[tris[t + 2]];
        const double d1 = area2(a, b, p), d2 = area2(b, c, p), d3 = area2(c, a, p);
        if ((d1 > 0 && d2 > 0 && d3 > 0) || (d1 < 0 && d2 < 0 && d3 < 0)) return true;
    }
    return false;
}

// A "C": the notch between its arms must stay empty (a fan from corner 0 filled it in).
TEST(Triangulate, ConcavePolygonKeepsItsNotchEmpty) {
    const std::vector<Vec3f> ring = {{0, 0, 0}, {3, 0, 0}, {3, 1, 0}, {1, 1, 0}, {1, 2, 0},
                                     {3, 2, 0}, {3, 3, 0}, {0, 3, 0}};
    PolygonTriangulator triangulator;
    std::vector<uint32_t> tris;
    EXPECT_EQ(triangulator.triangulate(ring, identity(ring.size()), tris), 6u);
    EXPECT_TRUE(triangulator.failure().empty());
    expectTiles(ring, tris);
    EXPECT_FALSE(covers(ring, tris, {2, 1.5f, 0}));  // inside the notch
    EXPECT_TRUE(covers(ring, tris, {0.5f, 1.5f, 0}));
}

TEST(Triangulate, ClockwisePolygonsStayClockwise) {
    std::vector<Vec3f> ring = {{0, 0, 0}, {3, 0, 0}, {3, 1, 0}, {1, 1, 0}, {1, 2, 0}, {3, 2, 0}, {3, 3, 0}, {0, 3, 0}};
    std::reverse(ring.begin(), ring.end());
    PolygonTriangulator triangulator;
    std::vector<uint32_t> tris;
    triangulator.triangulate(ring, identity(ring.size()), tris);
    ASSERT_LT(shoelace2(ring), 0);
    expectTiles(ring, tris);
}

// A concave quad (an arrow head) must be split along the diagonal through its reflex corner.
TEST(Triangulate, ConcaveQuadSplitsThroughItsReflexCorner) {
    const std::vector<Vec3f> ring = {{0, 0, 0}, {2, 1, 0}, {0, 2, 0}, {0.5f, 1, 0}};
    PolygonTriangulator triangulator;
    std::vector<uint32_t> tris;
    EXPECT_EQ(triangulator.triangulate(ring, identity(4), tris), 2u);
    expectTiles(ring, tris);
    EXPECT_EQ(tris, (std::vector<uint32_t>{0, 1, 3, 1, 2, 3}));
}

// Polygons in any plane: the projection drops the normal's largest axis.
TEST(Triangulate, PolygonsInEveryAxisPlane) {
    const std::vector<std::array<float, 2>> c = {{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 2}, {3, 2}, {3, 3}, {0, 3}};
    for (int axis = 0; axis < 3; ++axis) {
        std::vector<Vec3f> ring, flat;
        for (const auto& p : c) {
            Vec3f v{0, 0, 0};
            (&v.x)[(axis + 1) % 3] = p[0];
            (&v.x)[(axis + 2) % 3] = p[1];
            (&v.x)[axis] = 5.0f;  // off the origin
            ring.push_back(v);
            flat.push_back({p[0], p[1], 0});
        }
        PolygonTriangulator triangulator;
        std::vector<uint32_t> tris;
        EXPECT_EQ(triangulator.triangulate(ring, identity(ring.size()), tris), 6u) << "axis " << axis;
        expectTiles(flat, tris);  // the same triangles as in the XY plane
    }
}

// A square with a square hole, written as one polygon through a bridge edge (each bridge
// corner is passed twice), as some exporters write holes.
TEST(Triangulate, KeyholePolygonLeavesItsHoleOpen) {
    const std::vector<Vec3f> ring = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}, {0, 0, 0},
                                     {1, 1, 0}, {1, 3, 0}, {3, 3, 0}, {3, 1, 0}, {1, 1, 0}};
    PolygonTriangulator triangulator;
    std::vector<uint32_t> tris;
    triangulator.triangulate(ring, identity(ring.size()), tris);
    EXPECT_TRUE(triangulator.failure().empty());
    expectTiles(ring, tris);
    EXPECT_NEAR(std::fabs(shoelace2(ring)), 2 * (16 - 4), 1e-9);
    EXPECT_FALSE(covers(ring, tris, {2, 2, 0}));
    EXPECT_TRUE(covers(ring, tris, {0.5f, 2, 0}));
}

// A circle of 10^6 corners stored in float zigzags by its rounding; it still counts as
// convex and is clipped in O(n): n - 2 triangles tiling the disc.
TEST(Triangulate, MillionCornerCircleIsClippedAsConvex) {
    const size_t n = 1000000;
    std::vector<Vec3f> ring(n);
    for (size_t i = 0; i < n; ++i) {
        const double angle = 2 * M_PI * double(i) / double(n);
        ring[i] = {float(std::cos(angle)), float(std::sin(angle)), 0.0f};
    }
    PolygonTriangulator triangulator;
    std::vector<uint32_t> tris;
    EXPECT_EQ(triangulator.triangulate(ring, identity(n), tris), n - 2);
    EXPECT_TRUE(triangulator.failure().empty());
    expectTiles(ring, tris, 1e-6);
    std::vector<uint8_t> used(n, 0);
    for (uint32_t v : tris) used[v] = 1;
    EXPECT_EQ(std::count(used.begin(), used.end(), 1), long(n));
}

TEST(Triangulate, LargeNonConvexPolygonIsRefusedByName) {
    const size_t n = import::kMaxEarClipCorners + 2;
    std::vector<Vec3f> ring(n);
    for (size_t i = 0; i < n; ++i) {  // a star: every second corner pulled in
        const double angle = 2 * M_PI * double(i) / double(n), r = i % 2 ? 1.0 : 0.5;
        ring[i] = {float(r * std::cos(angle)), float(r * std::sin(angle)), 0.0f};
    }
    PolygonTriangulator triangulator;
    std::vector<uint32_t> tris;
    EXPECT_EQ(triangulator.triangulate(ring, identity(n), tris), 0u);
    EXPECT_NE(triangulator.failure().find("not convex exceeds the ear-clipping limit of 16384"), std::string::npos)
        << triangulator.failure();
    EXPECT_TRUE(tris.empty());
    ring.resize(import::kMaxEarClipCorners);  // at the limit: clipped
    EXPECT_EQ(triangulator.triangulate(ring, identity(ring.size()), tris), ring.size() - 2);
    EXPECT_TRUE(triangulator.failure().empty());
}

// Cycling over one triangle: earcut's repair took cubic time (3,000 corners: 7 s). Such a
// polygon becomes a fan up to the fan limit and is refused above it.
TEST(Triangulate, PolygonPassingACornerManyTimesIsAFanOrRefused) {
    const std::vector<Vec3f> positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    std::vector<uint32_t> corners(3000);
    for (size_t i = 0; i < corners.size(); ++i) corners[i] = uint32_t(i % 3);
    PolygonTriangulator triangulator;
    std::vector<uint32_t> tris;
    EXPECT_EQ(triangulator.triangulate(positions, corners, tris), 2998u);
    EXPECT_EQ(tris[3], 0u);  // a fan: every triangle starts at the first corner
    corners.resize(5000);
    for (size_t i = 0; i < corners.size(); ++i) corners[i] = uint32_t(i % 3);
    tris.clear();
    EXPECT_EQ(triangulator.triangulate(positions, corners, tris), 0u);
    EXPECT_NE(triangulator.failure().find("passes one corner more than twice"), std::string::npos)
        << triangulator.failure();
}

// All corners on one line: no plane to clip in; the fan's zero-area triangles are dropped
// later by the importer (and counted there).
TEST(Triangulate, CollinearPolygonGivesDegenerateTriangles) {
    const std::vector<Vec3f> ring = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}, {4, 4, 4}};
    PolygonTriangulator triangulator;
    std::vector<uint32_t> tris;
    EXPECT_EQ(triangulator.triangulate(ring, identity(5), tris), 3u);
    EXPECT_TRUE(triangulator.failure().empty());
}

}  // namespace
}  // namespace vastray::test
