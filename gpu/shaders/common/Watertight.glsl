// Watertight ray/triangle test (Woop, Benthin, Wald, JCGT 2013), operation for operation the
// same as core/include/vastray/core/TriangleIntersect.h, in fp32 on the hot path (consumer GPUs
// run fp64 at 1/32-1/64 of fp32):
// - every float result that feeds a multiply-add is `precise` (no FMA contraction, no
//   reassociation), as on the CPU (GCC in ISO C++20 mode does not contract);
// - an edge function that rounds to exactly 0 (rare) is recomputed exactly, as on the CPU, so that
//   its sign is exact and the test stays watertight: from Dekker's product errors, in fp32 and
//   without fma (GLSL does not promise to fuse one; lavapipe does not), so no fp64 at all;
// - divisions are GLSL's, which may be off by 2.5 ulp: t, u, v may then differ from the CPU's
//   in the last bits (lavapipe divides exactly and matches the CPU bit for bit; the tests that
//   compare bits run there). Watertightness does not depend on the division.
// Denormal inputs are out of scope: a device that flushes them to zero may differ there.
#ifndef VASTRAY_WATERTIGHT_GLSL
#define VASTRAY_WATERTIGHT_GLSL

struct WatertightRay {
    vec3 origin;
    int kx, ky, kz;
    float sx, sy, sz;
};

// WatertightRay::fromSurface for the ray being traced: set by wf_walk.comp for bounce and shadow
// rays (a per-invocation global, so that the traversal's signatures stay those trace.comp uses).
bool gRayFromSurface = false;

// std::fmax for the non-NaN operands it is used with here.
float cppFmax(float a, float b) { return a < b ? b : a; }

bool isFiniteVec(vec3 v) { return !any(isinf(v)) && !any(isnan(v)); }

// Mirrors prepareWatertightRay: false for a zero or non-finite direction.
bool prepareWatertightRay(vec3 origin, vec3 d, out WatertightRay r) {
    r.origin = origin;
    r.kx = 0, r.ky = 1, r.kz = 2;
    r.sx = 0.0, r.sy = 0.0, r.sz = 1.0;
    if (!isFiniteVec(d) || !isFiniteVec(origin)) return false;
    const float ax = abs(d.x), ay = abs(d.y), az = abs(d.z);
    const int kz = (ax >= ay && ax >= az) ? 0 : (ay >= az ? 1 : 2);
    if (d[kz] == 0.0) return false;
    int kx = (kz + 1) % 3;
    int ky = (kx + 1) % 3;
    if (d[kz] < 0.0) {  // looking down -z mirrors the plane; swapping x and y restores the winding
        const int swap = kx;
        kx = ky, ky = swap;
    }
    r.kx = kx, r.ky = ky, r.kz = kz;
    r.sx = d[kx] / d[kz];
    r.sy = d[ky] / d[kz];
    r.sz = 1.0 / d[kz];
    return true;
}

// Mirrors detail::productError (Dekker, Veltkamp's split): a*b == p + productError(a, b, p)
// exactly for p = a*b; every step rounded on its own.
float productError(float a, float b, float p) {
    precise float ca = 4097.0 * a, cb = 4097.0 * b;
    precise float ah = ca - (ca - a), al = a - ah;
    precise float bh = cb - (cb - b), bl = b - bh;
    precise float e = al * bl - (((p - ah * bh) - al * bh) - ah * bl);
    return e;
}

// Mirrors detail::zeroEdgeFunctionExact: a*b - c*d where the float result was exactly 0. Off the
// hot path.
float zeroEdgeFunctionExact(float a, float b, float c, float d) {
    precise float p = a * b, q = c * d;
    precise float e = productError(a, b, p) - productError(c, d, q);
    return e;
}

// Mirrors detail::conservativeTMin (pbrt-v4's bound on the rounding error of t).
float conservativeTMin(float ax, float ay, float bx, float by, float cx, float cy, float az, float bz, float cz,
                       float u, float v, float w, float rcpDet) {
    const float kGamma2 = 1.19209304e-07, kGamma3 = 1.78813956e-07, kGamma5 = 2.98023259e-07;
    const float maxZt = cppFmax(cppFmax(abs(az), abs(bz)), abs(cz));
    const float maxXt = cppFmax(cppFmax(abs(ax), abs(bx)), abs(cx));
    const float maxYt = cppFmax(cppFmax(abs(ay), abs(by)), abs(cy));
    precise float deltaZ = kGamma3 * maxZt;
    precise float deltaX = kGamma5 * (maxXt + maxZt);
    precise float deltaY = kGamma5 * (maxYt + maxZt);
    precise float deltaE = 2.0 * (kGamma2 * maxXt * maxYt + deltaY * maxXt + deltaX * maxYt);
    const float maxE = cppFmax(cppFmax(abs(u), abs(v)), abs(w));
    precise float bound = 3.0 * (kGamma3 * maxE * maxZt + deltaE * maxZt + deltaZ * maxE) * abs(rcpDet);
    return bound;
}

struct TriangleHit {
    float t, u, v;
    bool frontFacing;
};

bool intersectTriangle(WatertightRay r, vec3 v0, vec3 v1, vec3 v2, bool cullBackFace, float tMin, float tMax,
                       out TriangleHit hit) {
    hit = TriangleHit(0.0, 0.0, 0.0, false);
    precise vec3 a = v0 - r.origin, b = v1 - r.origin, c = v2 - r.origin;
    precise float ax = a[r.kx] - r.sx * a[r.kz], ay = a[r.ky] - r.sy * a[r.kz];
    precise float bx = b[r.kx] - r.sx * b[r.kz], by = b[r.ky] - r.sy * b[r.kz];
    precise float cx = c[r.kx] - r.sx * c[r.kz], cy = c[r.ky] - r.sy * c[r.kz];
    precise float u = cx * by - cy * bx;  // weight of v0
    precise float v = ax * cy - ay * cx;  // weight of v1
    precise float w = bx * ay - by * ax;  // weight of v2
    if (u == 0.0) u = zeroEdgeFunctionExact(cx, by, cy, bx);
    if (v == 0.0) v = zeroEdgeFunctionExact(ax, cy, ay, cx);
    if (w == 0.0) w = zeroEdgeFunctionExact(bx, ay, by, ax);
    const bool anyNegative = u < 0.0 || v < 0.0 || w < 0.0;
    const bool anyPositive = u > 0.0 || v > 0.0 || w > 0.0;
    if (anyNegative && (anyPositive || cullBackFace)) return false;
    precise float det = u + v + w;
    if (det == 0.0) return false;
    precise float az = r.sz * a[r.kz], bz = r.sz * b[r.kz], cz = r.sz * c[r.kz];
    precise float scaledT = u * az + v * bz + w * cz;
    precise float rcpDet = 1.0 / det;
    precise float t = scaledT * rcpDet;
    if (!(t >= tMin && t <= tMax)) return false;  // also rejects NaN
    if (gRayFromSurface && t <= conservativeTMin(ax, ay, bx, by, cx, cy, az, bz, cz, u, v, w, rcpDet)) return false;
    precise float hu = v * rcpDet, hv = w * rcpDet;
    hit = TriangleHit(t, hu, hv, det > 0.0);
    return true;
}

#endif  // VASTRAY_WATERTIGHT_GLSL
