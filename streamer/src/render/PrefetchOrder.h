#pragma once
// The order in which a cold out-of-core render queues a scene's chunks for decoding.
#include <cstdint>
#include <vector>

#include "vastray/core/Camera.h"
#include "vastray/core/RenderOptions.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {

// The first row of the region `bounds` (frame pixels, rows growing downwards) that the box
// `cell` may cover on the `frameWidth` x `frameHeight` image of `rays` (made for that size): its
// corners projected, a corner at or behind the eye's plane putting the box at row 0 (it may then
// cover any row); `bounds.height()` where the box lies wholly behind the eye or outside the region.
uint32_t firstRowSeen(const Aabb& cell, const CameraRays& rays, const PixelBounds& bounds, uint32_t frameWidth,
                      uint32_t frameHeight);

// Every chunk of `package`, in the order the device wavefront's streamed tiles (rows of the
// region, top first: Wavefront.cpp's TileGrid) first see them: by the band of rows (a sixteenth
// of the region's height) holding the first row its cell may cover, within a band nearer the
// eye first, chunks outside the view last (nearer first); the id breaks ties (PERF_NOTES 104).
std::vector<uint32_t> prefetchOrder(const PackageInfo& package, const Camera& camera, const PixelBounds& bounds,
                                    uint32_t frameWidth, uint32_t frameHeight);

}  // namespace vastray
