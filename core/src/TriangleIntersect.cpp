#include "vastray/core/TriangleIntersect.h"

#include <cmath>
#include <utility>

namespace vastray {

bool prepareWatertightRay(const Ray& ray, WatertightRay* out) {
    const Vec3f d = ray.direction;
    if (!isFinite(d) || !isFinite(ray.origin)) return false;
    const float ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
    const int kz = (ax >= ay && ax >= az) ? 0 : (ay >= az ? 1 : 2);
    if (d[kz] == 0.0f) return false;
    int kx = (kz + 1) % 3;
    int ky = (kx + 1) % 3;
    // Looking down -z mirrors the plane; swapping x and y restores the winding.
    if (d[kz] < 0.0f) std::swap(kx, ky);
    out->origin = ray.origin;
    out->kx = kx;
    out->ky = ky;
    out->kz = kz;
    out->sx = d[kx] / d[kz];
    out->sy = d[ky] / d[kz];
    out->sz = 1.0f / d[kz];
    return true;
}

}  // namespace vastray
