#include "vastray/core/RenderImage.h"

#include "vastray/core/RenderOptions.h"

namespace vastray {

void RenderImage::allocate(uint32_t w, uint32_t h, uint32_t aovFlags) {
    width = w;
    height = h;
    originX = originY = 0;
    frameWidth = w;
    frameHeight = h;
    aovs = aovFlags;
    const size_t n = size_t(w) * h;
    rgb.assign(3 * n, 0.0f);
    alpha.assign(n, 0.0f);
    depth.assign((aovFlags & kAovDepth) ? n : 0, std::numeric_limits<float>::infinity());
    normal.assign((aovFlags & kAovNormal) ? 3 * n : 0, 0.0f);
    albedo.assign((aovFlags & kAovAlbedo) ? 3 * n : 0, 0.0f);
    primId.assign((aovFlags & kAovPrimId) ? n : 0, kMissPrimId);
    chunkId.assign((aovFlags & kAovChunkId) ? n : 0, kMissPrimId);
    cost.assign((aovFlags & kAovCost) ? 2 * n : 0, 0.0f);
    uv.assign((aovFlags & kAovUv) ? 2 * n : 0, 0.0f);
}

void RenderImage::placeInFrame(uint32_t x0, uint32_t y0, uint32_t frameW, uint32_t frameH) {
    originX = x0;
    originY = y0;
    frameWidth = frameW;
    frameHeight = frameH;
}

}  // namespace vastray
