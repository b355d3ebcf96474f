// The module's exported table (everything else in the module is hidden).
#include "ImageModule.h"
#include "OiioImage.h"

extern "C" __attribute__((visibility("default"))) const vastray::ImageModuleApi* vastray_image_module() {
    static const vastray::ImageModuleApi api{vastray::kImageModuleVersion, &vastray::oiio::writeImageFile,
                                             &vastray::oiio::diffImageFiles,
                                             &vastray::oiio::readImageChannels,
                                             &vastray::oiio::writeRgba8Png,
                                             &vastray::oiio::readStoredImage,
                                             &vastray::oiio::writeStoredImage,
                                             &vastray::oiio::readRgba8Image,
                                             &vastray::oiio::decodeRgba8Image};
    return &api;
}
