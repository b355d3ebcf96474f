#include <algorithm>
#include <bit>
#include <cmath>

#include "vastray/streamer/Import.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {

QuantizationGrid QuantizationGrid::forBounds(const Aabb& bounds, uint32_t bits) {
    QuantizationGrid grid;
    grid.bits = bits;
    const Vec3f extent = bounds.extent();
    for (int axis = 0; axis < 3; ++axis) grid.origin[axis] = bounds.lo[axis];
    // One range for all axes (as Draco's explicit quantization): the grid step is isotropic.
    grid.range = std::max({double(extent.x), double(extent.y), double(extent.z)});
    if (!(grid.range > 0)) grid.range = 1;
    if (bits == 0) return grid;
    // The smallest power of two s with s * (2^bits - 3) >= range: the bounds, widened by up to a
    // step below to an origin on the grid, still end below the last coordinate.
    const double cells = std::max(1.0, double((uint64_t(1) << bits) - 3));
    int exponent = 0;
    std::frexp(grid.range / cells, &exponent);
    double s = std::ldexp(1.0, exponent);
    if (std::ldexp(1.0, exponent - 1) * cells >= grid.range) s = std::ldexp(1.0, exponent - 1);
    s = std::max(s, 0x1p-126);
    QuantizationGrid exact = grid;
    exact.range = s * double((uint64_t(1) << bits) - 1);
    for (int axis = 0; axis < 3; ++axis) exact.origin[axis] = std::floor(double(bounds.lo[axis]) / s) * s + 0.0;
    for (int axis = 0; axis < 3; ++axis)
        if (std::fabs(exact.origin[axis]) > kMaxAbsCoordinate) return grid;
    if (exact.range > 2.0 * kMaxAbsCoordinate || exact.step() != s) return grid;
    return exact;
}

double QuantizationGrid::step() const {
    return bits == 0 ? 0.0 : range / double((uint64_t(1) << bits) - 1);
}

int32_t QuantizationGrid::quantize(float value, int axis) const {
    const double maxQ = double((uint64_t(1) << bits) - 1);
    const double q = std::floor((double(value) - origin[axis]) / range * maxQ + 0.5);
    return int32_t(std::clamp(q, 0.0, maxQ));
}

float QuantizationGrid::dequantize(int32_t q, int axis) const {
    return float(origin[axis] + double(q) * step());
}

Vec3f QuantizationGrid::position(const int32_t* words) const {
    if (bits == 0) return {std::bit_cast<float>(words[0]), std::bit_cast<float>(words[1]), std::bit_cast<float>(words[2])};
    return {dequantize(words[0], 0), dequantize(words[1], 1), dequantize(words[2], 2)};
}

bool QuantizationGrid::packsPositions() const {
    if (bits == 0 || bits > 20) return false;
    const double s = step();
    int exponent = 0;
    if (!(s >= 0x1p-126 && s <= 0x1p100) || std::frexp(s, &exponent) != 0.5) return false;
    const double top = double((uint64_t(1) << bits) - 1) * s;
    for (int axis = 0; axis < 3; ++axis) {
        const double o = origin[axis];
        if (double(float(o)) != o || std::fmod(o, s) != 0) return false;
        // fp32's spacing in the binade of the grid's largest coordinate, against 2^19 steps (half
        // the margin the proof needs, so that rounding `largest` here cannot matter).
        const double largest = std::max(std::fabs(o), std::fabs(o + top));
        std::frexp(largest, &exponent);
        if (largest > 0 && std::ldexp(1.0, exponent - 24) > std::ldexp(s, 19)) return false;
    }
    return true;
}

uint64_t QuantizationGrid::packedPosition(const Vec3f& p) const {
    uint64_t packed = 0;
    packPositions(&p, 1, &packed);
    return packed;
}

void QuantizationGrid::packPositions(const Vec3f* positions, size_t count, uint64_t* out) const {
    const double inverse = 1.0 / step();  // a power of two: the products are exact
    const double o[3] = {origin[0], origin[1], origin[2]};
    constexpr double kLimit = double(1u << kPackedPositionBits);
    for (size_t v = 0; v < count; ++v) {
        uint64_t packed = 0;
        for (int axis = 0; axis < 3; ++axis) {
            const double m = (double(positions[v][axis]) - o[axis]) * inverse;
            packed |= (m >= 0 && m < kLimit ? uint64_t(m) : 0) << (kPackedPositionBits * axis);
        }
        out[v] = packed;
    }
}

Vec3f QuantizationGrid::unpackedPosition(uint64_t packed) const {
    const float s = float(step());
    constexpr uint64_t kMask = (uint64_t(1) << kPackedPositionBits) - 1;
    Vec3f p;
    for (int axis = 0; axis < 3; ++axis) {
        const float m = float(uint32_t((packed >> (kPackedPositionBits * axis)) & kMask));
        const float product = m * s;  // exact
        p[axis] = float(origin[axis]) + product;
    }
    return p;
}

bool QuantizationGrid::packsExactly(const Vec3f& p) const {
    for (int axis = 0; axis < 3; ++axis)
        if (!std::isfinite(p[axis])) return false;
    const Vec3f back = unpackedPosition(packedPosition(p));
    for (int axis = 0; axis < 3; ++axis)
        if (std::bit_cast<uint32_t>(back[axis]) != std::bit_cast<uint32_t>(p[axis])) return false;
    return true;
}

}  // namespace vastray
