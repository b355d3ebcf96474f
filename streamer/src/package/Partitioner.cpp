#include "package/Partitioner.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <tbb/parallel_for.h>

namespace vastray {
namespace {

constexpr double kMaxSideFraction = 0.9;
// Large cells are binned and split in fixed blocks on all cores. Blocks are fixed by index
// (not by the scheduler), and their outputs are joined in block order, so the result does
// not depend on the thread count.
constexpr size_t kBlock = 1 << 16;

size_t blockCount(size_t n) { return (n + kBlock - 1) / kBlock; }

template <typename Body>
void forEachBlock(size_t n, Body body) {
    tbb::parallel_for(size_t(0), blockCount(n), [&](size_t b) { body(b, b * kBlock, std::min(n, (b + 1) * kBlock)); });
}

template <typename T>
std::vector<T> joinBlocks(std::vector<std::vector<T>>& blocks) {
    size_t total = 0;
    for (const auto& block : blocks) total += block.size();
    std::vector<T> joined;
    joined.reserve(total);
    for (auto& block : blocks) {
        joined.insert(joined.end(), block.begin(), block.end());
        std::vector<T>().swap(block);
    }
    return joined;
}

struct Point3d {
    double v[3];
};

// Clips a convex polygon to one side of an axis plane (keep >= bound when `keepAbove`).
int clipPolygon(const Point3d* in, int count, Point3d* out, int axis, double bound, bool keepAbove) {
    int outCount = 0;
    for (int i = 0; i < count; ++i) {
        const Point3d& p = in[i];
        const Point3d& q = in[(i + 1) % count];
        const double dp = keepAbove ? p.v[axis] - bound : bound - p.v[axis];
        const double dq = keepAbove ? q.v[axis] - bound : bound - q.v[axis];
        if (dp >= 0) out[outCount++] = p;
        if ((dp < 0 && dq > 0) || (dp > 0 && dq < 0)) {
            const double s = dp / (dp - dq);
            Point3d r;
            for (int k = 0; k < 3; ++k) r.v[k] = p.v[k] + s * (q.v[k] - p.v[k]);
            r.v[axis] = bound;  // exactly on the plane, whatever the rounding
            out[outCount++] = r;
        }
    }
    return outCount;
}

Aabb triangleBounds(Vec3f a, Vec3f b, Vec3f c) {
    Aabb box;
    box.extend(a);
    box.extend(b);
    box.extend(c);
    return box;
}

}  // namespace

Aabb Partitioner::clipTriangle(Vec3f a, Vec3f b, Vec3f c, const Aabb& box) {
    const Aabb whole = triangleBounds(a, b, c);
    if (box.contains(whole)) return whole;
    if (!box.overlaps(whole)) return Aabb{};
    // A triangle clipped by 6 planes has at most 9 vertices.
    std::array<Point3d, 12> bufferA{}, bufferB{};
    bufferA[0] = {{a.x, a.y, a.z}};
    bufferA[1] = {{b.x, b.y, b.z}};
    bufferA[2] = {{c.x, c.y, c.z}};
    int count = 3;
    Point3d* in = bufferA.data();
    Point3d* out = bufferB.data();
    for (int axis = 0; axis < 3 && count > 0; ++axis) {
        count = clipPolygon(in, count, out, axis, box.lo[axis], true);
        std::swap(in, out);
        count = clipPolygon(in, count, out, axis, box.hi[axis], false);
        std::swap(in, out);
    }
    Aabb clipped;
    for (int i = 0; i < count; ++i)
        clipped.extend(Vec3f{float(in[i].v[0]), float(in[i].v[1]), float(in[i].v[2])});
    // Rounding to float may step outside by an ulp; the part is inside the box by construction.
    return count ? clipped.intersect(box) : Aabb{};
}

std::vector<TriangleRef> Partitioner::initialRefs(const std::vector<uint32_t>& triangles,
                                                  const Aabb& cell) const {
    std::vector<std::vector<TriangleRef>> blocks(blockCount(triangles.size()));
    forEachBlock(triangles.size(), [&](size_t b, size_t begin, size_t end) {
        blocks[b].reserve(end - begin);
        for (size_t k = begin; k < end; ++k) {
            const uint32_t* i = &indices_[3 * size_t(triangles[k])];
            const Aabb bounds = clipTriangle(positions_[i[0]], positions_[i[1]], positions_[i[2]], cell);
            if (!bounds.isEmpty()) blocks[b].push_back({triangles[k], bounds});
        }
    });
    return joinBlocks(blocks);
}

Aabb Partitioner::childBox(const Aabb& cell, const SplitPlane& plane, bool above) {
    Aabb box = cell;
    (above ? box.lo : box.hi)[plane.axis] = plane.position;
    return box;
}

// Start/end histograms of every axis: counts[axis][0][bin] starts, counts[axis][1][bin] ends.
using BinCounts = std::array<std::array<std::vector<uint64_t>, 2>, 3>;

static BinCounts binRefs(const std::vector<TriangleRef>& refs, const Aabb& cell, int bins) {
    std::vector<BinCounts> perBlock(blockCount(refs.size()));
    forEachBlock(refs.size(), [&](size_t b, size_t begin, size_t end) {
        BinCounts& counts = perBlock[b];
        for (int axis = 0; axis < 3; ++axis) {
            counts[axis][0].assign(bins, 0);
            counts[axis][1].assign(bins, 0);
            const double lo = cell.lo[axis], hi = cell.hi[axis];
            if (!(hi > lo)) continue;
            const double scale = bins / (hi - lo);
            for (size_t k = begin; k < end; ++k) {
                const Aabb& r = refs[k].bounds;
                counts[axis][0][std::clamp(int((r.lo[axis] - lo) * scale), 0, bins - 1)]++;
                counts[axis][1][std::clamp(int((r.hi[axis] - lo) * scale), 0, bins - 1)]++;
            }
        }
    });
    BinCounts total;
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            total[axis][side].assign(bins, 0);
            for (const BinCounts& block : perBlock)
                for (int i = 0; i < bins; ++i) total[axis][side][i] += block[axis][side][i];
        }
    return total;
}

