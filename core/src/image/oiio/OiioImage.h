#pragma once
// The OpenImageIO implementations behind writeImageFile and diffImageFiles (ImageFile.h and
// ImageDiff.h describe them); only the module's table calls these.
#include <OpenImageIO/imageio.h>

#include <string>

#include "vastray/core/ImageDiff.h"
#include "vastray/core/ImageFile.h"
#include "vastray/core/RenderImage.h"
#include "vastray/core/Result.h"

namespace vastray::oiio {

Status writeImageFile(const std::string& path, const RenderImage& image);
Result<ImageDiffReport> diffImageFiles(const std::string& pathA, const std::string& pathB);
Result<ImageChannels> readImageChannels(const std::string& path, const std::vector<std::string>& names,
                                        uint64_t maxPixels);
Status writeRgba8Png(const std::string& path, uint32_t width, uint32_t height,
                     const std::vector<uint8_t>& rgba);
Result<StoredImage> readStoredImage(const std::string& path);
Status writeStoredImage(const std::string& path, const StoredImage& image);
Result<Rgba8Image> readRgba8Image(const std::string& path, uint64_t maxPixels);
Result<Rgba8Image> decodeRgba8Image(const std::string& name, const std::string& extension,
                                    const std::vector<uint8_t>& bytes, uint64_t maxPixels);

// Records where `spec`'s image lies in its frame: the EXR data and display windows, or the PNG
// text chunk kRegionTextKey (nothing for a whole frame).
void setRegion(OIIO::ImageSpec& spec, bool png, uint32_t originX, uint32_t originY, uint32_t frameWidth,
               uint32_t frameHeight);

}  // namespace vastray::oiio
