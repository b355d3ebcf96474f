#pragma once
// The texture tests' view of the unit quad [0, 1]^2 at z = 0: looking straight at it from +z,
// the quad exactly filling a side x side image, so that with a side x side texture each pixel
// centre is a texel centre. One sample a pixel, no AOVs.
#include <cmath>
#include <cstdint>

#include "vastray/core/RenderOptions.h"

namespace vastray::test {

inline RenderOptions headOnUnitQuad(uint32_t side) {
    RenderOptions o;
    o.width = o.height = side;
    o.samplesPerPixel = 1;
    o.frameScene = false;
    const float fov = 40.0f;
    o.camera = {{0.5f, 0.5f, 0.5f / std::tan(fov * 0.5f * float(M_PI) / 180.0f)}, {0.5f, 0.5f, 0}, {0, 1, 0}, fov};
    return o;
}

}  // namespace vastray::test
