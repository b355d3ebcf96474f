#pragma once
// The Vulkan backend of the streaming renderer: a pool of chunk slots and one ray batch, all
// allocated once from the memory budget; stream_trace.comp dispatched per slot batch, and
// stream_walk.comp for whole rays when every chunk has a slot.
#include <cstdint>
#include <memory>
#include <string>

#include "vastray/core/Result.h"
#include "vastray/gpu/VulkanDevice.h"
#include "vastray/streamer/StreamingRenderer.h"

namespace vastray::gpu {

// How a budget is split: every figure is what the device is asked to allocate.
struct PoolPlan {
    uint64_t slotBytes = 0;      // one chunk slot: the largest chunk's upload (ChunkLayout)
    uint32_t slots = 0;          // chunk slots (never more than the package's chunks)
    uint32_t batchRays = 0;      // rays per trace call
    uint64_t rayBytes = 0;       // ray + hit buffers of one batch
    uint64_t tableBytes = 0;     // the slot table and stream_walk.comp's (top-level tree, chunk -> slot, touched)
    uint64_t totalBytes = 0;     // all of the above, <= the budget
    uint64_t minimumBytes = 0;   // one slot + the minimal batch + the tables
};

// The smallest batch a budget must hold besides one chunk slot.
constexpr uint32_t kMinBatchRays = 4096;
// The largest batch worth allocating: beyond it, bigger batches do not trace faster.
constexpr uint32_t kMaxBatchRays = 1u << 20;

// Splits `budget` between slots and the ray batch; an error (naming the minimum) when the
// budget cannot hold one slot plus a minimal batch.
Result<PoolPlan> planPool(const PackageInfo& package, const ChunkAttributes& attributes, uint64_t budget);

// device must outlive the backend. Every buffer is allocated here, once.
Result<std::unique_ptr<ChunkBackend>> createVulkanChunkBackend(VulkanDevice& device, const PackageInfo& package,
                                                               const ChunkAttributes& attributes, uint64_t budget);

}  // namespace vastray::gpu
