#pragma once
// Direction sampling shared by every backend. Directions are world space, unit length.
#include <cmath>

#include "vastray/core/VecMath.h"

namespace vastray {

constexpr float kPi = 3.14159265358979323846f;

// Orthonormal basis around unit n (Duff et al., "Building an Orthonormal Basis,
// Revisited", JCGT 6(1), 2017): no branch on a threshold, no singularity.
struct Frame {
    Vec3f tangent, bitangent, normal;
    Vec3f toWorld(Vec3f local) const { return tangent * local.x + bitangent * local.y + normal * local.z; }
    Vec3f toLocal(Vec3f world) const { return {dot(tangent, world), dot(bitangent, world), dot(normal, world)}; }
};

// Duff et al.'s branchless basis. The sign test is n.z >= 0, not copysign: a face parallel to
// the z axis has n.z = +0 or -0 depending on the order of its corners (codecs rotate them), and
// the frame, hence the bounce directions, must not depend on that.
inline Frame frameAround(Vec3f n) {
    const float sign = n.z >= 0.0f ? 1.0f : -1.0f;
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    return {{1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x}, {b, sign + n.y * n.y * a, -n.y}, n};
}

// Cosine-weighted direction about +z (pdf cos(theta) / pi) from u1, u2 in [0, 1).
inline Vec3f cosineHemisphere(float u1, float u2) {
    const float r = std::sqrt(u1);
    const float phi = 2.0f * kPi * u2;
    return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::fmax(0.0f, 1.0f - u1))};
}

}  // namespace vastray
