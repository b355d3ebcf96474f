#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "Infinity.h"
#include "TestMeshes.h"
#include "vastray/core/RayOffset.h"
#include "vastray/core/TriangleIntersect.h"
#include "vastray/core/VecMath.h"

namespace vastray {
namespace {

using test::kInf;
using test::randomVec;

// The double-precision reference's dot product (VecMath's dot sums in float).
double dotDouble(Vec3f a, Vec3f b) { return double(a.x) * b.x + double(a.y) * b.y + double(a.z) * b.z; }

TEST(TriangleIntersect, ExactHitHasExactTAndBarycentrics) {
    // Dyadic coordinates: every operation of the test is exact, so compare exactly.
    const Vec3f v0{0, 0, 0}, v1{4, 0, 0}, v2{0, 4, 0};
    TriangleHit h;
    ASSERT_TRUE(intersectTriangle(Ray{{1, 2, 2}, {0, 0, -1}}, v0, v1, v2, false, 0, kInf, &h));
    EXPECT_EQ(h.t, 2.0f);
    EXPECT_EQ(h.u, 0.25f);
    EXPECT_EQ(h.v, 0.5f);
    EXPECT_TRUE(h.frontFacing);  // counter-clockwise seen from +z
    ASSERT_TRUE(intersectTriangle(Ray{{1, 2, -2}, {0, 0, 1}}, v0, v1, v2, false, 0, kInf, &h));
    EXPECT_FALSE(h.frontFacing);
    EXPECT_FALSE(intersectTriangle(Ray{{1, 2, -2}, {0, 0, 1}}, v0, v1, v2, true, 0, kInf, &h));
    EXPECT_TRUE(intersectTriangle(Ray{{1, 2, 2}, {0, 0, -1}}, v0, v1, v2, true, 0, kInf, &h));
}

TEST(TriangleIntersect, RangeIsInclusiveAndExact) {
    const Vec3f v0{0, 0, 0}, v1{4, 0, 0}, v2{0, 4, 0};
    const Ray ray{{1, 1, 2}, {0, 0, -1}};  // t = 2 exactly
    TriangleHit h;
    EXPECT_TRUE(intersectTriangle(ray, v0, v1, v2, false, 2.0f, 2.0f, &h));
    EXPECT_FALSE(intersectTriangle(ray, v0, v1, v2, false, std::nextafter(2.0f, kInf), kInf, &h));
    EXPECT_FALSE(intersectTriangle(ray, v0, v1, v2, false, 0.0f, std::nextafter(2.0f, 0.0f), &h));
    EXPECT_FALSE(intersectTriangle(ray, v0, v1, v2, false, 0.0f, kInf, &h) && h.t < 0);
    EXPECT_FALSE(intersectTriangle(Ray{{1, 1, 2}, {0, 0, 1}}, v0, v1, v2, false, 0.0f, kInf, &h));  // behind
}

TEST(TriangleIntersect, DegenerateInputsNeverHit) {
    TriangleHit h;
    const Vec3f v0{0, 0, 0}, v1{4, 0, 0}, v2{0, 4, 0};
    EXPECT_FALSE(intersectTriangle(Ray{{1, 1, 2}, {0, 0, 0}}, v0, v1, v2, false, 0, kInf, &h));
    EXPECT_FALSE(intersectTriangle(Ray{{1, 1, 2}, {0, 0, NAN}}, v0, v1, v2, false, 0, kInf, &h));
    EXPECT_FALSE(intersectTriangle(Ray{{-1, 1, 0}, {1, 0, 0}}, v0, v1, v2, false, 0, kInf, &h));  // in plane
    EXPECT_FALSE(intersectTriangle(Ray{{1, 1, 2}, {0, 0, -1}}, v0, v1, {8, 0, 0}, false, 0, kInf, &h));
}

// Random triangles and rays: t, barycentrics and facing agree with a double-precision
// reference. Tolerance 1e-4 relative: float inputs, condition numbers bounded by the
// filter on the angle between ray and triangle.
// The fp32 recomputation of an edge function that rounded to 0 (Dekker's product errors) gives
// the float that double precision gives: the exact difference, rounded once. Products from
// 2^-60 to 2^60, pairs chosen so that both round to the same float (where the edge function is
// 0 in float) and nearby pairs that do not (where the function is never called, but still exact
// while the products are equal; the check covers only those equal ones).
TEST(TriangleIntersect, ZeroEdgeFunctionEqualsDouble) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> mantissa(1.0f, 2.0f);
    std::uniform_int_distribution<int> exponent(-30, 30), nudge(-3, 3), sign(0, 1);
    int checked = 0, nonZero = 0;
    for (int i = 0; i < 200000; ++i) {
        const auto pick = [&] { return (sign(rng) ? -1.0f : 1.0f) * std::ldexp(mantissa(rng), exponent(rng)); };
        const float a = pick(), b = pick(), c = pick();
        float d = (a * b) / c;
        for (int k = nudge(rng); k != 0; k += k > 0 ? -1 : 1) d = std::nextafter(d, k > 0 ? kInf : -kInf);
        if (a * b != c * d) continue;  // not a zero edge function in float
        ++checked;
        const float expected = float(double(a) * double(b) - double(c) * double(d));
        const float got = detail::zeroEdgeFunctionExact(a, b, c, d);
        if (expected != 0.0f) ++nonZero;
        ASSERT_EQ(got, expected) << std::hexfloat << a << " * " << b << " - " << c << " * " << d;
        ASSERT_EQ(std::signbit(got), std::signbit(expected)) << std::hexfloat << a << " " << b << " " << c << " " << d;
    }
    EXPECT_GT(checked, 20000);
    EXPECT_GT(nonZero, checked / 2) << "most equal float products still differ exactly";
}

TEST(TriangleIntersect, AgreesWithDoubleReference) {
    std::mt19937 rng(7);
    int hits = 0;
    for (int i = 0; i < 20000; ++i) {
        const Vec3f v0 = randomVec(rng, -1, 1), v1 = randomVec(rng, -1, 1), v2 = randomVec(rng, -1, 1);
        const Vec3f origin = randomVec(rng, -3, 3);
        const Vec3f aim = v0 + (v1 - v0) * 0.3f + (v2 - v0) * 0.3f + randomVec(rng, -0.2f, 0.2f);
        const Ray ray{origin, aim - origin};
        const Vec3f n = cross(v1 - v0, v2 - v0);
        const double dn = dotDouble(ray.direction, n);
        const double len = std::sqrt(dotDouble(n, n) * dotDouble(ray.direction, ray.direction));
        TriangleHit h;
        if (!intersectTriangle(ray, v0, v1, v2, false, 0, kInf, &h)) continue;
        if (std::abs(dn) < 0.05 * len) continue;  // grazing: ill-conditioned t
        ++hits;
        const double tRef = dotDouble(v0 - ray.origin, n) / dn;
        EXPECT_NEAR(h.t, tRef, 1e-4 * std::max(1.0, std::abs(tRef)));
        EXPECT_EQ(h.frontFacing, dn < 0);
        const Vec3f p = ray.origin + ray.direction * h.t;
        const Vec3f q = v0 * (1 - h.u - h.v) + v1 * h.u + v2 * h.v;
        EXPECT_NEAR(p.x, q.x, 1e-3);
        EXPECT_NEAR(p.y, q.y, 1e-3);
        EXPECT_NEAR(p.z, q.z, 1e-3);
    }
    EXPECT_GT(hits, 1000);
}

// Watertightness on the smallest closed neighbourhood: a fan of triangles around a shared
// vertex, seen from above so that it never folds over itself (a ray through a silhouette
// edge computed in float may legitimately pass outside). Rays aimed exactly at the shared vertex and at points of the shared edges must hit
// at least one triangle (exact count: misses must be 0).
TEST(TriangleIntersect, FanIsWatertightAtSharedEdgesAndVertex) {
    std::mt19937 rng(11);
    const int fan = 7;
    const Vec3f center{0.1f, -0.3f, 0.7f};
    Vec3f rim[fan];
    for (int i = 0; i < fan; ++i) {
        const float a = 2.0f * 3.14159265f * float(i) / fan;
        rim[i] = Vec3f{std::cos(a), std::sin(a), 0.1f * std::sin(3.0f * a)} + center;
    }
    std::uniform_real_distribution<float> s(0.0f, 1.0f);
    int misses = 0;
    for (int i = 0; i < 20000; ++i) {
        const Vec3f origin = center + Vec3f{0, 0, 2.5f} + randomVec(rng, -0.5f, 0.5f);
        const int e = i % fan;
        const Vec3f target = (i % 5 == 0) ? center : center + (rim[e] - center) * s(rng);
        const Ray ray{origin, target - origin};
        bool any = false;
        for (int k = 0; k < fan; ++k) {
            TriangleHit h;
            any |= intersectTriangle(ray, center, rim[k], rim[(k + 1) % fan], false, 0, kInf, &h);
        }
        misses += !any;
    }
    EXPECT_EQ(misses, 0);
}

}  // namespace
}  // namespace vastray

