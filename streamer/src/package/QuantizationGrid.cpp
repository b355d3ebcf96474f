#include <algorithm>
#include <bit>
#include <cmath>

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
    return grid;
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

}  // namespace vastray
