#include "OiioImage.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "vastray/core/FilePath.h"
#include "vastray/core/ImageFile.h"
#include "vastray/core/RenderOptions.h"

namespace vastray::oiio {
namespace {


Status writeWith(const std::string& path, const OIIO::ImageSpec& spec, OIIO::TypeDesc format,
                 const void* pixels) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) return Status::error(path + ": cannot write: " + OIIO::geterror());
    if (!out->open(path, spec)) return Status::error(path + ": " + out->geterror());
    if (!out->write_image(format, pixels)) return Status::error(path + ": " + out->geterror());
    if (!out->close()) return Status::error(path + ": " + out->geterror());
    return Status::ok();
}

OIIO::ImageSpec rgba8PngSpec(uint32_t width, uint32_t height) {
    OIIO::ImageSpec spec(int(width), int(height), 4, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:ColorSpace", "sRGB");
    // The colours are the displayed ones, not multiplied by alpha: without this OIIO divided
    // them by alpha (PNG stores unassociated alpha), so partly covered edge pixels came out
    // too bright, often clipped to 255.
    spec.attribute("oiio:UnassociatedAlpha", 1);
    return spec;
}

Status writePng(const std::string& path, const RenderImage& image) {
    if (image.aovs != kAovNone)
        return Status::error(path + ": AOVs need an .exr output (PNG holds the beauty only)");
    std::vector<uint8_t> pixels(image.pixelCount() * 4);
    for (uint64_t i = 0; i < image.pixelCount(); ++i) {
        for (int c = 0; c < 3; ++c)
            pixels[4 * i + c] = uint8_t(std::lround(255.0f * toneMapToDisplay(image.rgb[3 * i + c])));
        pixels[4 * i + 3] = uint8_t(std::lround(255.0f * std::clamp(image.alpha[i], 0.0f, 1.0f)));
    }
    OIIO::ImageSpec spec = rgba8PngSpec(image.width, image.height);
    setRegion(spec, true, image.originX, image.originY, image.frameWidth, image.frameHeight);
    return writeWith(path, spec, OIIO::TypeDesc::UINT8, pixels.data());
}

// One pixel record matching the EXR channel list: floats, then the uint32 channels (primid, chunkid).
struct ChannelLayout {
    std::vector<std::string> names;
    size_t floatCount = 0;
    size_t uintCount = 0;
};

ChannelLayout exrLayout(uint32_t aovs) {
    ChannelLayout layout{{"R", "G", "B", "A"}};
    if (aovs & kAovDepth) layout.names.push_back("Z");
    if (aovs & kAovNormal) layout.names.insert(layout.names.end(), {"N.x", "N.y", "N.z"});
    if (aovs & kAovAlbedo) layout.names.insert(layout.names.end(), {"albedo.R", "albedo.G", "albedo.B"});
    if (aovs & kAovCost) layout.names.insert(layout.names.end(), {"cost.cells", "cost.triangles"});
    if (aovs & kAovUv) layout.names.insert(layout.names.end(), {"uv.u", "uv.v"});
    layout.floatCount = layout.names.size();
    if (aovs & kAovPrimId) layout.names.push_back("primid");
    if (aovs & kAovChunkId) layout.names.push_back("chunkid");
    layout.uintCount = layout.names.size() - layout.floatCount;
    return layout;
}

std::vector<uint8_t> packExrPixels(const RenderImage& image, const ChannelLayout& layout) {
    const size_t stride = (layout.floatCount + layout.uintCount) * 4;
    std::vector<uint8_t> bytes(image.pixelCount() * stride);
    for (uint64_t i = 0; i < image.pixelCount(); ++i) {
        std::vector<float> f{image.rgb[3 * i], image.rgb[3 * i + 1], image.rgb[3 * i + 2], image.alpha[i]};
        if (image.aovs & kAovDepth) f.push_back(image.depth[i]);
        if (image.aovs & kAovNormal) f.insert(f.end(), &image.normal[3 * i], &image.normal[3 * i] + 3);
        if (image.aovs & kAovAlbedo) f.insert(f.end(), &image.albedo[3 * i], &image.albedo[3 * i] + 3);
        if (image.aovs & kAovCost) f.insert(f.end(), &image.cost[2 * i], &image.cost[2 * i] + 2);
        if (image.aovs & kAovUv) f.insert(f.end(), &image.uv[2 * i], &image.uv[2 * i] + 2);
        uint8_t* at = bytes.data() + i * stride;
        std::memcpy(at, f.data(), f.size() * 4);
        at += f.size() * 4;
        if (image.aovs & kAovPrimId) std::memcpy(at, &image.primId[i], 4), at += 4;
        if (image.aovs & kAovChunkId) std::memcpy(at, &image.chunkId[i], 4);
    }
    return bytes;
}

Status writeExr(const std::string& path, const RenderImage& image) {
    const ChannelLayout layout = exrLayout(image.aovs);
    OIIO::ImageSpec spec(int(image.width), int(image.height), int(layout.names.size()),
                         OIIO::TypeDesc::FLOAT);
    spec.channelnames = layout.names;
    spec.alpha_channel = 3;
    if (image.aovs & kAovDepth) spec.z_channel = 4;
    if (layout.uintCount > 0) {
        spec.channelformats.assign(layout.names.size(), OIIO::TypeDesc::FLOAT);
        for (size_t c = layout.floatCount; c < layout.names.size(); ++c)
            spec.channelformats[c] = OIIO::TypeDesc::UINT32;
    }
    spec.attribute("compression", "zip");
    setRegion(spec, false, image.originX, image.originY, image.frameWidth, image.frameHeight);
    if (image.hasCamera) {  // OpenEXR's worldToCamera and worldToNDC (OIIO's names for them)
        spec.attribute("worldtocamera", OIIO::TypeMatrix44, image.worldToCamera.data());
        spec.attribute("worldtoscreen", OIIO::TypeMatrix44, image.worldToNdc.data());
    }
    const std::vector<uint8_t> bytes = packExrPixels(image, layout);
    // With per-channel formats, UNKNOWN means "the data is in the file's native formats".
    return writeWith(path, spec, layout.uintCount > 0 ? OIIO::TypeDesc::UNKNOWN : OIIO::TypeDesc::FLOAT,
                     bytes.data());
}

}  // namespace

