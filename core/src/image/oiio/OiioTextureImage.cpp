// readRgba8Image and decodeRgba8Image (vastray/core/ImageFile.h) through OpenImageIO.
#include <OpenImageIO/filesystem.h>

#include "OiioImage.h"

namespace vastray::oiio {
namespace {

Result<Rgba8Image> readOpened(OIIO::ImageInput& input, const std::string& name, uint64_t maxPixels) {
    const OIIO::ImageSpec& spec = input.spec();
    const uint64_t pixels = uint64_t(std::max(spec.width, 0)) * uint64_t(std::max(spec.height, 0));
    if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1)
        return Status::error(name + ": an image of " + std::to_string(spec.width) + "x" +
                             std::to_string(spec.height) + "x" + std::to_string(spec.depth) +
                             " pixels is not a 2D texture");
    if (pixels > maxPixels)
        return Status::error(name + ": " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                             " pixels is more than the " + std::to_string(maxPixels) + " a texture may have");
    if (spec.nchannels < 1 || spec.nchannels > 4)
        return Status::error(name + ": " + std::to_string(spec.nchannels) +
                             " channels; a texture has 1 (grey), 2 (grey, alpha), 3 (RGB) or 4 (RGBA)");
    const int channels = spec.nchannels;
    std::vector<uint8_t> stored(pixels * uint64_t(channels));
    if (!input.read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, stored.data()))
        return Status::error(name + ": " + input.geterror());
    Rgba8Image image;
    image.width = uint32_t(spec.width);
    image.height = uint32_t(spec.height);
    image.texels.resize(pixels * 4);
    for (uint64_t i = 0; i < pixels; ++i) {
        const uint8_t* s = stored.data() + i * uint64_t(channels);
        uint8_t* d = image.texels.data() + i * 4;
        const bool grey = channels <= 2;
        d[0] = s[0];
        d[1] = grey ? s[0] : s[1];
        d[2] = grey ? s[0] : s[2];
        d[3] = channels == 2 ? s[1] : channels == 4 ? s[3] : 255;
    }
    return image;
}

OIIO::ImageSpec textureConfig() {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // the stored colours, not multiplied by alpha
    return config;
}

}  // namespace

Result<Rgba8Image> readRgba8Image(const std::string& path, uint64_t maxPixels) {
    const OIIO::ImageSpec config = textureConfig();
    auto input = OIIO::ImageInput::open(path, &config);
    if (!input) return Status::error(path + ": cannot read: " + OIIO::geterror());
    return readOpened(*input, path, maxPixels);
}

Result<Rgba8Image> decodeRgba8Image(const std::string& name, const std::string& extension,
                                    const std::vector<uint8_t>& bytes, uint64_t maxPixels) {
    if (bytes.empty()) return Status::error(name + ": an empty image");
    OIIO::Filesystem::IOMemReader memory(bytes.data(), bytes.size());
    const OIIO::ImageSpec config = textureConfig();
    // The extension picks the reader; it reads from `memory`, never from a file of that name.
    auto input = OIIO::ImageInput::create("texture" + extension, true, &config, &memory);
    if (!input) return Status::error(name + ": cannot read as a " + extension + " image: " + OIIO::geterror());
    return readOpened(*input, name, maxPixels);
}

}  // namespace vastray::oiio
