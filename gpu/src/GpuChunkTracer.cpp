#include "vastray/gpu/GpuChunkTracer.h"

#include "ChunkValidation.h"

#include <algorithm>
#include <string>

namespace vastray::gpu {
namespace {

const uint32_t kTraceSpirv[] =
#include "trace.spv.inc"
    ;

static_assert(kTraceStackSize == kMaxKdDepth, "trace.comp's stack must hold the deepest tree");
static_assert(sizeof(KdNode) == 2 * sizeof(uint32_t), "trace.comp reads a node as two words");

// Largest x group count every device supports (maxComputeWorkGroupCount[0] >= 65535).
constexpr uint64_t kMaxRaysPerDispatch = 65535ull * kTraceWorkgroupSize;

Result<GpuBuffer> uploadArray(VulkanDevice& device, const void* data, uint64_t bytes) {
    auto buffer = device.createBuffer(bytes);
    if (!buffer) return buffer.status();
    VASTRAY_TRY(buffer->upload(data, bytes));
    return std::move(buffer).value();
}

// Out-of-range references would read outside the buffers on the device: reject them here.
Status validate(const ChunkArrays& c) {
    if (!c.kdTree) return Status::error("chunk has no KD-tree");
    if (!c.singleSided.empty() && c.singleSided.size() != c.indices.size() / 3)
        return Status::error("singleSided has " + std::to_string(c.singleSided.size()) + " entries for " +
                             std::to_string(c.indices.size() / 3) + " triangles");
    return validateChunkGeometry(*c.kdTree, c.positions.size(), c.indices);
}

// Four per-triangle bytes to a word, as trace.comp reads them.
std::vector<uint32_t> packBytes(std::span<const uint8_t> bytes) {
    std::vector<uint32_t> words((bytes.size() + 3) / 4, 0u);
    for (size_t i = 0; i < bytes.size(); ++i) words[i / 4] |= uint32_t(bytes[i]) << (8 * (i % 4));
    return words;
}

}  // namespace

Result<std::unique_ptr<GpuChunkTracer>> GpuChunkTracer::create(VulkanDevice& device) {
    std::unique_ptr<GpuChunkTracer> tracer(new GpuChunkTracer(device));
    auto pipeline = ComputePipeline::create(device, kTraceSpirv, sizeof(TracePushConstants));
    if (!pipeline) return pipeline.status();
    tracer->pipeline_ = std::move(pipeline).value();
    return tracer;
}

Status GpuChunkTracer::upload(const ChunkArrays& chunk) {
    VASTRAY_TRY(validate(chunk));
    // Free the previous chunk first so that the peak never holds two chunks.
    for (GpuBuffer* b : {&nodes_, &leafRefs_, &positions_, &indices_, &singleSided_}) *b = GpuBuffer();
    const KdTree& tree = *chunk.kdTree;
    const std::vector<uint32_t> packed = packBytes(chunk.singleSided);
    auto nodes = uploadArray(device_, tree.nodes.data(), tree.nodes.size() * sizeof(KdNode));
    if (!nodes) return nodes.status();
    auto refs = uploadArray(device_, tree.leafRefs.data(), tree.leafRefs.size() * sizeof(uint32_t));
    if (!refs) return refs.status();
    auto positions = uploadArray(device_, chunk.positions.data(), chunk.positions.size_bytes());
    if (!positions) return positions.status();
    auto indices = uploadArray(device_, chunk.indices.data(), chunk.indices.size_bytes());
    if (!indices) return indices.status();
    auto singleSided = uploadArray(device_, packed.data(), packed.size() * sizeof(uint32_t));
    if (!singleSided) return singleSided.status();
    nodes_ = std::move(nodes).value(), leafRefs_ = std::move(refs).value();
    positions_ = std::move(positions).value(), indices_ = std::move(indices).value();
    singleSided_ = std::move(singleSided).value();
    chunk_ = TracePushConstants{};
    chunk_.nodes = nodes_.address(), chunk_.leafRefs = leafRefs_.address();
    chunk_.positions = positions_.address(), chunk_.indices = indices_.address();
    chunk_.singleSided = singleSided_.address();
    chunk_.nodeCount = uint32_t(tree.nodes.size());
    chunk_.hasSingleSided = chunk.singleSided.empty() ? 0u : 1u;
    chunk_.boundsLoX = tree.bounds.lo.x, chunk_.boundsLoY = tree.bounds.lo.y, chunk_.boundsLoZ = tree.bounds.lo.z;
    chunk_.boundsHiX = tree.bounds.hi.x, chunk_.boundsHiY = tree.bounds.hi.y, chunk_.boundsHiZ = tree.bounds.hi.z;
    return Status::ok();
}

uint64_t GpuChunkTracer::residentChunkBytes() const {
    return nodes_.allocatedBytes() + leafRefs_.allocatedBytes() + positions_.allocatedBytes() +
           indices_.allocatedBytes() + singleSided_.allocatedBytes();
}

Status GpuChunkTracer::reserveRays(uint64_t count) {
    if (count <= rayCapacity_) return Status::ok();
    rays_ = GpuBuffer(), hits_ = GpuBuffer();
    rayCapacity_ = 0;
    auto rays = device_.createBuffer(count * sizeof(TraceRay));
    if (!rays) return rays.status();
    auto hits = device_.createBuffer(count * sizeof(TraceHit), VulkanDevice::MemoryUse::Readback);
    if (!hits) return hits.status();
    rays_ = std::move(rays).value(), hits_ = std::move(hits).value();
    rayCapacity_ = count;
    return Status::ok();
}

// One dispatch per kMaxRaysPerDispatch rays; each gets its slice through the base addresses.
Status GpuChunkTracer::dispatch(uint64_t rayCount) {
    return device_.submit([&](VkCommandBuffer cmd) {
        for (uint64_t first = 0; first < rayCount; first += kMaxRaysPerDispatch) {
            TracePushConstants pc = chunk_;
            const uint64_t count = std::min(kMaxRaysPerDispatch, rayCount - first);
            pc.rays = rays_.address() + first * sizeof(TraceRay);
            pc.hits = hits_.address() + first * sizeof(TraceHit);
            pc.rayCount = uint32_t(count);
            pipeline_->record(cmd, &pc, uint32_t((count + kTraceWorkgroupSize - 1) / kTraceWorkgroupSize));
        }
    });
}

Result<std::vector<TraceHit>> GpuChunkTracer::trace(std::span<const TraceRay> rays) {
    if (!nodes_.isValid()) return Status::error("trace: no chunk uploaded");
    std::vector<TraceHit> hits(rays.size());
    if (rays.empty()) return hits;
    VASTRAY_TRY(reserveRays(rays.size()));
    VASTRAY_TRY(rays_.upload(rays.data(), rays.size_bytes()));
    VASTRAY_TRY(dispatch(rays.size()));
    VASTRAY_TRY(hits_.download(hits.data(), hits.size() * sizeof(TraceHit)));
    return hits;
}

}  // namespace vastray::gpu
