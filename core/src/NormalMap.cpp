#include "vastray/core/NormalMap.h"

#include <cmath>

#include "vastray/core/VecMath.h"

namespace vastray {
namespace {
bool finite(Vec3f a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
}  // namespace

UvDerivatives uvDerivatives(const UvTransform& transform, Vec3f p0, Vec3f p1, Vec3f p2, std::array<float, 2> t0,
                            std::array<float, 2> t1, std::array<float, 2> t2) {
    std::array<float, 2> uv[3];
    applyUvTransform(transform, t0[0], t0[1], uv[0][0], uv[0][1]);
    applyUvTransform(transform, t1[0], t1[1], uv[1][0], uv[1][1]);
    applyUvTransform(transform, t2[0], t2[1], uv[2][0], uv[2][1]);
    const float du1 = uv[1][0] - uv[0][0], dv1 = uv[1][1] - uv[0][1];
    const float du2 = uv[2][0] - uv[0][0], dv2 = uv[2][1] - uv[0][1];
    const float det = du1 * dv2 - dv1 * du2;
    UvDerivatives d;
    if (!(det != 0.0f) || !std::isfinite(det)) return d;
    const float r = 1.0f / det;
    const Vec3f e1 = p1 - p0, e2 = p2 - p0;
    d.dpdu = (e1 * dv2 - e2 * dv1) * r;
    d.dpdv = (e2 * du1 - e1 * du2) * r;
    d.valid = finite(d.dpdu) && finite(d.dpdv);
    return d;
}

Vec3f decodeNormalTexel(float r, float g, float b, float scale) {
    return {(2.0f * r - 1.0f) * scale, (2.0f * g - 1.0f) * scale, 2.0f * b - 1.0f};
}

Vec3f perturbNormal(Vec3f normal, const UvDerivatives& d, Vec3f local) {
    if (!d.valid || !finite(local) || (local.x == 0.0f && local.y == 0.0f && local.z > 0.0f)) return normal;
    const Vec3f along = d.dpdu - normal * dot(normal, d.dpdu);
    const float alongLength = length(along);
    if (!(alongLength > 0.0f) || !std::isfinite(alongLength)) return normal;
    const Vec3f tangent = along * (1.0f / alongLength);
    Vec3f bitangent = cross(normal, tangent);
    if (dot(bitangent, d.dpdv) > 0.0f) bitangent = bitangent * -1.0f;  // up the image is -dp/dv
    const Vec3f bent = tangent * local.x + bitangent * local.y + normal * local.z;
    const float bentLength = length(bent);
    if (!(bentLength > 0.0f) || !std::isfinite(bentLength)) return normal;
    return bent * (1.0f / bentLength);
}

}  // namespace vastray
