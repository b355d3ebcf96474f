#pragma once
// Image files through OpenImageIO (linked by vastray_image only; no OIIO type here).
#include <string>

#include "vastray/core/RenderImage.h"
#include "vastray/core/Result.h"

namespace vastray {

// By extension: .png writes the beauty tone mapped to 8-bit sRGB (no AOVs: an error if
// any were requested); .exr writes 32-bit float linear R,G,B,A and, when present, the
// channels Z, N.x, N.y, N.z, albedo.R, albedo.G, albedo.B, cost.cells, cost.triangles (float)
// and primid, chunkid (uint32).
Status writeImageFile(const std::string& path, const RenderImage& image);

// Tone mapping of the PNG beauty (docs/RENDERING.md): extended Reinhard with white
// point 4 per channel, then the sRGB transfer function. Input linear, output [0, 1].
float toneMapToDisplay(float linear);

}  // namespace vastray
