#pragma once
// PNG bytes in memory for images import makes itself (a base colour map with a mask baked into
// its alpha, AlphaMask.h): 8 bits a sample, 1 to 4 channels (grey, grey + alpha, RGB, RGBA),
// no filter, zlib-deflated row by row, so no second copy of the texels is made.
#include <cstdint>
#include <vector>

#include "vastray/core/Result.h"

namespace vastray::import {

// `texels`: width * height * channels bytes, row 0 at the top.
Result<std::vector<uint8_t>> encodePng(uint32_t width, uint32_t height, uint32_t channels,
                                       const std::vector<uint8_t>& texels);

}  // namespace vastray::import
