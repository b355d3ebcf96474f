#pragma once
// A rendered frame, or a region of one, in memory: linear beauty plus the AOVs every backend
// produces. Row-major, row 0 at the top.
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

namespace vastray {

constexpr uint32_t kMissPrimId = 0xFFFFFFFFu;

struct RenderImage {
    uint32_t width = 0, height = 0;
    // Where the image lies in the frame it is part of: its pixel (0, 0) is the frame's pixel
    // (originX, originY). allocate() makes it the whole frame (origin 0, frame = its size).
    uint32_t originX = 0, originY = 0, frameWidth = 0, frameHeight = 0;
    uint32_t aovs = 0;             // AovFlags present besides the beauty
    std::vector<float> rgb;        // 3 per pixel, linear radiance (sample mean)
    std::vector<float> alpha;      // fraction of samples whose camera ray hit geometry
    std::vector<float> depth;      // distance eye..hit of the pixel-centre ray; +inf on a miss
    std::vector<float> normal;     // 3 per pixel, unit geometric normal facing the camera; 0 on a miss
    std::vector<float> albedo;     // 3 per pixel, base colour; 0 on a miss
    std::vector<uint32_t> primId;  // triangle index in the imported mesh; kMissPrimId on a miss
    std::vector<uint32_t> chunkId; // chunk whose cell produced the pixel-centre hit; kMissPrimId on a miss
    std::vector<float> cost;       // 2 per pixel: cells traced, triangles tested, over all the pixel's rays
    std::vector<float> uv;         // 2 per pixel, the pixel-centre hit's texture coordinates; 0 on a miss
                                   // or where the scene has none
    // The camera that rendered the frame (recordCamera, Camera.h), written into an EXR header as
    // OpenEXR's standard worldToCamera and worldToNDC: row vectors, p' = [x y z 1] * M, M row by
    // row. Camera space is left-handed (x right, y up, z the view direction, origin at the eye);
    // NDC (0, 0) and (1, 1) are the display window's top-left and bottom-right corners.
    bool hasCamera = false;
    std::array<float, 16> worldToCamera{}, worldToNdc{};

    // Sizes every buffer for width x height (AOV buffers only when requested).
    void allocate(uint32_t w, uint32_t h, uint32_t aovFlags);
    uint64_t pixelCount() const { return uint64_t(width) * height; }
    // Makes the image the region `x0, y0` .. `x0 + width, y0 + height` of a frameW x frameH frame.
    void placeInFrame(uint32_t x0, uint32_t y0, uint32_t frameW, uint32_t frameH);
    bool isRegion() const { return originX != 0 || originY != 0 || frameWidth != width || frameHeight != height; }
};

}  // namespace vastray
