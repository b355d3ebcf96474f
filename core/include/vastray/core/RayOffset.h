#pragma once
// Where a secondary ray starts: Wächter and Binder, "A Fast and Robust Method for Avoiding
// Self-Intersection", Ray Tracing Gems ch. 6 (2019). The hit point moves along the
// geometric normal by a fixed number of float ULPs (so the offset scales with the
// coordinate's magnitude), or by a tiny absolute step near the origin where ULPs vanish.
// Never a fixed world-space epsilon.
#include <bit>
#include <cmath>
#include <cstdint>

#include "vastray/core/Vec3.h"

namespace vastray {

// `p`: hit point computed from barycentrics; `n`: unit geometric normal on the side the
// new ray leaves into.
inline Vec3f offsetRayOrigin(Vec3f p, Vec3f n) {
    constexpr float kOrigin = 1.0f / 32.0f;
    constexpr float kFloatScale = 1.0f / 65536.0f;
    constexpr float kIntScale = 256.0f;
    Vec3f out;
    for (int axis = 0; axis < 3; ++axis) {
        const auto ulps = static_cast<int32_t>(kIntScale * n[axis]);
        const int32_t bits = std::bit_cast<int32_t>(p[axis]) + (p[axis] < 0.0f ? -ulps : ulps);
        out[axis] =
            std::fabs(p[axis]) < kOrigin ? p[axis] + kFloatScale * n[axis] : std::bit_cast<float>(bits);
    }
    return out;
}

}  // namespace vastray
