#pragma once
// Polygon triangulation for the importers (OBJ faces, PLY face lists): ear clipping with
// mapbox's earcut (vendored, third_party/earcut), so that a concave polygon (a ring, an L)
// keeps its shape instead of filling in as a fan would, and a polygon of 10^6 corners
// triangulates in well under a second when it is convex (a disc, a cylinder's cap: clipped
// in O(n) without earcut's tests). Earcut's time grows faster than linearly on large
// concave polygons (16,384 random corners: 0.9 s), so concave ones are limited to
// kMaxEarClipCorners; polygons that pass a corner more than twice are fans (kMaxFanCorners).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "vastray/core/Vec3.h"

namespace vastray::import {

// Concave polygons up to this many corners are ear-clipped (random 16,384-corner rings: 0.9 s).
constexpr uint64_t kMaxEarClipCorners = 16384;

class PolygonTriangulator {
public:
    PolygonTriangulator();
    ~PolygonTriangulator();
    PolygonTriangulator(const PolygonTriangulator&) = delete;
    PolygonTriangulator& operator=(const PolygonTriangulator&) = delete;

    // Appends the triangles of the polygon `corners` (indices into `positions`, in the
    // file's winding order) to `out`, three indices each, every triangle wound as the
    // polygon is. Triangles and convex quads take a fast path; a polygon whose corners are
    // all collinear (no plane) becomes a fan of degenerate triangles, which the importers'
    // last step drops and counts. Returns the number of triangles appended; 0 with
    // failure() set when the polygon is over a limit (the caller names file and element).
    uint64_t triangulate(const std::vector<Vec3f>& positions, const std::vector<uint32_t>& corners,
                         std::vector<uint32_t>& out);
    const std::string& failure() const { return failure_; }

private:
    struct Scratch;
    std::unique_ptr<Scratch> scratch_;
    std::string failure_;
};

}  // namespace vastray::import
