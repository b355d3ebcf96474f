#pragma once
// The CPU reference renderer: the whole scene in one Embree BVH, tiles rendered in
// parallel with TBB. Every pixel depends only on its own random keys, so the image is
// bit-identical whatever the thread count or tile order.
#include <cstdint>
#include <functional>

#include "vastray/core/RenderImage.h"
#include "vastray/core/RenderOptions.h"
#include "vastray/core/RenderStats.h"
#include "vastray/core/Result.h"
#include "vastray/cpu/RenderScene.h"

namespace vastray {

// Called after each finished tile, from worker threads, with (tiles done, tiles total).
using RenderProgress = std::function<void(uint64_t done, uint64_t total)>;

Result<RenderImage> renderWithEmbree(const RenderScene& scene, const RenderOptions& options,
                                     RenderStats* stats = nullptr, const RenderProgress& progress = {});

}  // namespace vastray
