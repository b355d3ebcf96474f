// Portable float maps, written without the OpenImageIO module: the one image format a program
// can write where that module (and OpenImageIO's ~260 libraries) is absent, e.g. the device
// bundle that times a cold render (docs/PERFORMANCE.md). Three lines of text and raw floats:
// nothing a library would spare us, and the module stays optional.
#include "PfmFile.h"

#include <bit>
#include <cstdio>
#include <memory>
#include <vector>

namespace vastray {

Status writePfmFile(const std::string& path, const RenderImage& image) {
    if (image.aovs != 0) return Status::error(path + ": a .pfm holds the beauty only; AOVs need an .exr");
    if (image.isRegion())
        return Status::error(path + ": a .pfm cannot record where a region lies in its frame; use .exr or .png");
    const uint64_t pixels = image.pixelCount();
    if (image.rgb.size() != 3 * pixels)
        return Status::error(path + ": " + std::to_string(image.rgb.size()) + " colour values for " +
                             std::to_string(pixels) + " pixels");
    std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "wb"), &std::fclose);
    if (!file) return Status::error(path + ": cannot open for writing");
    // A negative scale says little-endian; rows go bottom to top.
    const float scale = std::endian::native == std::endian::little ? -1.0f : 1.0f;
    bool ok = std::fprintf(file.get(), "PF\n%u %u\n%.1f\n", image.width, image.height, double(scale)) > 0;
    for (uint32_t row = image.height; ok && row-- > 0;)
        ok = std::fwrite(image.rgb.data() + uint64_t(row) * image.width * 3, sizeof(float), uint64_t(image.width) * 3,
                         file.get()) == uint64_t(image.width) * 3;
    // The last buffered bytes go out on close, which can fail too.
    ok = std::fclose(file.release()) == 0 && ok;
    if (!ok) return Status::error(path + ": write failed (disk full?)");
    return Status::ok();
}

}  // namespace vastray
