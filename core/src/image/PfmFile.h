#pragma once
#include <string>

#include "vastray/core/ImageFile.h"
#include "vastray/core/RenderImage.h"
#include "vastray/core/Result.h"

namespace vastray {

// Writes the beauty's linear RGB as a little-endian portable float map (no alpha, no AOVs, no
// region: each is an error naming the file). ImageFile.h's writeImageFile calls it for .pfm.
Status writePfmFile(const std::string& path, const RenderImage& image);

// Reads a portable float map ("PF": RGB, "Pf": grey, read as R = G = B; either byte order; each
// value multiplied by |scale|) as R, G and B planes, row 0 at the top. Errors name the file and
// what is wrong: the header (a token longer than 32 bytes, sizes of 0 or more than maxPixels
// pixels, a scale of 0 or not finite), or pixel data shorter or longer than the header says.
Result<ImageChannels> readPfmFile(const std::string& path, uint64_t maxPixels);

}  // namespace vastray
