#pragma once
#include <limits>

#include "vastray/core/Vec3.h"

namespace vastray {

// Axis-aligned box in world space. An empty box has lo > hi.
struct Aabb {
    Vec3f lo{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
             std::numeric_limits<float>::infinity()};
    Vec3f hi{-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
             -std::numeric_limits<float>::infinity()};

    bool isEmpty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    void extend(Vec3f p) { lo = min(lo, p); hi = max(hi, p); }
    void extend(const Aabb& b) { lo = min(lo, b.lo); hi = max(hi, b.hi); }
    Vec3f extent() const { return hi - lo; }
    double surfaceArea() const {
        if (isEmpty()) return 0.0;
        const Vec3f e = extent();
        return 2.0 * (double(e.x) * e.y + double(e.y) * e.z + double(e.z) * e.x);
    }
    int longestAxis() const {
        const Vec3f e = extent();
        return (e.x >= e.y && e.x >= e.z) ? 0 : (e.y >= e.z ? 1 : 2);
    }
    Aabb intersect(const Aabb& b) const { return {max(lo, b.lo), min(hi, b.hi)}; }
    bool overlaps(const Aabb& b) const {
        return lo.x <= b.hi.x && b.lo.x <= hi.x && lo.y <= b.hi.y && b.lo.y <= hi.y &&
               lo.z <= b.hi.z && b.lo.z <= hi.z;
    }
    bool contains(const Aabb& b) const {
        return lo.x <= b.lo.x && lo.y <= b.lo.y && lo.z <= b.lo.z && hi.x >= b.hi.x &&
               hi.y >= b.hi.y && hi.z >= b.hi.z;
    }
    friend bool operator==(const Aabb& a, const Aabb& b) { return a.lo == b.lo && a.hi == b.hi; }
};

}  // namespace vastray
