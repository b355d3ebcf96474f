// Image files read and written exactly as stored (StoredImage), for `vastray assemble`: no
// conversion of sample types, no association of alpha, the region an image covers kept.
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstring>
#include <cctype>
#include <cstdio>
#include <filesystem>

#include "OiioImage.h"
#include "vastray/core/FilePath.h"

namespace vastray::oiio {
namespace {

bool isPng(const std::string& path) { return lowerExtension(path) == ".png"; }

Result<SampleType> sampleType(const std::string& path, const std::string& channel, OIIO::TypeDesc t) {
    if (t == OIIO::TypeDesc::UINT8) return SampleType::UInt8;
    if (t == OIIO::TypeDesc::UINT16) return SampleType::UInt16;
    if (t == OIIO::TypeDesc::HALF) return SampleType::Half;
    if (t == OIIO::TypeDesc::FLOAT) return SampleType::Float;
    if (t == OIIO::TypeDesc::UINT32) return SampleType::UInt32;
    return Status::error(path + ": channel " + channel + " has sample type " + t.c_str() +
                         " (expected uint8, uint16, half, float or uint32)");
}

OIIO::TypeDesc typeDesc(SampleType t) {
    switch (t) {
        case SampleType::UInt8: return OIIO::TypeDesc::UINT8;
        case SampleType::UInt16: return OIIO::TypeDesc::UINT16;
        case SampleType::Half: return OIIO::TypeDesc::HALF;
        case SampleType::Float: return OIIO::TypeDesc::FLOAT;
        case SampleType::UInt32: return OIIO::TypeDesc::UINT32;
    }
    return OIIO::TypeDesc::UNKNOWN;
}

// The PNG text chunk "X0,Y0,X1,Y1 WxH" (OiioImageFile.cpp's setRegion writes it).
Status parseRegionText(const std::string& path, const std::string& text, StoredImage& image) {
    unsigned x0 = 0, y0 = 0, x1 = 0, y1 = 0, w = 0, h = 0;
    char end = 0;
    if (std::sscanf(text.c_str(), "%u,%u,%u,%u %ux%u%c", &x0, &y0, &x1, &y1, &w, &h, &end) != 6)
        return Status::error(path + ": text chunk " + kRegionTextKey + " '" + text + "': expected X0,Y0,X1,Y1 WxH");
    if (x1 - x0 != image.width || y1 - y0 != image.height || x0 >= x1 || y0 >= y1)
        return Status::error(path + ": text chunk " + kRegionTextKey + " '" + text + "' does not match the " +
                             std::to_string(image.width) + "x" + std::to_string(image.height) + " image");
    image.originX = x0, image.originY = y0, image.frameWidth = w, image.frameHeight = h;
    return Status::ok();
}

// Where the image lies: the EXR data window inside the display window, the PNG text chunk, or the
// whole frame. The region must lie inside the frame.
Status readRegion(const std::string& path, const OIIO::ImageSpec& spec, StoredImage& image) {
    image.originX = 0, image.originY = 0, image.frameWidth = image.width, image.frameHeight = image.height;
    if (isPng(path)) {
        const std::string text = spec.get_string_attribute(kRegionTextKey);
        if (!text.empty()) VASTRAY_TRY(parseRegionText(path, text, image));
    } else {
        const int64_t x = int64_t(spec.x) - spec.full_x, y = int64_t(spec.y) - spec.full_y;
        if (x < 0 || y < 0 || spec.full_width < 1 || spec.full_height < 1)
            return Status::error(path + ": data window starts outside the display window");
        image.originX = uint32_t(x), image.originY = uint32_t(y);
        image.frameWidth = uint32_t(spec.full_width), image.frameHeight = uint32_t(spec.full_height);
    }
    if (uint64_t(image.originX) + image.width > image.frameWidth ||
        uint64_t(image.originY) + image.height > image.frameHeight)
        return Status::error(path + ": its region reaches beyond its " + std::to_string(image.frameWidth) + "x" +
                             std::to_string(image.frameHeight) + " frame");
    return Status::ok();
}

}  // namespace

Result<StoredImage> readStoredImage(const std::string& path) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // PNG: the stored colours, not multiplied by alpha
    auto input = OIIO::ImageInput::open(path, &config);
    if (!input) return Status::error(path + ": cannot read: " + OIIO::geterror());
    const OIIO::ImageSpec& spec = input->spec();
    if (spec.depth > 1 || spec.width < 1 || spec.height < 1 || spec.nchannels < 1)
        return Status::error(path + ": not a 2D image with pixels");
    StoredImage image;
    image.width = uint32_t(spec.width), image.height = uint32_t(spec.height);
    VASTRAY_TRY(readRegion(path, spec, image));
    const OIIO::ParamValue* toCamera = spec.find_attribute("worldtocamera", OIIO::TypeMatrix44);
    const OIIO::ParamValue* toNdc = spec.find_attribute("worldtoscreen", OIIO::TypeMatrix44);
    if (toCamera && toNdc) {
        std::memcpy(image.worldToCamera.data(), toCamera->data(), 64);
        std::memcpy(image.worldToNdc.data(), toNdc->data(), 64);
        image.hasCamera = true;
    }
    for (int c = 0; c < spec.nchannels; ++c) {
        image.channels.push_back(spec.channel_name(c));
        auto type = sampleType(path, image.channels.back(), spec.channelformat(c));
        if (!type) return type.status();
        image.types.push_back(*type);
    }
    image.pixels.resize(uint64_t(image.width) * image.height * image.pixelBytes());
    // UNKNOWN: every channel in the file's own type.
    if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UNKNOWN, image.pixels.data()))
        return Status::error(path + ": " + input->geterror());
    return image;
}

