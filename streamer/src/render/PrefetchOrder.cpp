#include "render/PrefetchOrder.h"

#include <algorithm>
#include <tuple>

#include "vastray/core/VecMath.h"

namespace vastray {

uint32_t firstRowSeen(const Aabb& cell, const CameraRays& rays, const PixelBounds& bounds, uint32_t frameWidth,
                      uint32_t frameHeight) {
    const Vec3f f = rays.forward(), u = rays.up(), r = rays.right();
    const float uu = dot(u, u), rr = dot(r, r);
    float lowY = 1e30f, highY = -1e30f, lowX = 1e30f, highX = -1e30f;
    bool behind = false, inFront = false;
    for (int k = 0; k < 8; ++k) {
        const Vec3f corner{(k & 1) ? cell.hi.x : cell.lo.x, (k & 2) ? cell.hi.y : cell.lo.y,
                           (k & 4) ? cell.hi.z : cell.lo.z};
        const Vec3f d = corner - rays.eye();
        const float z = dot(d, f);
        if (!(z > 1e-6f * length(d))) {
            behind = true;
            continue;
        }
        inFront = true;
        // CameraRays::primary's screen coordinates, in [-1, 1] across the frame.
        const float sy = dot(d, u) / (uu * z), sx = dot(d, r) / (rr * z);
        lowY = std::min(lowY, sy), highY = std::max(highY, sy);
        lowX = std::min(lowX, sx), highX = std::max(highX, sx);
    }
    if (!inFront) return bounds.height();
    if (behind) return 0;
    // sy = 1 - 2 (y + jitter) / height: rows grow downwards.
    const float top = (1.0f - highY) * 0.5f * float(frameHeight), bottom = (1.0f - lowY) * 0.5f * float(frameHeight);
    const float left = (lowX + 1.0f) * 0.5f * float(frameWidth), right = (highX + 1.0f) * 0.5f * float(frameWidth);
    if (!(bottom >= float(bounds.y0) && top < float(bounds.y1) && right >= float(bounds.x0) && left < float(bounds.x1)))
        return bounds.height();
    return uint32_t(std::max(top, float(bounds.y0))) - bounds.y0;
}

std::vector<uint32_t> prefetchOrder(const PackageInfo& package, const Camera& camera, const PixelBounds& bounds,
                                    uint32_t frameWidth, uint32_t frameHeight) {
    const CameraRays rays(camera, frameWidth, frameHeight);
    const uint32_t band = std::max(1u, bounds.height() / 16);
    std::vector<std::tuple<uint32_t, float, uint32_t>> keyed;
    keyed.reserve(package.chunks.size());
    for (const ChunkInfo& c : package.chunks) {
        float d2 = 0;  // from the eye to the cell
        for (int a = 0; a < 3; ++a) {
            const float d = std::max({c.cell.lo[a] - camera.eye[a], camera.eye[a] - c.cell.hi[a], 0.0f});
            d2 += d * d;
        }
        const uint32_t row = firstRowSeen(c.cell, rays, bounds, frameWidth, frameHeight);
        keyed.emplace_back(row >= bounds.height() ? UINT32_MAX : row / band, d2, c.id);
    }
    std::sort(keyed.begin(), keyed.end());
    std::vector<uint32_t> order;
    order.reserve(keyed.size());
    for (const auto& [rowBand, d2, id] : keyed) order.push_back(id);
    return order;
}

}  // namespace vastray
