#pragma once
// The OpenImageIO implementations behind writeImageFile and diffImageFiles (ImageFile.h and
// ImageDiff.h describe them); only the module's table calls these.
#include <string>

#include "vastray/core/ImageDiff.h"
#include "vastray/core/RenderImage.h"
#include "vastray/core/Result.h"

namespace vastray::oiio {

Status writeImageFile(const std::string& path, const RenderImage& image);
Result<ImageDiffReport> diffImageFiles(const std::string& pathA, const std::string& pathB);

}  // namespace vastray::oiio
