#pragma once
// Alpha masks on another image than the base colour map's (an MTL map_d, an assimp opacity
// map), baked at import into the base colour map's alpha so that the material is a cut-out
// (Material::alphaCutoff 0.5; docs/RENDERING.md, "Cut-outs"). Both the OBJ and the assimp
// importer call bakeAlphaMasks; the assimp one in its parent process (the image module is not
// loaded in the child).
#include <cstdint>
#include <string>
#include <vector>

#include "vastray/core/ImageFile.h"
#include "vastray/core/Mesh.h"
#include "vastray/core/Result.h"

namespace vastray::import {

// Which scalar of a mask image cuts: MTL -imfchan's r, g, b, m (matte: the alpha) and l
// (luminance: 0.2126 R + 0.7152 G + 0.0722 B of the stored 8-bit values, not decoded from sRGB).
// Auto: the alpha when the image has an alpha channel (imageHasAlpha), else the luminance.
enum class MaskChannel : uint8_t { Auto = 0, Red, Green, Blue, Alpha, Luminance };
constexpr uint8_t kMaskChannelMax = uint8_t(MaskChannel::Luminance);

// Whether encoded image bytes carry alpha: a PNG of colour type 4 or 6 (grey or RGB with alpha)
// or with a tRNS chunk before its pixels; a JPEG never does.
bool imageHasAlpha(const std::vector<uint8_t>& bytes);
MaskChannel resolveMaskChannel(MaskChannel channel, const std::vector<uint8_t>& bytes);

// One material's mask, as an importer found it.
struct AlphaMaskRequest {
    uint32_t material = 0;  // into the mesh's materials
    uint32_t mask = 0;      // into the mesh's textures: the mask image
    MaskChannel channel = MaskChannel::Auto;
    // The mask's UV transform: the base colour binding's when the material has no base colour map
    // (with one, the importer has checked that both maps share their transform and wrap modes).
    UvTransform transform = kIdentityUvTransform;
    // The mask is the base colour map's own image: when its channel is the alpha nothing is baked.
    bool sameImageAsBase = false;
};

// `mask`'s channel multiplied into `base`'s alpha: the result has base's size and RGB; the
// mask is resampled bilinearly at base's texel centres (x = (i + 0.5) mw / bw - 0.5, likewise y),
// its neighbours wrapped (repeat) or clamped to its edge (clamp, mirror) per `wrapS`/`wrapT`, then
// alpha = round(base alpha * mask / 255). Without a base (nullptr): white RGB of the mask's size.
Rgba8Image bakeAlpha(const Rgba8Image* base, const Rgba8Image& mask, MaskChannel channel, TextureWrap wrapS,
                     TextureWrap wrapT);

// For each request: the material's base colour texture (if any) and its mask decoded (within
// kMaxTextureSide² texels each), baked (bakeAlpha) and stored as a new PNG texture (sRGB, the base
// map's wrap modes, else the mask's), which the material's base colour map then reads;
// alphaCutoff becomes 0.5 unless it has one (glTF MASK through assimp). Requests with one base and mask share the result. Textures no map
// reads any more (masks) are dropped. Errors name the material and the image.
Status bakeAlphaMasks(TriangleMesh& mesh, const std::vector<AlphaMaskRequest>& requests);

}  // namespace vastray::import
