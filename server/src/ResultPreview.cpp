// Result previews: one channel group of a job's image as an 8-bit PNG a browser can show (EXR
// cannot be shown). The mappings are documented in docs/SERVICE.md, "Result previews"; they
// are for looking at, not for measuring (the EXR is the data).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "JobRequest.h"
#include "vastray/core/ImageFile.h"
#include "vastray/server/Service.h"

namespace vastray::server {
namespace {

namespace fs = std::filesystem;
using Rgba = std::vector<uint8_t>;

// A preview holds up to 4 float planes and the RGBA bytes of the whole image in memory (about
// 20 bytes a pixel): at most 4096 x 4096 pixels, ~340 MB, however large a job may render.
constexpr uint64_t kMaxPreviewPixels = 4096ull * 4096ull;

struct PreviewKind {
    const char* name;
    std::vector<std::string> channels;  // EXR channel names (ImageFile.h)
};

const std::vector<PreviewKind>& previewKinds() {
    static const std::vector<PreviewKind> kinds{
        {"beauty", {"R", "G", "B", "A"}},      {"depth", {"Z"}},
        {"normal", {"N.x", "N.y", "N.z"}},     {"albedo", {"albedo.R", "albedo.G", "albedo.B"}},
        {"primid", {"primid"}},                {"chunkid", {"chunkid"}},
        {"cost", {"cost.triangles"}},          {"uv", {"uv.u", "uv.v"}}};
    return kinds;
}

uint8_t toByte(float unit) { return uint8_t(std::lround(255.0f * std::clamp(unit, 0.0f, 1.0f))); }

float srgbEncode(float linear) {
    const float x = std::clamp(linear, 0.0f, 1.0f);
    return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
}

void setPixel(Rgba& out, size_t i, float r, float g, float b, float a = 1.0f) {
    uint8_t* pixel = &out[4 * i];
    pixel[0] = toByte(r), pixel[1] = toByte(g), pixel[2] = toByte(b), pixel[3] = toByte(a);
}

// Beauty from an EXR: the tone mapping of the PNG the CLI writes (toneMapToDisplay), alpha kept.
void mapBeauty(const ImageChannels& in, Rgba& out) {
    const auto& p = in.planes;
    for (size_t i = 0; i < p[0].size(); ++i)
        setPixel(out, i, toneMapToDisplay(p[0][i]), toneMapToDisplay(p[1][i]), toneMapToDisplay(p[2][i]),
                 p[3].empty() ? 1.0f : p[3][i]);
}

// Depth: the nearest hit white, the farthest 20 % grey, linear in distance between; misses black.
void mapDepth(const ImageChannels& in, Rgba& out) {
    const std::vector<float>& z = in.planes[0];
    float nearest = INFINITY, farthest = -INFINITY;
    for (float d : z)
        if (std::isfinite(d)) nearest = std::min(nearest, d), farthest = std::max(farthest, d);
    const float span = farthest > nearest ? farthest - nearest : 1.0f;
    for (size_t i = 0; i < z.size(); ++i) {
        const float v = std::isfinite(z[i]) ? 1.0f - 0.8f * (z[i] - nearest) / span : 0.0f;
        setPixel(out, i, v, v, v);
    }
}

// Normal: each component n in [-1, 1] as (n + 1) / 2; misses (normal 0) black.
void mapNormal(const ImageChannels& in, Rgba& out) {
    const auto& p = in.planes;
    for (size_t i = 0; i < p[0].size(); ++i) {
        const bool miss = p[0][i] == 0.0f && p[1][i] == 0.0f && p[2][i] == 0.0f;
        auto unit = [&](float n) { return miss ? 0.0f : 0.5f * (n + 1.0f); };
        setPixel(out, i, unit(p[0][i]), unit(p[1][i]), unit(p[2][i]));
    }
}

// Albedo: the base colour with the sRGB transfer function and no tone mapping; misses black.
void mapAlbedo(const ImageChannels& in, Rgba& out) {
    const auto& p = in.planes;
    for (size_t i = 0; i < p[0].size(); ++i)
        setPixel(out, i, srgbEncode(p[0][i]), srgbEncode(p[1][i]), srgbEncode(p[2][i]));
}

// Ids are labels, not magnitudes: each id gets its own hue (golden-ratio steps, so neighbouring
// ids differ clearly), full saturation, value 0.9; misses (kMissPrimId) black.
void mapIds(const ImageChannels& in, Rgba& out) {
    const std::vector<float>& ids = in.planes[0];
    const float miss = float(kMissPrimId);
    for (size_t i = 0; i < ids.size(); ++i) {
        if (ids[i] >= miss) {
            setPixel(out, i, 0, 0, 0);
            continue;
        }
        const float hue = std::fmod(double(ids[i]) * 0.6180339887498949, 1.0) * 6.0f;
        auto channel = [&](float offset) {
            const float k = std::fmod(offset + hue, 6.0f);
            return 0.9f * (1.0f - std::clamp(std::min(k, 4.0f - k), 0.0f, 1.0f));
        };
        setPixel(out, i, channel(5.0f), channel(3.0f), channel(1.0f));
    }
}

// UV: the fractional parts of u and v as red and green (a repeating texture's tiles show as
// repeated ramps); misses and scenes without UVs (0, 0) black.
void mapUv(const ImageChannels& in, Rgba& out) {
    const auto& p = in.planes;
    for (size_t i = 0; i < p[0].size(); ++i)
        setPixel(out, i, p[0][i] - std::floor(p[0][i]), p[1][i] - std::floor(p[1][i]), 0.0f);
}

// Cost: triangle tests of the pixel's rays on a log scale, t = log(1 + c) / log(1 + the image's
// largest c), through a heat ramp black -> red -> yellow -> white (thirds of t).
void mapCost(const ImageChannels& in, Rgba& out) {
    const std::vector<float>& cost = in.planes[0];
    const float largest = cost.empty() ? 0.0f : *std::max_element(cost.begin(), cost.end());
    const float scale = largest > 0.0f ? 1.0f / std::log1p(largest) : 0.0f;
    for (size_t i = 0; i < cost.size(); ++i) {
        const float t = std::log1p(std::max(cost[i], 0.0f)) * scale;
        setPixel(out, i, 3.0f * t, 3.0f * t - 1.0f, 3.0f * t - 2.0f);
    }
}

Rgba mapPreview(const std::string& aov, const ImageChannels& in) {
    Rgba out(size_t(in.width) * in.height * 4);
    using Mapping = void (*)(const ImageChannels&, Rgba&);
    static const std::map<std::string, Mapping> mappings{
        {"beauty", mapBeauty}, {"depth", mapDepth}, {"normal", mapNormal}, {"albedo", mapAlbedo},
        {"primid", mapIds},    {"chunkid", mapIds}, {"cost", mapCost},     {"uv", mapUv}};
    mappings.at(aov)(in, out);
    return out;
}

ServiceResult<const PreviewKind*> findPreviewKind(const std::string& aov) {
    std::string names;
    for (const PreviewKind& kind : previewKinds()) {
        if (aov == kind.name) return &kind;
        names += (names.empty() ? "" : ", ") + std::string(kind.name);
    }
    return invalidArgument("aov", "'" + aov + "': expected one of " + names);
}

ServiceResult<std::string> readWhole(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return internalError(path.string() + ": cannot read");
    std::ostringstream bytes;
    bytes << in.rdbuf();
    return bytes.str();
}

}  // namespace

ServiceResult<std::string> Service::resultPreviewPng(const std::string& jobId, const std::string& aov) {
    auto kind = findPreviewKind(aov);
    if (!kind) return kind.status();
    auto file = resultFile(jobId);
    if (!file) return file.status();
    // A PNG result is already the beauty as the CLI writes it.
    if (file->contentType == "image/png" && aov == "beauty") return readWhole(file->path);
    v1::GetJobRequest get;
    get.set_id(jobId);
    auto job = getJob(get);
    if (!job) return job.status();
    const uint64_t pixels = uint64_t(job->request().width()) * job->request().height();
    if (pixels > kMaxPreviewPixels)
        return invalidArgument("aov", "previews are made for images of at most 4096 x 4096 pixels; job " + jobId +
                                          " is " + std::to_string(job->request().width()) + " x " +
                                          std::to_string(job->request().height()) + " (download the file)");
    auto channels = readImageChannels(file->path.string(), (*kind)->channels);
    if (!channels) return internalError(channels.message());
    const auto needed = channels->planes.begin() + (aov == "beauty" ? 3 : 1);  // beauty: alpha may be absent
    const bool present = std::all_of(channels->planes.begin(), needed,
                                     [](const std::vector<float>& plane) { return !plane.empty(); });
    if (!present)
        return invalidArgument("aov", "'" + aov + "': job " + jobId + " was rendered without it " +
                                          "(request it with \"aovs\" when submitting)");
    const fs::path png = objects_->scratchDir() / ("preview-" + randomHex(16) + ".png");
    const Status written =
        writeRgba8Png(png.string(), channels->width, channels->height, mapPreview(aov, *channels));
    auto bytes = written ? readWhole(png) : ServiceResult<std::string>(internalError(written.message()));
    std::error_code error;
    fs::remove(png, error);
    return bytes;
}

}  // namespace vastray::server
