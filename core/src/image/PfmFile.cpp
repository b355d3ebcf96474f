// Portable float maps, written without the OpenImageIO module: the one image format a program
// can write where that module (and OpenImageIO's ~260 libraries) is absent, e.g. the device
// bundle that times a cold render (docs/PERFORMANCE.md). Three lines of text and raw floats:
// nothing a library would spare us, and the module stays optional.
#include "PfmFile.h"

#include <bit>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

namespace vastray {
namespace {

// The next whitespace-separated token of the header, at most 32 bytes; "" at the end or when longer.
std::string headerToken(FILE* file) {
    int c = std::fgetc(file);
    while (c != EOF && std::isspace(c)) c = std::fgetc(file);
    std::string token;
    while (c != EOF && !std::isspace(c)) {
        if (token.size() == 32) return "";
        token += char(c);
        c = std::fgetc(file);
    }
    return token;  // the one whitespace byte after it is consumed
}

}  // namespace

Result<ImageChannels> readPfmFile(const std::string& path, uint64_t maxPixels) {
    std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!file) return Status::error(path + ": cannot open: " + std::strerror(errno));
    const std::string magic = headerToken(file.get());
    if (magic != "PF" && magic != "Pf") return Status::error(path + ": not a portable float map (no PF or Pf header)");
    const uint32_t channels = magic == "PF" ? 3 : 1;
    const std::string widthText = headerToken(file.get()), heightText = headerToken(file.get()),
                      scaleText = headerToken(file.get());
    auto size = [](const std::string& text) -> uint64_t {
        if (text.empty() || text.size() > 9 || text.find_first_not_of("0123456789") != std::string::npos) return 0;
        return std::stoull(text);
    };
    const uint64_t width = size(widthText), height = size(heightText);
    if (width == 0 || height == 0)
        return Status::error(path + ": the header's size '" + widthText + " " + heightText +
                             "' is not two whole numbers from 1 to 999999999");
    if (width * height > maxPixels)
        return Status::error(path + ": " + std::to_string(width) + "x" + std::to_string(height) +
                             " pixels is more than the " + std::to_string(maxPixels) + " this read accepts");
    char* end = nullptr;
    const float scale = scaleText.empty() ? 0.0f : std::strtof(scaleText.c_str(), &end);
    if (scaleText.empty() || *end != '\0' || !std::isfinite(scale) || scale == 0.0f)
        return Status::error(path + ": the header's scale '" + scaleText + "' is not a finite, non-zero number");
    const bool swap = (scale < 0.0f) != (std::endian::native == std::endian::little);
    const uint64_t values = width * height * channels;
    std::vector<float> data(values);
    const uint64_t got = std::fread(data.data(), sizeof(float), values, file.get());
    if (got != values)
        return Status::error(path + ": " + std::to_string(got * 4) + " bytes of pixels where the header says " +
                             std::to_string(values * 4) + " (truncated?)");
    if (std::fgetc(file.get()) != EOF) return Status::error(path + ": bytes after the pixels the header announces");
    const float factor = std::fabs(scale);
    ImageChannels out;
    out.width = uint32_t(width), out.height = uint32_t(height);
    out.planes.assign(3, std::vector<float>(width * height));
    for (uint64_t y = 0; y < height; ++y)
        for (uint64_t x = 0; x < width; ++x)
            for (uint32_t c = 0; c < 3; ++c) {
                float v = data[((height - 1 - y) * width + x) * channels + (channels == 3 ? c : 0)];
                if (swap) v = std::bit_cast<float>(__builtin_bswap32(std::bit_cast<uint32_t>(v)));
                out.planes[c][y * width + x] = factor == 1.0f ? v : v * factor;
            }
    return out;
}

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
