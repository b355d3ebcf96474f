#include "OiioImage.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <vector>
#include <cmath>
#include <limits>

namespace vastray::oiio {
namespace {

struct OpenedImage {
    std::unique_ptr<OIIO::ImageInput> input;
    OIIO::ImageSpec spec;
};

Result<OpenedImage> openImage(const std::string& path) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // PNG: the stored colours, not multiplied by alpha
    auto input = OIIO::ImageInput::open(path, &config);
    if (!input) return Status::error(path + ": cannot read: " + OIIO::geterror());
    OIIO::ImageSpec spec = input->spec();
    return OpenedImage{std::move(input), std::move(spec)};
}

int channelIndex(const OIIO::ImageSpec& spec, const std::string& name) {
    const auto& names = spec.channelnames;
    const auto it = std::find(names.begin(), names.end(), name);
    return it == names.end() ? -1 : int(it - names.begin());
}

template <typename T>
Result<std::vector<T>> readChannel(OpenedImage& image, const std::string& path, int channel,
                                   OIIO::TypeDesc type) {
    std::vector<T> values(size_t(image.spec.width) * image.spec.height);
    if (!image.input->read_image(0, 0, channel, channel + 1, type, values.data()))
        return Status::error(path + ": " + image.input->geterror());
    return values;
}

Status compareBeauty(const std::string& pathA, const std::string& pathB, int channels,
                     ImageDiffReport& report) {
    OIIO::ImageBuf a(pathA), b(pathB);
    if (!a.read(0, 0, true, OIIO::TypeDesc::FLOAT)) return Status::error(pathA + ": " + a.geterror());
    if (!b.read(0, 0, true, OIIO::TypeDesc::FLOAT)) return Status::error(pathB + ": " + b.geterror());
    OIIO::ROI roi = OIIO::get_roi(a.spec());
    roi.chend = std::min(channels, 3);
    // Thresholds at infinity: we want the statistics, and `error` then means a real failure.
    constexpr float kNoThreshold = std::numeric_limits<float>::infinity();
    const OIIO::ImageBufAlgo::CompareResults r =
        OIIO::ImageBufAlgo::compare(a, b, kNoThreshold, kNoThreshold, roi);
    if (r.error) return Status::error(pathA + " vs " + pathB + ": compare failed: " + OIIO::geterror());
    report.beautyRmse = r.rms_error;
    report.beautyPsnr = r.PSNR;
    report.beautyMaxError = r.maxerror;
    return Status::ok();
}

Status compareDepth(OpenedImage& a, const std::string& pathA, OpenedImage& b, const std::string& pathB,
                    ImageDiffReport& report) {
    auto za = readChannel<float>(a, pathA, channelIndex(a.spec, "Z"), OIIO::TypeDesc::FLOAT);
    if (!za) return za.status();
    auto zb = readChannel<float>(b, pathB, channelIndex(b.spec, "Z"), OIIO::TypeDesc::FLOAT);
    if (!zb) return zb.status();
    double sum = 0;
    uint64_t both = 0;
    for (size_t i = 0; i < za->size(); ++i) {
        const bool hitA = std::isfinite((*za)[i]), hitB = std::isfinite((*zb)[i]);
        if (hitA != hitB) ++report.depthHitMismatch;
        if (!hitA || !hitB) continue;
        const double reference = std::fabs(double((*zb)[i]));
        sum += std::fabs(double((*za)[i]) - (*zb)[i]) / std::max(reference, 1e-30);
        ++both;
    }
    report.hasDepth = true;
    report.depthMeanRelativeError = both ? sum / double(both) : 0.0;
    return Status::ok();
}

Status comparePrimIds(OpenedImage& a, const std::string& pathA, OpenedImage& b, const std::string& pathB,
                      ImageDiffReport& report) {
    auto pa = readChannel<uint32_t>(a, pathA, channelIndex(a.spec, "primid"), OIIO::TypeDesc::UINT32);
    if (!pa) return pa.status();
    auto pb = readChannel<uint32_t>(b, pathB, channelIndex(b.spec, "primid"), OIIO::TypeDesc::UINT32);
    if (!pb) return pb.status();
    uint64_t same = 0;
    for (size_t i = 0; i < pa->size(); ++i) same += (*pa)[i] == (*pb)[i];
    report.hasPrimId = true;
    report.primIdAgreement = pa->empty() ? 1.0 : double(same) / double(pa->size());
    return Status::ok();
}

}  // namespace

Result<ImageDiffReport> diffImageFiles(const std::string& pathA, const std::string& pathB) {
    auto a = openImage(pathA);
    if (!a) return a.status();
    auto b = openImage(pathB);
    if (!b) return b.status();
    const OIIO::ImageSpec &sa = a->spec, &sb = b->spec;
    if (sa.width != sb.width || sa.height != sb.height)
        return Status::error("sizes differ: " + pathA + " is " + std::to_string(sa.width) + "x" +
                             std::to_string(sa.height) + ", " + pathB + " is " + std::to_string(sb.width) +
                             "x" + std::to_string(sb.height));
    if (sa.channelnames != sb.channelnames) {
        auto join = [](const std::vector<std::string>& names) {
            std::string s;
            for (const std::string& n : names) s += (s.empty() ? "" : ",") + n;
            return s;
        };
        return Status::error("channels differ: " + pathA + " has " + join(sa.channelnames) + ", " + pathB +
                             " has " + join(sb.channelnames));
    }
    ImageDiffReport report;
    report.width = uint32_t(sa.width);
    report.height = uint32_t(sa.height);
    report.channels = sa.channelnames;
    VASTRAY_TRY(compareBeauty(pathA, pathB, sa.nchannels, report));
    if (channelIndex(sa, "Z") >= 0) VASTRAY_TRY(compareDepth(*a, pathA, *b, pathB, report));
    if (channelIndex(sa, "primid") >= 0) VASTRAY_TRY(comparePrimIds(*a, pathA, *b, pathB, report));
    return report;
}

Result<ImageChannels> readImageChannels(const std::string& path, const std::vector<std::string>& names,
                                        uint64_t maxPixels) {
    auto image = openImage(path);
    if (!image) return image.status();
    const uint64_t pixels = uint64_t(std::max(image->spec.width, 0)) * uint64_t(std::max(image->spec.height, 0));
    if (pixels > maxPixels)
        return Status::error(path + ": " + std::to_string(image->spec.width) + "x" +
                             std::to_string(image->spec.height) + " pixels is more than the " +
                             std::to_string(maxPixels) + " this read accepts");
    ImageChannels out;
    out.width = uint32_t(image->spec.width);
    out.height = uint32_t(image->spec.height);
    for (const std::string& name : names) {
        const int channel = channelIndex(image->spec, name);
        std::vector<float>& plane = out.planes.emplace_back();
        if (channel < 0) continue;
        // Read integer ids as integers: OIIO would scale them into 0..1 on a conversion to float.
        if (image->spec.channelformat(channel) == OIIO::TypeDesc::UINT32) {
            auto ids = readChannel<uint32_t>(*image, path, channel, OIIO::TypeDesc::UINT32);
            if (!ids) return ids.status();
            plane.assign(ids->begin(), ids->end());
        } else {
            auto values = readChannel<float>(*image, path, channel, OIIO::TypeDesc::FLOAT);
            if (!values) return values.status();
            plane = std::move(*values);
        }
    }
    return out;
}

}  // namespace vastray::oiio
