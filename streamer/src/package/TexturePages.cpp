#include "TexturePages.h"

#include <tbb/parallel_for.h>
#include <zstd.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace vastray {
namespace {

// One destination texel's share of the source texels along one axis.
struct Tap {
    uint32_t first = 0, count = 0;
    float weights[3] = {0.0f, 0.0f, 0.0f};
};

// Destination texel d of `dst` covers source texels [d * src / dst, (d + 1) * src / dst): with
// dst = max(1, floor(src / 2)) that is at most three texels (an odd side), weighted by overlap.
std::vector<Tap> taps(uint32_t src, uint32_t dst) {
    std::vector<Tap> out(dst);
    const double scale = double(src) / double(dst);
    for (uint32_t d = 0; d < dst; ++d) {
        const double lo = d * scale, hi = (d + 1) * scale;
        Tap& t = out[d];
        t.first = uint32_t(std::floor(lo));
        for (uint32_t s = t.first; s < src && double(s) < hi && t.count < 3; ++s) {
            const double overlap = std::min(hi, double(s + 1)) - std::max(lo, double(s));
            t.weights[t.count++] = float(overlap / scale);
        }
    }
    return out;
}

uint8_t encodeChannel(float linear, bool srgb) {
    double c = std::clamp(double(linear), 0.0, 1.0);
    if (srgb) c = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
    return uint8_t(std::lround(std::clamp(c, 0.0, 1.0) * 255.0));
}

float decodeChannel(uint8_t value, bool srgb) { return srgb ? srgb8ToLinear(value) : float(value) / 255.0f; }

}  // namespace

Rgba8Image downsampleLevel(const Rgba8Image& level, TextureEncoding encoding) {
    const bool srgb = encoding == TextureEncoding::Srgb;
    Rgba8Image out;
    out.width = std::max(1u, level.width / 2);
    out.height = std::max(1u, level.height / 2);
    out.texels.resize(size_t(out.width) * out.height * 4);
    const std::vector<Tap> across = taps(level.width, out.width), down = taps(level.height, out.height);
    tbb::parallel_for(uint32_t(0), out.height, [&](uint32_t y) {
        std::vector<float> row(size_t(out.width) * 4, 0.0f);
        const Tap& ty = down[y];
        for (uint32_t k = 0; k < ty.count; ++k) {
            const uint8_t* src = level.texels.data() + size_t(ty.first + k) * level.width * 4;
            for (uint32_t x = 0; x < out.width; ++x) {
                const Tap& tx = across[x];
                for (uint32_t j = 0; j < tx.count; ++j) {
                    const uint8_t* texel = src + size_t(tx.first + j) * 4;
                    const float w = ty.weights[k] * tx.weights[j];
                    for (int c = 0; c < 4; ++c) row[x * 4 + c] += w * decodeChannel(texel[c], srgb && c < 3);
                }
            }
        }
        uint8_t* dst = out.texels.data() + size_t(y) * out.width * 4;
        for (uint32_t i = 0; i < out.width * 4; ++i) dst[i] = encodeChannel(row[i], srgb && (i % 4) < 3);
    });
    return out;
}

Result<TexturePyramid> buildTexturePyramid(const Rgba8Image& image, TextureWrap wrapS, TextureWrap wrapT,
                                           TextureEncoding encoding) {
    auto layout = makeTextureLayout(image.width, image.height);
    if (!layout) return layout.status();
    if (image.texels.size() != size_t(image.width) * image.height * 4)
        return Status::error("a " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                             " texture has " + std::to_string(image.texels.size()) + " bytes of texels, not " +
                             std::to_string(size_t(image.width) * image.height * 4));
    TexturePyramid pyramid;
    pyramid.layout = *layout;
    pyramid.wrapS = wrapS;
    pyramid.wrapT = wrapT;
    pyramid.encoding = encoding;
    pyramid.pages.resize(size_t(layout->pageCount) * kTexturePageBytes);
    Rgba8Image next;
    const Rgba8Image* level = &image;
    for (uint32_t l = 0; l < layout->levelCount; ++l) {
        const TextureLevel& info = layout->levels[l];
        const uint32_t pages = info.pagesX * info.pagesY;
        tbb::parallel_for(uint32_t(0), pages, [&](uint32_t p) {
            const uint32_t px = p % info.pagesX, py = p / info.pagesX;
            uint8_t* page = pyramid.pages.data() + size_t(info.firstPage + p) * kTexturePageBytes;
            for (uint32_t j = 0; j < kTexturePageSide; ++j) {
                const uint32_t y = storedTexelIndex(std::min(py * kTexturePageTexels + j, info.height), info.height, wrapT);
                const uint8_t* src = level->texels.data() + size_t(y) * info.width * 4;
                for (uint32_t i = 0; i < kTexturePageSide; ++i) {
                    const uint32_t x =
                        storedTexelIndex(std::min(px * kTexturePageTexels + i, info.width), info.width, wrapS);
                    std::memcpy(page + (size_t(j) * kTexturePageSide + i) * 4, src + size_t(x) * 4, 4);
                }
            }
        });
        if (l + 1 < layout->levelCount) {
            next = downsampleLevel(*level, encoding);
            level = &next;
        }
    }
    return pyramid;
}

std::vector<uint8_t> encodeTexturePage(const uint8_t* page) {
    std::vector<uint8_t> out(ZSTD_compressBound(kTexturePageBytes));
    const size_t size = ZSTD_compress(out.data(), out.size(), page, kTexturePageBytes, 3);
    // Compressing a buffer of a fixed size into its bound cannot fail.
    out.resize(ZSTD_isError(size) ? 0 : size);
    return out;
}

Status decodeTexturePage(const uint8_t* data, size_t size, uint8_t* page) {
    const unsigned long long content = ZSTD_getFrameContentSize(data, size);
    if (content != kTexturePageBytes)
        return Status::error(content == ZSTD_CONTENTSIZE_ERROR     ? std::string("not a zstd frame")
                             : content == ZSTD_CONTENTSIZE_UNKNOWN ? std::string("a zstd frame of unknown size")
                                                                    : "a zstd frame of " + std::to_string(content) +
                                                                          " bytes, not " +
                                                                          std::to_string(kTexturePageBytes));
    const size_t got = ZSTD_decompress(page, kTexturePageBytes, data, size);
    if (ZSTD_isError(got)) return Status::error(std::string("zstd: ") + ZSTD_getErrorName(got));
    if (got != kTexturePageBytes)
        return Status::error("inflates to " + std::to_string(got) + " bytes, not " + std::to_string(kTexturePageBytes));
    return Status::ok();
}

}  // namespace vastray
