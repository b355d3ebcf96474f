#include "import/AlphaMask.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <tuple>

#include "import/GltfTextures.h"
#include "import/PngWriter.h"
#include "vastray/core/Texture.h"

namespace vastray::import {
namespace {

uint32_t bigEndian32(const uint8_t* p) { return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | p[3]; }

// The scalar of one texel, 0..255.
float channelOf(const uint8_t* texel, MaskChannel channel) {
    switch (channel) {
        case MaskChannel::Red: return texel[0];
        case MaskChannel::Green: return texel[1];
        case MaskChannel::Blue: return texel[2];
        case MaskChannel::Luminance: return 0.2126f * texel[0] + 0.7152f * texel[1] + 0.0722f * texel[2];
        case MaskChannel::Auto:
        case MaskChannel::Alpha: break;
    }
    return texel[3];
}

// The two texels a bilinear filter at x reads (x in texels, centres at integers) and the
// second one's weight.
struct Taps {
    uint32_t a, b;
    double weight;
};
Taps tapsAt(double x, uint32_t size, TextureWrap wrap) {
    const double lower = std::floor(x);
    const double weight = x - lower;
    const int64_t i = int64_t(lower);
    const int64_t n = size;
    if (wrap == TextureWrap::Repeat) return {uint32_t(((i % n) + n) % n), uint32_t((((i + 1) % n) + n) % n), weight};
    if (x <= 0.0) return {0, 0, 0.0};
    if (x >= double(n - 1)) return {uint32_t(n - 1), uint32_t(n - 1), 0.0};
    return {uint32_t(i), uint32_t(i + 1), weight};
}

// The mask's scalars resampled at the centres of a width x height image's texels.
std::vector<float> resampledMask(const Rgba8Image& mask, MaskChannel channel, uint32_t width, uint32_t height,
                                 TextureWrap wrapS, TextureWrap wrapT) {
    std::vector<float> scalars(size_t(mask.width) * mask.height);
    for (size_t t = 0; t < scalars.size(); ++t) scalars[t] = channelOf(&mask.texels[4 * t], channel);
    if (mask.width == width && mask.height == height) return scalars;
    std::vector<Taps> columns(width);
    for (uint32_t x = 0; x < width; ++x)
        columns[x] = tapsAt((x + 0.5) * mask.width / width - 0.5, mask.width, wrapS);
    std::vector<float> out(size_t(width) * height);
    for (uint32_t y = 0; y < height; ++y) {
        const Taps row = tapsAt((y + 0.5) * mask.height / height - 0.5, mask.height, wrapT);
        const float* r0 = &scalars[size_t(row.a) * mask.width];
        const float* r1 = &scalars[size_t(row.b) * mask.width];
        for (uint32_t x = 0; x < width; ++x) {
            const Taps& c = columns[x];
            const double top = r0[c.a] + c.weight * (r0[c.b] - r0[c.a]);
            const double bottom = r1[c.a] + c.weight * (r1[c.b] - r1[c.a]);
            out[size_t(y) * width + x] = float(top + row.weight * (bottom - top));
        }
    }
    return out;
}

// A texture's texels, within the package's texture limits (kMaxTextureSide a side, checked here
// too: a mask baked on white keeps its size, and the limit is better named at its own image).
Result<Rgba8Image> decoded(const TextureSource& source) {
    auto image =
        decodeRgba8Image(source.name, source.extension, source.bytes, uint64_t(kMaxTextureSide) * kMaxTextureSide);
    if (image && (image->width > kMaxTextureSide || image->height > kMaxTextureSide))
        return Status::error(source.name + ": " + std::to_string(image->width) + " x " +
                             std::to_string(image->height) + " texels is outside 1.." +
                             std::to_string(kMaxTextureSide) + " per side");
    return image;
}

// The baked texture of one (base, mask, channel): its PNG bytes as a TextureSource.
Result<TextureSource> bakeTexture(const TextureSource* base, const TextureSource& mask, MaskChannel channel) {
    auto maskImage = decoded(mask);
    if (!maskImage) return maskImage.status();
    Result<Rgba8Image> baseImage = Rgba8Image{};
    if (base) {
        baseImage = decoded(*base);
        if (!baseImage) return baseImage.status();
    }
    const TextureSource& sampling = base ? *base : mask;
    Rgba8Image baked = bakeAlpha(base ? &*baseImage : nullptr, *maskImage, channel, sampling.wrapS, sampling.wrapT);
    auto png = encodePng(baked.width, baked.height, 4, baked.texels);
    if (!png) return png.status();
    TextureSource out;
    out.name = (base ? base->name : std::string("white")) + " with the alpha of " + mask.name;
    out.extension = ".png";
    out.bytes = std::move(*png);
    out.wrapS = sampling.wrapS, out.wrapT = sampling.wrapT;
    out.encoding = TextureEncoding::Srgb;
    return out;
}

// Drops the textures no material's map reads, renumbering the maps.
void dropUnreadTextures(TriangleMesh& mesh) {
    std::vector<uint32_t> renumbered(mesh.textures.size(), kNoTexture);
    for (const Material& m : mesh.materials)
        for (const TextureBinding& b : m.textures.slots)
            if (b.texture != kNoTexture) renumbered[b.texture] = 0;
    uint32_t kept = 0;
    for (uint32_t t = 0; t < mesh.textures.size(); ++t) {
        if (renumbered[t] == kNoTexture) continue;
        renumbered[t] = kept;
        if (kept != t) mesh.textures[kept] = std::move(mesh.textures[t]);
        ++kept;
    }
    mesh.textures.resize(kept);
    for (Material& m : mesh.materials)
        for (TextureBinding& b : m.textures.slots)
            if (b.texture != kNoTexture) b.texture = renumbered[b.texture];
}

}  // namespace

bool imageHasAlpha(const std::vector<uint8_t>& bytes) {
    static constexpr uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
    if (bytes.size() < 33 || std::memcmp(bytes.data(), kSignature, 8) != 0) return false;
    const uint8_t colourType = bytes[25];  // IHDR's: after the signature, length, type, width, height, depth
    if (colourType == 4 || colourType == 6) return true;
    for (size_t at = 8; at + 8 <= bytes.size();) {
        const uint32_t length = bigEndian32(&bytes[at]);
        const char* type = reinterpret_cast<const char*>(&bytes[at + 4]);
        if (std::memcmp(type, "tRNS", 4) == 0) return true;
        if (std::memcmp(type, "IDAT", 4) == 0 || std::memcmp(type, "IEND", 4) == 0) return false;
        at += 12 + uint64_t(length);
    }
    return false;
}

MaskChannel resolveMaskChannel(MaskChannel channel, const std::vector<uint8_t>& bytes) {
    if (channel != MaskChannel::Auto) return channel;
    return imageHasAlpha(bytes) ? MaskChannel::Alpha : MaskChannel::Luminance;
}

Rgba8Image bakeAlpha(const Rgba8Image* base, const Rgba8Image& mask, MaskChannel channel, TextureWrap wrapS,
                     TextureWrap wrapT) {
    Rgba8Image out;
    if (base) {
        out = *base;
    } else {
        out.width = mask.width, out.height = mask.height;
        out.texels.assign(size_t(mask.width) * mask.height * 4, 255);
    }
    const std::vector<float> scalars = resampledMask(mask, channel, out.width, out.height, wrapS, wrapT);
    for (size_t t = 0; t < scalars.size(); ++t) {
        uint8_t& alpha = out.texels[4 * t + 3];
        alpha = uint8_t(std::lround(std::clamp(double(alpha) * scalars[t] / 255.0, 0.0, 255.0)));
    }
    return out;
}

Status bakeAlphaMasks(TriangleMesh& mesh, const std::vector<AlphaMaskRequest>& requests) {
    if (requests.empty()) return Status::ok();
    std::map<std::tuple<uint32_t, uint32_t, MaskChannel>, uint32_t> bakedOf;
    for (const AlphaMaskRequest& request : requests) {
        Material& material = mesh.materials[request.material];
        TextureBinding& binding = material.textures.slots[uint32_t(TextureSlot::BaseColor)];
        const MaskChannel channel = resolveMaskChannel(request.channel, mesh.textures[request.mask].bytes);
        // MTL has no cutoff, assimp's opacity neither: glTF's default (a glTF MASK's own is kept).
        const float cutoff = material.alphaCutoff > 0.0f ? material.alphaCutoff : 0.5f;
        if (request.sameImageAsBase && channel == MaskChannel::Alpha && binding.texture != kNoTexture) {
            material.alphaCutoff = cutoff;
            continue;
        }
        const auto key = std::make_tuple(binding.texture, request.mask, channel);
        auto found = bakedOf.find(key);
        if (found == bakedOf.end()) {
            const TextureSource* base = binding.texture == kNoTexture ? nullptr : &mesh.textures[binding.texture];
            auto baked = bakeTexture(base, mesh.textures[request.mask], channel);
            if (!baked) return baked.status().withContext("material '" + material.name + "' alpha mask: ");
            if (mesh.textures.size() >= kMaxSceneTextures)
                return Status::error("material '" + material.name + "' alpha mask: more than " +
                                     std::to_string(kMaxSceneTextures) + " textures in one scene");
            found = bakedOf.emplace(key, uint32_t(mesh.textures.size())).first;
            mesh.textures.push_back(std::move(*baked));
        }
        if (binding.texture == kNoTexture) binding.transform = request.transform;
        binding.texture = found->second;
        material.alphaCutoff = cutoff;
    }
    dropUnreadTextures(mesh);
    return Status::ok();
}

}  // namespace vastray::import
