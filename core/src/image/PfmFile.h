#pragma once
#include <string>

#include "vastray/core/RenderImage.h"
#include "vastray/core/Result.h"

namespace vastray {

// Writes the beauty's linear RGB as a little-endian portable float map (no alpha, no AOVs, no
// region: each is an error naming the file). ImageFile.h's writeImageFile calls it for .pfm.
Status writePfmFile(const std::string& path, const RenderImage& image);

}  // namespace vastray
