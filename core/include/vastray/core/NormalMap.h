#pragma once
// Tangent-space normal maps (docs/RENDERING.md, "Normal maps"): the tangent frame of a triangle
// from its UV derivatives (pbrt-v4's and Mitsuba 3's choice when a mesh carries no tangents),
// the texel's decoding (glTF 2.0's normalTexture) and the bent shading normal. Every step is a
// plain float expression in the order written here, so that the GPU kernel computes the same
// floats (its GLSL twin marks them `precise`).
#include <array>

#include "vastray/core/MaterialTextures.h"
#include "vastray/core/Vec3.h"

namespace vastray {

// A triangle's position derivatives along the map's texture axes, in world units per unit of
// u and of v (v grows downwards in the image: glTF's texture space, which the package stores).
// valid is false when the UVs span no area (their determinant is 0) or a derivative is not
// finite: the map then leaves the shading normal as it is.
struct UvDerivatives {
    Vec3f dpdu, dpdv;
    bool valid = false;
};
// From corners p0, p1, p2 and their UVs t0, t1, t2, each UV first mapped by `transform` (the
// normal map's KHR_texture_transform): the frame follows the image's axes.
UvDerivatives uvDerivatives(const UvTransform& transform, Vec3f p0, Vec3f p1, Vec3f p2, std::array<float, 2> t0,
                            std::array<float, 2> t1, std::array<float, 2> t2);

// The tangent-space normal a texel's linear (r, g, b) in [0, 1] encodes (glTF: +X towards +u,
// +Y up in the image, +Z along the surface normal): ((2r - 1) scale, (2g - 1) scale, 2b - 1),
// not normalized.
Vec3f decodeNormalTexel(float r, float g, float b, float scale);

// The unit front-side shading normal `normal` (the interpolated vertex normal, or the geometric
// one, before either is turned towards the ray) bent by the tangent-space normal `local`:
// normalize(local.x T + local.y B + local.z normal), with T = dp/du made orthogonal to `normal`
// (Gram-Schmidt) and B = cross(normal, T), negated unless it points up the image (-dp/dv).
// `normal` itself, bit for bit, when the frame is not valid, local is (0, 0, z > 0), T or the
// sum vanishes, or a value is not finite.
Vec3f perturbNormal(Vec3f normal, const UvDerivatives& derivatives, Vec3f local);

}  // namespace vastray
