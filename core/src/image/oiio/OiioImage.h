#pragma once
// The OpenImageIO implementations behind writeImageFile and diffImageFiles (ImageFile.h and
// ImageDiff.h describe them); only the module's table calls these.
#include <string>

#include "vastray/core/ImageDiff.h"
#include "vastray/core/ImageFile.h"
#include "vastray/core/RenderImage.h"
#include "vastray/core/Result.h"

namespace vastray::oiio {

Status writeImageFile(const std::string& path, const RenderImage& image);
Result<ImageDiffReport> diffImageFiles(const std::string& pathA, const std::string& pathB);
Result<ImageChannels> readImageChannels(const std::string& path, const std::vector<std::string>& names);
Status writeRgba8Png(const std::string& path, uint32_t width, uint32_t height,
                     const std::vector<uint8_t>& rgba);

}  // namespace vastray::oiio