std::optional<SplitPlane> Partitioner::findSplit(const std::vector<TriangleRef>& refs, const Aabb& cell) const {
    const int bins = options_.bins;
    const double n = double(refs.size());
    const double cellArea = cell.surfaceArea();
    const BinCounts counts = binRefs(refs, cell, bins);
    std::optional<SplitPlane> best;
    for (int axis = 0; axis < 3; ++axis) {
        const double lo = cell.lo[axis], hi = cell.hi[axis];
        if (!(hi > lo)) continue;
        const std::vector<uint64_t>& starts = counts[axis][0];
        const std::vector<uint64_t>& ends = counts[axis][1];
        // Left of plane i: triangles starting in bins < i; right: ending in bins >= i.
        uint64_t left = 0, right = uint64_t(refs.size());
        for (int i = 1; i < bins; ++i) {
            left += starts[i - 1];
            right -= ends[i - 1];
            const float position = float(lo + (hi - lo) * i / bins);
            if (!(position > cell.lo[axis] && position < cell.hi[axis])) continue;
            // The top level must shrink cells: a plane leaving 90% on one side is no progress.
            if (double(std::max(left, right)) > kMaxSideFraction * n) continue;
            SplitPlane plane{axis, position, 0};
            const double areaLeft = childBox(cell, plane, false).surfaceArea();
            const double areaRight = childBox(cell, plane, true).surfaceArea();
            plane.cost = (areaLeft * double(left) + areaRight * double(right)) / cellArea +
                         options_.duplicationCost * (double(left + right) - n);
            if (!best || plane.cost < best->cost) best = plane;
        }
    }
    return best;
}

void Partitioner::split(std::vector<TriangleRef>& refs, const Aabb& cell, const SplitPlane& plane,
                        std::vector<TriangleRef>& left, std::vector<TriangleRef>& right) const {
    const int axis = plane.axis;
    const float p = plane.position;
    const Aabb below = childBox(cell, plane, false), above = childBox(cell, plane, true);
    std::vector<std::vector<TriangleRef>> lefts(blockCount(refs.size())), rights(lefts.size());
    forEachBlock(refs.size(), [&](size_t block, size_t begin, size_t end) {
        std::vector<TriangleRef>& l = lefts[block];
        std::vector<TriangleRef>& r = rights[block];
        for (size_t k = begin; k < end; ++k) {
            const TriangleRef& ref = refs[k];
            const float lo = ref.bounds.lo[axis], hi = ref.bounds.hi[axis];
            if (lo == p && hi == p) {
                l.push_back(ref);
                r.push_back(ref);
            } else if (hi <= p) {
                l.push_back(ref);
            } else if (lo >= p) {
                r.push_back(ref);
            } else {
                const uint32_t* i = &indices_[3 * size_t(ref.triangle)];
                const Vec3f a = positions_[i[0]], b = positions_[i[1]], c = positions_[i[2]];
                const Aabb inBelow = clipTriangle(a, b, c, below);
                const Aabb inAbove = clipTriangle(a, b, c, above);
                if (!inBelow.isEmpty()) l.push_back({ref.triangle, inBelow});
                if (!inAbove.isEmpty()) r.push_back({ref.triangle, inAbove});
            }
        }
    });
    std::vector<TriangleRef>().swap(refs);
    left = joinBlocks(lefts);
    right = joinBlocks(rights);
}

}  // namespace vastray
