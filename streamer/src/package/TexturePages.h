#pragma once
// A texture image made into what the package stores (core/Texture.h describes the layout):
// its mip levels, cut into pages, each page compressed on its own (zstd) so that a render
// reads and decodes only the pages its rays ask for.
#include <cstdint>
#include <string>
#include <vector>

#include "vastray/core/ImageFile.h"
#include "vastray/core/Result.h"
#include "vastray/core/Texture.h"

namespace vastray {

// Every level of an image and every page of them (layout.pageCount * kTexturePageBytes bytes).
using TexturePyramid = DecodedTexture;

// The next level of `level` (each side max(1, floor(side / 2))): every texel the average of the
// part of `level` it covers, each source texel weighted by the area it shares with it (a box
// filter that is exact for odd sides too), averaged in linear space (sRGB decoded, then
// encoded again, rounded); alpha linear.
Rgba8Image downsampleLevel(const Rgba8Image& level, TextureEncoding encoding);

// The pyramid of `image`: errors name its size and the limit (makeTextureLayout).
Result<TexturePyramid> buildTexturePyramid(const Rgba8Image& image, TextureWrap wrapS, TextureWrap wrapT,
                                           TextureEncoding encoding);

// One page (kTexturePageBytes bytes) compressed, and back: decodePage refuses anything but a
// stream that inflates to exactly kTexturePageBytes bytes; its error says what was wrong (the
// caller names the file, the texture and the page).
std::vector<uint8_t> encodeTexturePage(const uint8_t* page);
Status decodeTexturePage(const uint8_t* data, size_t size, uint8_t* page);

}  // namespace vastray