void setRegion(OIIO::ImageSpec& spec, bool png, uint32_t originX, uint32_t originY, uint32_t frameWidth,
               uint32_t frameHeight) {
    const bool whole = originX == 0 && originY == 0 && frameWidth == uint32_t(spec.width) &&
                       frameHeight == uint32_t(spec.height);
    if (whole) return;
    if (png) {
        spec.attribute(kRegionTextKey, std::to_string(originX) + "," + std::to_string(originY) + "," +
                                           std::to_string(originX + spec.width) + "," +
                                           std::to_string(originY + spec.height) + " " +
                                           std::to_string(frameWidth) + "x" + std::to_string(frameHeight));
        return;
    }
    spec.x = int(originX), spec.y = int(originY);
    spec.full_x = 0, spec.full_y = 0;
    spec.full_width = int(frameWidth), spec.full_height = int(frameHeight);
}

Status writeRgba8Png(const std::string& path, uint32_t width, uint32_t height,
                     const std::vector<uint8_t>& rgba) {
    if (rgba.size() != uint64_t(width) * height * 4)
        return Status::error(path + ": " + std::to_string(rgba.size()) + " bytes are not " +
                             std::to_string(width) + "x" + std::to_string(height) + " RGBA pixels");
    return writeWith(path, rgba8PngSpec(width, height), OIIO::TypeDesc::UINT8, rgba.data());
}

Status writeImageFile(const std::string& path, const RenderImage& image) {
    const std::string ext = lowerExtension(path);
    if (ext == ".png") return writePng(path, image);
    if (ext == ".exr") return writeExr(path, image);
    return Status::error(path + ": unsupported image format '" + ext + "' (expected .png or .exr)");
}

}  // namespace vastray::oiio
