#pragma once
// A rendered frame in memory: linear beauty plus the AOVs every backend produces.
// Row-major, row 0 at the top.
#include <cstdint>
#include <limits>
#include <vector>

namespace vastray {

constexpr uint32_t kMissPrimId = 0xFFFFFFFFu;

struct RenderImage {
    uint32_t width = 0, height = 0;
    uint32_t aovs = 0;             // AovFlags present besides the beauty
    std::vector<float> rgb;        // 3 per pixel, linear radiance (sample mean)
    std::vector<float> alpha;      // fraction of samples whose camera ray hit geometry
    std::vector<float> depth;      // distance eye..hit of the pixel-centre ray; +inf on a miss
    std::vector<float> normal;     // 3 per pixel, unit geometric normal facing the camera; 0 on a miss
    std::vector<float> albedo;     // 3 per pixel, base colour; 0 on a miss
    std::vector<uint32_t> primId;  // triangle index in the imported mesh; kMissPrimId on a miss
    std::vector<uint32_t> chunkId; // chunk whose cell produced the pixel-centre hit; kMissPrimId on a miss
    std::vector<float> cost;       // 2 per pixel: cells traced, triangles tested, over all the pixel's rays

    // Sizes every buffer for width x height (AOV buffers only when requested).
    void allocate(uint32_t w, uint32_t h, uint32_t aovFlags);
    uint64_t pixelCount() const { return uint64_t(width) * height; }
};

}  // namespace vastray
