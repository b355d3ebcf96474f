#include "vastray/core/Texture.h"

#include <algorithm>
#include <cmath>

namespace vastray {

const char* textureWrapName(TextureWrap wrap) {
    switch (wrap) {
        case TextureWrap::Repeat: return "repeat";
        case TextureWrap::Clamp: return "clamp";
        case TextureWrap::Mirror: return "mirror";
    }
    return "unknown";
}

Result<TextureLayout> makeTextureLayout(uint32_t width, uint32_t height) {
    if (width == 0 || height == 0 || width > kMaxTextureSide || height > kMaxTextureSide)
        return Status::error("a texture of " + std::to_string(width) + "x" + std::to_string(height) +
                             " texels is outside 1.." + std::to_string(kMaxTextureSide) + " per side");
    TextureLayout layout;
    layout.width = width;
    layout.height = height;
    uint32_t w = width, h = height;
    for (;;) {
        TextureLevel& level = layout.levels[layout.levelCount++];
        level.width = w;
        level.height = h;
        level.pagesX = (w + kTexturePageTexels - 1) / kTexturePageTexels;
        level.pagesY = (h + kTexturePageTexels - 1) / kTexturePageTexels;
        level.firstPage = layout.pageCount;
        layout.pageCount += level.pagesX * level.pagesY;
        if (w == 1 && h == 1) break;
        w = std::max(1u, w / 2);
        h = std::max(1u, h / 2);
    }
    return layout;
}

uint32_t storedTexelIndex(uint32_t index, uint32_t size, TextureWrap wrap) {
    if (index < size) return index;
    return wrap == TextureWrap::Repeat ? index % size : size - 1;
}

namespace {

// u mapped by the wrap mode, then to the upper-left texel of the footprint and its weight.
void footprintAxis(float u, uint32_t size, TextureWrap wrap, uint32_t& texel, float& weight) {
    if (!std::isfinite(u)) u = 0.0f;
    const float n = float(size);
    if (wrap == TextureWrap::Repeat) {
        const float x = (u - std::floor(u)) * n - 0.5f;  // in [-0.5, size - 0.5]
        const float x0 = std::floor(x);
        weight = x - x0;
        texel = x0 < 0.0f ? size - 1 : std::min(uint32_t(x0), size - 1);
        return;
    }
    if (wrap == TextureWrap::Mirror) {
        const float t = u - 2.0f * std::floor(0.5f * u);  // in [0, 2]
        u = t > 1.0f ? 2.0f - t : t;
    }
    const float x = std::clamp(std::clamp(u, 0.0f, 1.0f) * n - 0.5f, 0.0f, n - 1.0f);
    const float x0 = std::floor(x);
    texel = std::min(uint32_t(x0), size - 1);
    weight = x - float(texel);
}

struct SrgbTable {
    std::array<float, 256> values{};
    SrgbTable() {
        for (uint32_t i = 0; i < 256; ++i) {
            const double c = double(i) / 255.0;
            values[i] = float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
        }
    }
};

TextureSample bilinear(const TextureLayout& layout, uint32_t level, TextureWrap wrapS, TextureWrap wrapT,
                       TextureEncoding encoding, const TexturePageFetch& fetch, float u, float v) {
    const TextureFootprint f = textureFootprint(layout, level, wrapS, wrapT, u, v);
    const uint8_t* page = fetch(f.page);
    const float weights[4] = {(1.0f - f.fx) * (1.0f - f.fy), f.fx * (1.0f - f.fy), (1.0f - f.fx) * f.fy,
                              f.fx * f.fy};
    TextureSample s;
    for (uint32_t corner = 0; corner < 4; ++corner) {
        const uint32_t x = f.localX + (corner & 1), y = f.localY + (corner >> 1);
        const uint8_t* texel = page + (size_t(y) * kTexturePageSide + x) * 4;
        float rgb[3];
        for (int c = 0; c < 3; ++c)
            rgb[c] = encoding == TextureEncoding::Srgb ? srgb8ToLinear(texel[c]) : float(texel[c]) / 255.0f;
        s.r += weights[corner] * rgb[0];
        s.g += weights[corner] * rgb[1];
        s.b += weights[corner] * rgb[2];
        s.a += weights[corner] * (float(texel[3]) / 255.0f);
    }
    return s;
}

}  // namespace

TextureFootprint textureFootprint(const TextureLayout& layout, uint32_t level, TextureWrap wrapS,
                                  TextureWrap wrapT, float u, float v) {
    const TextureLevel& l = layout.levels[level];
    uint32_t x = 0, y = 0;
    TextureFootprint f;
    footprintAxis(u, l.width, wrapS, x, f.fx);
    footprintAxis(v, l.height, wrapT, y, f.fy);
    f.page = l.firstPage + (y / kTexturePageTexels) * l.pagesX + x / kTexturePageTexels;
    f.localX = x % kTexturePageTexels;
    f.localY = y % kTexturePageTexels;
    return f;
}

float srgb8ToLinear(uint8_t value) {
    static const SrgbTable table;
    return table.values[value];
}

float textureLod(float texelArea, float worldArea, float coneWidth, float cosTheta) {
    const float c = std::fabs(cosTheta);
    if (!(texelArea > 0.0f) || !(worldArea > 0.0f) || !(coneWidth > 0.0f) || !(c > 1e-6f)) return 0.0f;
    const float lod = 0.5f * std::log2(texelArea / worldArea) + std::log2(coneWidth / c);
    return std::isfinite(lod) ? lod : 0.0f;
}

TextureSample sampleTexture(const TextureLayout& layout, TextureWrap wrapS, TextureWrap wrapT,
                            TextureEncoding encoding, const TexturePageFetch& fetch, float u, float v, float lod) {
    const float top = float(layout.levelCount - 1);
    lod = std::isfinite(lod) ? std::clamp(lod, 0.0f, top) : 0.0f;
    const uint32_t l0 = uint32_t(lod);
    const float t = lod - float(l0);
    TextureSample a = bilinear(layout, l0, wrapS, wrapT, encoding, fetch, u, v);
    if (t <= 0.0f || l0 + 1 >= layout.levelCount) return a;
    const TextureSample b = bilinear(layout, l0 + 1, wrapS, wrapT, encoding, fetch, u, v);
    a.r += t * (b.r - a.r);
    a.g += t * (b.g - a.g);
    a.b += t * (b.b - a.b);
    a.a += t * (b.a - a.a);
    return a;
}

TextureSample sampleTexture(const DecodedTexture& t, float u, float v, float lod) {
    return sampleTexture(t.layout, t.wrapS, t.wrapT, t.encoding,
                         [&t](uint32_t page) { return t.pages.data() + size_t(page) * kTexturePageBytes; }, u, v, lod);
}

}  // namespace vastray