Status writeStoredImage(const std::string& path, const StoredImage& image) {
    if (image.types.size() != image.channels.size() || image.channels.empty() ||
        image.pixels.size() != uint64_t(image.width) * image.height * image.pixelBytes())
        return Status::error(path + ": inconsistent image to write");
    const bool png = isPng(path);
    OIIO::ImageSpec spec(int(image.width), int(image.height), int(image.channels.size()), typeDesc(image.types[0]));
    spec.channelnames = image.channels;
    const bool mixed = std::any_of(image.types.begin(), image.types.end(),
                                   [&](SampleType t) { return t != image.types[0]; });
    if (mixed)
        for (SampleType t : image.types) spec.channelformats.push_back(typeDesc(t));
    const auto at = [&](const char* name) {
        const auto it = std::find(image.channels.begin(), image.channels.end(), name);
        return it == image.channels.end() ? -1 : int(it - image.channels.begin());
    };
    spec.alpha_channel = at("A");
    spec.z_channel = at("Z");
    if (png) {
        spec.attribute("oiio:ColorSpace", "sRGB");
        spec.attribute("oiio:UnassociatedAlpha", 1);  // the stored colours as they are
    } else {
        spec.attribute("compression", "zip");
        if (image.hasCamera) {
            spec.attribute("worldtocamera", OIIO::TypeMatrix44, image.worldToCamera.data());
            spec.attribute("worldtoscreen", OIIO::TypeMatrix44, image.worldToNdc.data());
        }
    }
    setRegion(spec, png, image.originX, image.originY, image.frameWidth, image.frameHeight);
    auto out = OIIO::ImageOutput::create(path);
    if (!out) return Status::error(path + ": cannot write: " + OIIO::geterror());
    if (!out->open(path, spec)) return Status::error(path + ": " + out->geterror());
    if (!out->write_image(mixed ? OIIO::TypeDesc::UNKNOWN : typeDesc(image.types[0]), image.pixels.data()))
        return Status::error(path + ": " + out->geterror());
    if (!out->close()) return Status::error(path + ": " + out->geterror());
    return Status::ok();
}

}  // namespace vastray::oiio
