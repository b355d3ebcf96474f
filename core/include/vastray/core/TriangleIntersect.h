#pragma once
// Watertight ray/triangle test after Woop, Benthin and Wald, "Watertight Ray/Triangle
// Intersection", JCGT 2(1), 2013. A ray that passes exactly through a shared edge or vertex
// of a closed mesh hits at least one of the triangles meeting there: no cracks.
// The GPU shader mirrors this function operation for operation.
#include <cmath>
#include <cstdint>

#include "vastray/core/Ray.h"
#include "vastray/core/Vec3.h"

namespace vastray {

// Per-ray constants of the test: the axis permutation that makes the dominant direction
// component z (winding-preserving), and the shear that maps the ray onto +z.
struct WatertightRay {
    Vec3f origin;
    int kx = 0, ky = 1, kz = 2;
    float sx = 0, sy = 0, sz = 1;
    // The ray leaves a surface (a bounce or shadow ray): hits within t's rounding error of the
    // origin are refused (detail::conservativeTMin). Not for rays from a camera: the bound
    // refuses every hit on a near-degenerate triangle, whose t is all rounding error.
    bool fromSurface = false;
};

struct TriangleHit {
    float t = 0;
    float u = 0;  // barycentric weight of v1; the hit point is (1-u-v)*v0 + u*v1 + v*v2
    float v = 0;  // barycentric weight of v2
    // Counter-clockwise seen from the ray origin: dot(direction, cross(v1-v0, v2-v0)) < 0.
    bool frontFacing = false;
};

// Returns false when the direction is zero or not finite (no test can hit then).
bool prepareWatertightRay(const Ray& ray, WatertightRay* out);

namespace detail {
// gamma(n) of pbrt-v4: n * eps / (1 - n * eps), eps = 2^-24, the relative error bound of n
// float operations (rounded up, so that bounds built from them stay conservative).
inline constexpr float kGamma2 = 1.19209304e-07f;
inline constexpr float kGamma3 = 1.78813956e-07f;
inline constexpr float kGamma5 = 2.98023259e-07f;

// pbrt-v4's bound on the rounding error of a hit's t (Pharr, Jakob, Humphreys, "Physically Based
// Rendering" 4th ed., section 6.8.4): from the sheared vertex coordinates and the edge functions.
// A hit at t <= this bound may lie behind the origin: a ray leaving a large triangle from a
// point a few ULPs above it re-hits it at a tiny positive t unless such hits are refused (the
// error of t grows with the vertices' distance from the origin, not with the hit point's size).
inline float conservativeTMin(float ax, float ay, float bx, float by, float cx, float cy, float az, float bz,
                              float cz, float u, float v, float w, float rcpDet) {
    const float maxZt = std::fmax(std::fmax(std::fabs(az), std::fabs(bz)), std::fabs(cz));
    const float maxXt = std::fmax(std::fmax(std::fabs(ax), std::fabs(bx)), std::fabs(cx));
    const float maxYt = std::fmax(std::fmax(std::fabs(ay), std::fabs(by)), std::fabs(cy));
    const float deltaZ = kGamma3 * maxZt;
    const float deltaX = kGamma5 * (maxXt + maxZt);
    const float deltaY = kGamma5 * (maxYt + maxZt);
    const float deltaE = 2.0f * (kGamma2 * maxXt * maxYt + deltaY * maxXt + deltaX * maxYt);
    const float maxE = std::fmax(std::fmax(std::fabs(u), std::fabs(v)), std::fabs(w));
    return 3.0f * (kGamma3 * maxE * maxZt + deltaE * maxZt + deltaZ * maxE) * std::fabs(rcpDet);
}

// Dekker's product error without fma (Veltkamp's split; T. J. Dekker, "A floating-point technique
// for extending the available precision", 1971): for p = fl(a*b), a*b == p + productError(a, b, p)
// exactly, in float arithmetic alone, while no step overflows or underflows. Within the imported
// coordinate range (|x| <= 1e18, so sheared coordinates stay below ~4e18) nothing overflows;
// products below ~2^-100 lose bits of their error (denormal territory, out of scope).
// Every operation must be rounded on its own: ISO C++ does not contract a*b+c into an fma (the
// project builds with CMAKE_CXX_EXTENSIONS OFF) and Watertight.glsl marks the same steps `precise`.
inline float productError(float a, float b, float p) {
    const float ca = 4097.0f * a, cb = 4097.0f * b;  // 2^12 + 1 splits a 24-bit significand in two halves
    const float ah = ca - (ca - a), al = a - ah;
    const float bh = cb - (cb - b), bl = b - bh;
    return al * bl - (((p - ah * bh) - al * bh) - ah * bl);
}

// An edge function a*b - c*d that rounded to exactly 0 in float, recomputed exactly: it rounds
// to 0 only when fl(a*b) == fl(c*d) (a float subtraction is exact near 0 and rounding is
// monotone, so a non-zero result already has the exact sign), and then a*b - c*d equals the
// difference of the two product errors, which one float subtraction rounds correctly. This is
// the same float a double-precision recomputation gives, in fp32 only (consumer GPUs run fp64 at
// 1/32-1/64 of the rate, and some have none); tests/core/TriangleIntersectTest.cpp checks it
// against double.
inline float zeroEdgeFunctionExact(float a, float b, float c, float d) {
    return productError(a, b, a * b) - productError(c, d, c * d);
}
}  // namespace detail

// Hit when the ray passes through the triangle (edges and vertices included) at a t with
// tMin <= t <= tMax (the check is on the returned t, so callers can rely on it exactly), and for
// a ray that leaves a surface, t beyond its own rounding error: never at the ray's origin.
// cullBackFace: a single-sided triangle is invisible from behind. Degenerate triangles and
// rays lying in the triangle's plane never hit. Inline because it is the inner loop of traversal.
inline bool intersectTriangle(const WatertightRay& r, Vec3f v0, Vec3f v1, Vec3f v2, bool cullBackFace,
                              float tMin, float tMax, TriangleHit* hit) {
    const Vec3f a = v0 - r.origin, b = v1 - r.origin, c = v2 - r.origin;
    const float ax = a[r.kx] - r.sx * a[r.kz], ay = a[r.ky] - r.sy * a[r.kz];
    const float bx = b[r.kx] - r.sx * b[r.kz], by = b[r.ky] - r.sy * b[r.kz];
    const float cx = c[r.kx] - r.sx * c[r.kz], cy = c[r.ky] - r.sy * c[r.kz];
    float u = cx * by - cy * bx;  // weight of v0
    float v = ax * cy - ay * cx;  // weight of v1
    float w = bx * ay - by * ax;  // weight of v2
    // Exact signs where rounding gave 0 (the test's watertightness hangs on them).
    if (u == 0.0f) u = detail::zeroEdgeFunctionExact(cx, by, cy, bx);
    if (v == 0.0f) v = detail::zeroEdgeFunctionExact(ax, cy, ay, cx);
    if (w == 0.0f) w = detail::zeroEdgeFunctionExact(bx, ay, by, ax);
    const bool anyNegative = u < 0.0f || v < 0.0f || w < 0.0f;
    const bool anyPositive = u > 0.0f || v > 0.0f || w > 0.0f;
    if (anyNegative && (anyPositive || cullBackFace)) return false;
    const float det = u + v + w;
    if (det == 0.0f) return false;
    const float az = r.sz * a[r.kz], bz = r.sz * b[r.kz], cz = r.sz * c[r.kz];
    const float scaledT = u * az + v * bz + w * cz;
    const float rcpDet = 1.0f / det;
    const float t = scaledT * rcpDet;
    if (!(t >= tMin && t <= tMax)) return false;  // also rejects NaN
    if (r.fromSurface && t <= detail::conservativeTMin(ax, ay, bx, by, cx, cy, az, bz, cz, u, v, w, rcpDet))
        return false;
    hit->t = t;
    hit->u = v * rcpDet;
    hit->v = w * rcpDet;
    hit->frontFacing = det > 0.0f;
    return true;
}

// Convenience form for one-off tests; traversal prepares the ray once instead.
inline bool intersectTriangle(const Ray& ray, Vec3f v0, Vec3f v1, Vec3f v2, bool cullBackFace, float tMin,
                              float tMax, TriangleHit* hit) {
    WatertightRay r;
    return prepareWatertightRay(ray, &r) && intersectTriangle(r, v0, v1, v2, cullBackFace, tMin, tMax, hit);
}

}  // namespace vastray