namespace vastray {
namespace {

// Rays leaving a large triangle from a point a few ULPs above it (core/RayOffset.h) towards the
// upper hemisphere can only hit it behind their origin. Without the bound on t's rounding error
// some re-hit it at a tiny positive t (the error of t scales with the vertices' distance from
// the origin, ~700 here); with fromSurface none does.
TEST(TriangleIntersect, RayLeavingALargeTriangleNeverReHitsIt) {
    const Vec3f v0{-700, 0, -700}, v1{700, 0, -700}, v2{700, 0, 700};
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    int reHits[2] = {0, 0};
    for (int i = 0; i < 20000; ++i) {
        const float a = unit(rng), b = unit(rng) * (1.0f - a);
        const Vec3f p = v0 + (v1 - v0) * a + (v2 - v0) * b;
        const Vec3f n{0, 1, 0};
        Vec3f d{unit(rng) * 2 - 1, unit(rng) * 0.2f + 1e-4f, unit(rng) * 2 - 1};
        const Ray ray{offsetRayOrigin(p, n), d};
        for (int fromSurface = 0; fromSurface < 2; ++fromSurface) {
            WatertightRay r;
            ASSERT_TRUE(prepareWatertightRay(ray, &r));
            r.fromSurface = fromSurface != 0;
            TriangleHit hit;
            reHits[fromSurface] += intersectTriangle(r, v0, v1, v2, false, 0.0f, INFINITY, &hit);
        }
    }
    EXPECT_GT(reHits[0], 0) << "the case should be hard: plain float t re-hits the triangle";
    EXPECT_EQ(reHits[1], 0);
}

}  // namespace
}  // namespace vastray
