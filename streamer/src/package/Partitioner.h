#pragma once
// The top-level split: a binned surface-area cost that also charges for duplicated
// references, and the exact classification of triangles against a split plane (a
// triangle's bounds are always its part inside the cell, found by clipping).
#include <cstdint>
#include <optional>
#include <vector>

#include "vastray/core/Aabb.h"
#include "vastray/core/Vec3.h"

namespace vastray {

struct TriangleRef {
    uint32_t triangle;
    Aabb bounds;  // the triangle clipped to the current cell
};

struct SplitPlane {
    int axis = 0;
    float position = 0;
    double cost = 0;
};

struct PartitionOptions {
    int bins = 32;
    // Extra cost of one duplicated reference, in units of "one triangle in the whole cell".
    double duplicationCost = 0.5;
};

class Partitioner {
public:
    Partitioner(const Vec3f* positions, const uint32_t* indices, PartitionOptions options = {})
        : positions_(positions), indices_(indices), options_(options) {}

    // Refs for every triangle that touches `cell`, with clipped bounds.
    std::vector<TriangleRef> initialRefs(const std::vector<uint32_t>& triangles, const Aabb& cell) const;

    // The cheapest plane that actually separates something; nullopt when no plane reduces
    // the larger side (every triangle spans the whole cell).
    std::optional<SplitPlane> findSplit(const std::vector<TriangleRef>& refs, const Aabb& cell) const;

    // Moves refs to the children; a ref straddling the plane is clipped to each child box.
    // A triangle lying in the plane goes to both; one touching it only from one side to that side.
    void split(std::vector<TriangleRef>& refs, const Aabb& cell, const SplitPlane& plane,
               std::vector<TriangleRef>& left, std::vector<TriangleRef>& right) const;

    static Aabb childBox(const Aabb& cell, const SplitPlane& plane, bool above);

    // Bounds of the part of a triangle inside `box` (Sutherland–Hodgman in double); empty when
    // they do not meet.
    static Aabb clipTriangle(Vec3f a, Vec3f b, Vec3f c, const Aabb& box);

private:
    const Vec3f* positions_;
    const uint32_t* indices_;
    PartitionOptions options_;
};

}  // namespace vastray
