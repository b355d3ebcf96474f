#pragma once
// Image files through OpenImageIO, which lives in a module loaded on the first image read or
// write (src/image/ImageModule.h says why); no OIIO type here.
#include <cmath>
#include <string>

#include "vastray/core/RenderImage.h"
#include "vastray/core/Result.h"

namespace vastray {

// By extension: .png writes the beauty tone mapped to 8-bit sRGB (no AOVs: an error if
// any were requested); .exr writes 32-bit float linear R,G,B,A and, when present, the
// channels Z, N.x, N.y, N.z, albedo.R, albedo.G, albedo.B, cost.cells, cost.triangles (float)
// and primid, chunkid (uint32).
Status writeImageFile(const std::string& path, const RenderImage& image);

// Loads the image module now (it is otherwise loaded by the first read or write): commands
// call it before long work, so that a missing or broken module fails at once, not after a
// render. The error names the module and every place it was looked for.
Status loadImageModule();

// Tone mapping of the PNG beauty (docs/RENDERING.md): extended Reinhard with white
// point 4 per channel, then the sRGB transfer function. Input linear, output [0, 1].
inline float toneMapToDisplay(float linear) {
    constexpr float kWhiteSquared = 16.0f;
    const float x = std::fmax(linear, 0.0f);
    const float mapped = std::fmin(x * (1.0f + x / kWhiteSquared) / (1.0f + x), 1.0f);
    return mapped <= 0.0031308f ? 12.92f * mapped : 1.055f * std::pow(mapped, 1.0f / 2.4f) - 0.055f;
}

}  // namespace vastray
