#include "vastray/core/RayCone.h"

#include <cmath>

#include "vastray/core/Sampling.h"
#include "vastray/core/VecMath.h"

namespace vastray {

const char* textureLodModeName(TextureLodMode mode) { return mode == TextureLodMode::Finest ? "finest" : "cone"; }

float scatterSpread(float pdf, float maxSpread) {
    if (!(pdf > 0.0f) || !std::isfinite(pdf)) return maxSpread;
    return maxSpread * std::fmin(1.0f, 1.0f / (kPi * pdf));
}

RayCone scatterCone(RayCone cone, float t, float pdf, float maxSpread) {
    return {coneWidthAt(cone, t), cone.spread + scatterSpread(pdf, maxSpread)};
}

float worldPerUvArea(Vec3f p0, Vec3f p1, Vec3f p2, std::array<float, 2> t0, std::array<float, 2> t1,
                     std::array<float, 2> t2) {
    const float world = length(cross(p1 - p0, p2 - p0));
    const float du1 = t1[0] - t0[0], dv1 = t1[1] - t0[1], du2 = t2[0] - t0[0], dv2 = t2[1] - t0[1];
    const float uv = std::fabs(du1 * dv2 - dv1 * du2);
    const float ratio = world / uv;
    return uv > 0.0f && std::isfinite(ratio) ? ratio : 0.0f;
}

float mapLod(const UvTransform& m, uint32_t width, uint32_t height, const MapFootprint& footprint) {
    const float det = std::fabs(m[0] * m[4] - m[1] * m[3]);
    return textureLod(det * float(width) * float(height), footprint.worldPerUv, footprint.coneWidth,
                      footprint.cosTheta);
}

}  // namespace vastray
