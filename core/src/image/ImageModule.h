#pragma once
// The OpenImageIO image module's entry point. OpenImageIO brings ~260 shared libraries whose
// relocation took ~0.35 s at every start of the program, so it lives in a module
// (libvastray_oiio.so) that the first image read or write loads; commands that touch no image
// (info, generate, --help, an import of a file without texture maps) never load it.
#include <cstdint>
#include <string>

#include "vastray/core/ImageDiff.h"
#include "vastray/core/ImageFile.h"
#include "vastray/core/RenderImage.h"
#include "vastray/core/Result.h"

namespace vastray {

// Bumped whenever the table or the types it passes change: a module from another build is refused.
constexpr uint32_t kImageModuleVersion = 5;

struct ImageModuleApi {
    uint32_t version;
    Status (*writeImageFile)(const std::string& path, const RenderImage& image);
    Result<ImageDiffReport> (*diffImageFiles)(const std::string& pathA, const std::string& pathB);
    Result<ImageChannels> (*readImageChannels)(const std::string& path, const std::vector<std::string>& names,
                                               uint64_t maxPixels);
    Status (*writeRgba8Png)(const std::string& path, uint32_t width, uint32_t height,
                            const std::vector<uint8_t>& rgba);
    Result<StoredImage> (*readStoredImage)(const std::string& path);
    Status (*writeStoredImage)(const std::string& path, const StoredImage& image);
    Result<Rgba8Image> (*readRgba8Image)(const std::string& path, uint64_t maxPixels);
    Result<Rgba8Image> (*decodeRgba8Image)(const std::string& name, const std::string& extension,
                                           const std::vector<uint8_t>& bytes, uint64_t maxPixels);
};

}  // namespace vastray

// The one symbol the module exports.
extern "C" const vastray::ImageModuleApi* vastray_image_module();
#define VASTRAY_IMAGE_MODULE_SYMBOL "vastray_image_module"
#define VASTRAY_IMAGE_MODULE_FILE "libvastray_oiio.so"
