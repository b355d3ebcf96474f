#pragma once
// Vector helpers the renderers share (Vec3.h holds the plain type and its arithmetic).
#include <cmath>

#include "vastray/core/Vec3.h"

namespace vastray {

inline float dot(Vec3f a, Vec3f b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3f cross(Vec3f a, Vec3f b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(Vec3f a) { return std::sqrt(dot(a, a)); }
// Zero stays zero (callers validate directions before they matter).
inline Vec3f normalize(Vec3f a) {
    const float l = length(a);
    return l > 0.0f ? a * (1.0f / l) : a;
}
// Component-wise product (colours, throughput).
inline Vec3f mul(Vec3f a, Vec3f b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
inline float maxComponent(Vec3f a) { return std::fmax(a.x, std::fmax(a.y, a.z)); }

}  // namespace vastray
