#include "import/Triangulate.h"

#include <array>
#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include <mapbox/earcut.hpp>

#include "import/ImportCommon.h"

namespace vastray::import {

using Point2 = std::array<double, 2>;

struct PolygonTriangulator::Scratch {
    std::vector<std::vector<Point2>> rings{1};  // one outer ring: faces have no holes
    std::vector<uint32_t> convex;               // clipConvex's shrinking ring
    mapbox::detail::Earcut<uint32_t> earcut;    // reused: its node pool outlives a polygon
};

PolygonTriangulator::PolygonTriangulator() : scratch_(std::make_unique<Scratch>()) {}
PolygonTriangulator::~PolygonTriangulator() = default;

namespace {

double cross2(const Point2& a, const Point2& b, const Point2& c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

void fan(const std::vector<uint32_t>& corners, std::vector<uint32_t>& out) {
    for (size_t i = 1; i + 1 < corners.size(); ++i) out.insert(out.end(), {corners[0], corners[i], corners[i + 1]});
}

// No turn against the polygon's orientation (collinear corners allowed), and the turns add
// up to one full circle (a star drawn twice around turns twice). A corner that lies behind
// the line of its neighbours by less than `tolerance` (the positions' float rounding) counts
// as collinear: a 10^6-corner circle stored in float zigzags by that much.
bool isConvex(const std::vector<Point2>& ring, double orientation, double tolerance) {
    const size_t n = ring.size();
    double turning = 0;
    for (size_t i = 0; i < n; ++i) {
        const Point2& a = ring[(i + n - 1) % n];
        const Point2& b = ring[i];
        const Point2& c = ring[(i + 1) % n];
        const double cross = cross2(a, b, c) * orientation;
        if (cross < 0 && -cross > tolerance * std::hypot(c[0] - a[0], c[1] - a[1])) return false;
        const double dot = (b[0] - a[0]) * (c[0] - b[0]) + (b[1] - a[1]) * (c[1] - b[1]);
        turning += std::atan2(cross, dot);
    }
    return turning < 2 * M_PI + 1.0;  // exactly 2 pi up to rounding; twice around is 4 pi
}

// Convex polygons: clip every second corner, round after round, as earcut does but without
// its point-in-triangle tests (nothing lies inside a convex ear). O(n), and each round's
// triangles join neighbouring corners, so the partition sees small triangles, not a fan.
void clipConvex(const std::vector<uint32_t>& corners, std::vector<uint32_t>& ring, std::vector<uint32_t>& out) {
    ring.assign(corners.begin(), corners.end());
    size_t m = ring.size();
    while (m >= 3) {
        size_t kept = 0, i = 0;
        for (; i + 2 < m; i += 2) {
            out.insert(out.end(), {ring[i], ring[i + 1], ring[i + 2]});
            ring[kept++] = ring[i];
        }
        for (; i < m; ++i) ring[kept++] = ring[i];
        m = kept;
    }
}

// A corner passed more than twice (twice is a bridge to a hole, as some exporters write
// them) makes a polygon that winds over itself; earcut's repair of it took cubic time
// (3,000 corners cycling over one triangle: 7 s).
bool revisitsACorner(const std::vector<Point2>& ring) {
    struct Hash {
        size_t operator()(const Point2& p) const {
            return std::hash<double>()(p[0]) * 0x9E3779B97F4A7C15ull ^ std::hash<double>()(p[1]);
        }
    };
    std::unordered_map<Point2, int, Hash> seen;
    seen.reserve(ring.size());
    for (const Point2& p : ring)
        if (++seen[p] > 2) return true;
    return false;
}

}  // namespace

uint64_t PolygonTriangulator::triangulate(const std::vector<Vec3f>& positions, const std::vector<uint32_t>& corners,
                                          std::vector<uint32_t>& out) {
    failure_.clear();
    const size_t n = corners.size();
    if (n < 3) return 0;
    if (n == 3) {
        out.insert(out.end(), corners.begin(), corners.end());
        return 1;
    }
    // Newell's normal, relative to the first corner (no cancellation far from the origin).
    const Vec3f origin = positions[corners[0]];
    auto local = [&](size_t i) {
        const Vec3f& p = positions[corners[i]];
        return std::array<double, 3>{double(p.x) - origin.x, double(p.y) - origin.y, double(p.z) - origin.z};
    };
    std::array<double, 3> normal{0, 0, 0};
    for (size_t i = 0; i < n; ++i) {
        const auto a = local(i), b = local((i + 1) % n);
        normal[0] += (a[1] - b[1]) * (a[2] + b[2]);
        normal[1] += (a[2] - b[2]) * (a[0] + b[0]);
        normal[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    // Project onto the plane of the two other axes, in cyclic order, so that the polygon
    // winds counter-clockwise there exactly when its normal points along the dropped axis.
    int drop = 0;
    for (int k = 1; k < 3; ++k)
        if (std::fabs(normal[k]) > std::fabs(normal[drop])) drop = k;
    if (normal[drop] == 0.0) {  // collinear corners: nothing to clip; the fan is all degenerate
        fan(corners, out);
        return n - 2;
    }
    const int u = (drop + 1) % 3, v = (drop + 2) % 3;
    const double orientation = normal[drop] > 0 ? 1.0 : -1.0;
    std::vector<Point2>& ring = scratch_->rings[0];
    ring.resize(n);
    float extent = 0;  // largest coordinate magnitude: sets the positions' rounding
    for (size_t i = 0; i < n; ++i) {
        const auto p = local(i);
        ring[i] = {p[u], p[v]};
        const Vec3f& world = positions[corners[i]];
        extent = std::max({extent, std::fabs(world.x), std::fabs(world.y), std::fabs(world.z)});
    }
    if (n == 4) {  // quads, the common polygon: split along a diagonal that lies inside
        if (cross2(ring[0], ring[1], ring[2]) * orientation > 0 && cross2(ring[0], ring[2], ring[3]) * orientation > 0) {
            out.insert(out.end(), {corners[0], corners[1], corners[2], corners[0], corners[2], corners[3]});
            return 2;
        }
        if (cross2(ring[0], ring[1], ring[3]) * orientation > 0 && cross2(ring[1], ring[2], ring[3]) * orientation > 0) {
            out.insert(out.end(), {corners[0], corners[1], corners[3], corners[1], corners[2], corners[3]});
            return 2;
        }
    }
    if (isConvex(ring, orientation, 8.0 * std::numeric_limits<float>::epsilon() * extent)) {
        clipConvex(corners, scratch_->convex, out);
        return n - 2;
    }
    if (n > kMaxEarClipCorners) {
        failure_ = "a polygon of " + std::to_string(n) + " corners that is not convex exceeds the ear-clipping limit of " +
                   std::to_string(kMaxEarClipCorners) + " (convex ones may have up to " +
                   std::to_string(kMaxPolygonCorners) + ")";
        return 0;
    }
    if (revisitsACorner(ring)) {
        if (n > kMaxFanCorners) {
            failure_ = "a polygon of " + std::to_string(n) + " corners passes one corner more than twice; " +
                       "such polygons are fan-triangulated, up to " + std::to_string(kMaxFanCorners) + " corners";
            return 0;
        }
        fan(corners, out);
        return n - 2;
    }
    scratch_->earcut(scratch_->rings);
    const std::vector<uint32_t>& local3 = scratch_->earcut.indices;
    if (local3.empty()) {  // self-overlapping beyond earcut's repair: keep every corner covered
        fan(corners, out);
        return n - 2;
    }
    for (size_t t = 0; t + 2 < local3.size(); t += 3) {
        uint32_t a = local3[t], b = local3[t + 1], c = local3[t + 2];
        if (cross2(ring[a], ring[b], ring[c]) * orientation < 0) std::swap(b, c);
        out.insert(out.end(), {corners[a], corners[b], corners[c]});
    }
    return local3.size() / 3;
}

}  // namespace vastray::import
