#pragma once
// Traces batches of rays against one chunk resident on the device: the first building block of
// the streaming tracer. Results equal intersectKdTree (core/KdTree.h) bit for bit: same closest
// hit, t, u, v, facing, tie rule and node/triangle counters (see gpu/shaders/trace.comp).
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "shared/TraceTypes.h"
#include "vastray/core/KdTree.h"
#include "vastray/core/Result.h"
#include "vastray/core/Vec3.h"
#include "vastray/gpu/ComputePipeline.h"
#include "vastray/gpu/VulkanDevice.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray::gpu {

// A chunk's arrays as the tracer reads them; nothing is copied until upload.
struct ChunkArrays {
    const KdTree* kdTree = nullptr;
    std::span<const Vec3f> positions;
    std::span<const uint32_t> indices;     // 3 per triangle, into positions
    std::span<const uint8_t> singleSided;  // one per triangle (nonzero: invisible from behind), or empty
};

class GpuChunkTracer {
public:
    // device must outlive the tracer.
    static Result<std::unique_ptr<GpuChunkTracer>> create(VulkanDevice& device);

    // Replaces the resident chunk. Checks that the tree's references and the indices are in range.
    Status upload(const ChunkArrays& chunk);

    // Closest hit of every ray in [ray.tMin, ray.tMax]; hits[i] belongs to rays[i]. Blocks until
    // the device is done. Ray and hit buffers grow to the largest batch seen and are reused.
    Result<std::vector<TraceHit>> trace(std::span<const TraceRay> rays);

    // Device bytes of the resident chunk, and of everything this tracer holds (chunk + ray batch).
    uint64_t residentChunkBytes() const;
    uint64_t deviceBytes() const { return residentChunkBytes() + rays_.allocatedBytes() + hits_.allocatedBytes(); }

private:
    explicit GpuChunkTracer(VulkanDevice& device) : device_(device) {}
    Status reserveRays(uint64_t count);
    Status dispatch(uint64_t rayCount);

    VulkanDevice& device_;
    std::unique_ptr<ComputePipeline> pipeline_;
    GpuBuffer nodes_, leafRefs_, positions_, indices_, singleSided_;
    GpuBuffer rays_, hits_;
    uint64_t rayCapacity_ = 0;
    TracePushConstants chunk_{};  // the chunk's part of the push constants
};

}  // namespace vastray::gpu
