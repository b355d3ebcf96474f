#include "vastray/gpu/VulkanChunkBackend.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <vector>

#include "ChunkValidation.h"
#include "shared/StreamTypes.h"
#include "vastray/core/ByteSize.h"
#include "shared/TraceTypes.h"
#include "vastray/gpu/ComputePipeline.h"

namespace vastray::gpu {
namespace {

const uint32_t kStreamTraceSpirv[] =
#include "stream_trace.spv.inc"
    ;
const uint32_t kStreamWalkSpirv[] =
#include "stream_walk.spv.inc"
    ;

static_assert(sizeof(StreamRayGpu) == sizeof(StreamRay) && sizeof(StreamHitGpu) == sizeof(StreamHit));
static_assert(kHitFound == kStreamHitFound && kHitFrontFacing == kStreamHitFrontFacing);
static_assert(kTraceStackSize == kMaxKdDepth, "the kernel's stack must hold the deepest tree");
static_assert(sizeof(StreamWalkGpu) == sizeof(StreamResult) && offsetof(StreamWalkGpu, chunk) == offsetof(StreamResult, chunk) &&
              offsetof(StreamWalkGpu, cell) == offsetof(StreamResult, cell));
static_assert(kWalkIncomplete == ChunkBackend::kWalkIncomplete && kWalkNoHit == kMissPrimId &&
              kWalkNoHit == kEmptyCell);

// Devices round allocations up (to 64 KiB at most on the devices we know); planning with that
// granularity keeps the allocated total under the budget.
constexpr uint64_t kAllocationGranule = 64 * 1024;
constexpr uint64_t kRayBytes = sizeof(StreamRayGpu) + sizeof(StreamHitGpu);
// Largest x group count every device supports (maxComputeWorkGroupCount[0] >= 65535).
constexpr uint64_t kMaxRaysPerDispatch = 65535ull * kTraceWorkgroupSize;

// Copies to or from a mapped buffer in 256 KiB pieces on all cores: one core writing through a
// write-combined mapping manages a few GB/s, well below what PCIe takes (most arrays of a
// 4 MiB chunk are under 1 MiB, so larger pieces left them to one core).
template <typename Copy>
Status copyInPieces(uint64_t size, Copy&& copy) {
    constexpr uint64_t kPiece = 256 << 10;
    const uint64_t pieces = (size + kPiece - 1) / kPiece;
    if (pieces <= 1) return size == 0 ? Status::ok() : copy(0, size);
    std::atomic<bool> failed{false};
    tbb::parallel_for(uint64_t(0), pieces, [&](uint64_t i) {
        const uint64_t at = i * kPiece;
        if (!copy(at, std::min(kPiece, size - at))) failed = true;
    });
    return failed ? Status::error("copy to or from the device failed") : Status::ok();
}

uint64_t granules(uint64_t bytes) { return (std::max<uint64_t>(bytes, 1) + kAllocationGranule - 1) / kAllocationGranule * kAllocationGranule; }
uint64_t batchBytes(uint64_t rays) { return granules(rays * sizeof(StreamRayGpu)) + granules(rays * sizeof(StreamHitGpu)); }
// One buffer holds the tables: the slot table, then stream_walk.comp's top-level tree, chunk ->
// slot map and touched flags (byte offsets, 16-byte aligned). For most scenes they fit the one
// allocation granule the slot table alone would take.
struct TableLayout {
    uint64_t topNodes, chunkSlots, touched, totalBytes;
};
TableLayout tableLayout(uint64_t slots, const PackageInfo& package) {
    auto align = [](uint64_t bytes) { return (bytes + 15) / 16 * 16; };
    TableLayout t{};
    t.topNodes = align(slots * sizeof(ChunkSlot));
    t.chunkSlots = t.topNodes + align(package.topTree.size() * sizeof(KdNode));
    t.touched = t.chunkSlots + align(package.chunks.size() * 4);
    t.totalBytes = t.touched + align(package.chunks.size() * 4);
    return t;
}

class VulkanChunkBackend final : public ChunkBackend {
public:
    VulkanChunkBackend(VulkanDevice& device, const PackageInfo& package, const PoolPlan& plan,
                       const ChunkAttributes& attributes)
        : device_(device), plan_(plan), attributes_(attributes), tables_(tableLayout(plan.slots, package)),
          bounds_(package.bounds),
          topNodeCount_(uint32_t(package.topTree.size())), chunkCount_(uint32_t(package.chunks.size())) {}

    Status init(const PackageInfo& package) {
        auto pipeline = ComputePipeline::create(device_, kStreamTraceSpirv, sizeof(StreamPushConstants));
        if (!pipeline) return pipeline.status();
        pipeline_ = std::move(pipeline).value();
        auto walkPipeline = ComputePipeline::create(device_, kStreamWalkSpirv, sizeof(StreamWalkPushConstants));
        if (!walkPipeline) return walkPipeline.status();
        walkPipeline_ = std::move(walkPipeline).value();
        for (uint32_t s = 0; s < plan_.slots; ++s) {
            auto slot = device_.createBuffer(plan_.slotBytes);
            if (!slot) return slot.status().withContext("chunk slot " + std::to_string(s) + ": ");
            slots_.push_back(std::move(slot).value());
        }
        auto table = device_.createBuffer(tables_.totalBytes);
        if (!table) return table.status();
        table_ = std::move(table).value();
        if (topNodeCount_ > 0)
            VASTRAY_TRY(table_.upload(package.topTree.data(), topNodeCount_ * sizeof(KdNode), tables_.topNodes));
        auto rays = device_.createBuffer(uint64_t(plan_.batchRays) * sizeof(StreamRayGpu));
        if (!rays) return rays.status();
        rays_ = std::move(rays).value();
        auto hits = device_.createBuffer(uint64_t(plan_.batchRays) * sizeof(StreamHitGpu),
                                         VulkanDevice::MemoryUse::Readback);
        if (!hits) return hits.status();
        hits_ = std::move(hits).value();
        allocated_ = table_.allocatedBytes() + rays_.allocatedBytes() + hits_.allocatedBytes();
        for (const GpuBuffer& b : slots_) allocated_ += b.allocatedBytes();
        const std::vector<ChunkSlot> empty(plan_.slots, ChunkSlot{});
        return table_.upload(empty.data(), empty.size() * sizeof(ChunkSlot));
    }

    std::string name() const override { return "vulkan"; }
    uint32_t slotCount() const override { return plan_.slots; }
    uint32_t maxBatchRays() const override { return plan_.batchRays; }
    uint64_t bytesUploaded() const override { return uploaded_; }
    uint64_t peakDeviceBytes() const override { return allocated_; }  // everything is allocated up front
    double uploadSeconds() const override { return uploadSeconds_; }
    double deviceSeconds() const override { return deviceSeconds_; }

    Status load(uint32_t slot, const DecodedChunk& chunk, std::span<const uint8_t> singleSided) override {
        if (slot >= slots_.size()) return Status::error("slot " + std::to_string(slot) + " does not exist");
        const auto start = std::chrono::steady_clock::now();
        const KdTree& tree = chunk.kdTree;
        const uint64_t triangles = chunk.indices.size() / 3;
        // Constant time for the package reader's chunks (DecodedChunk::validated); a pass over
        // the arrays only for hand-made ones.
        VASTRAY_TRY(validate(chunk, singleSided).withContext("chunk " + std::to_string(chunk.id) + ": "));
        const ChunkLayout layout =
            chunkLayout(tree.nodes.size(), tree.leafRefs.size(), chunk.positions.size(), triangles, attributes_);
        if (layout.totalBytes > plan_.slotBytes)
            return Status::error("chunk " + std::to_string(chunk.id) + " needs " + std::to_string(layout.totalBytes) +
                                 " bytes, more than a slot's " + std::to_string(plan_.slotBytes) +
                                 " (the package directory understates it: damaged package?)");
        GpuBuffer& b = slots_[slot];
        uint64_t bytes = 0;
        auto put = [&](uint64_t offset, const void* data, uint64_t size) -> Status {
            bytes += size;
            return copyInPieces(size, [&](uint64_t at, uint64_t n) {
                return b.upload(static_cast<const uint8_t*>(data) + at, n, offset + at);
            });
        };
        VASTRAY_TRY(put(layout.nodes, tree.nodes.data(), tree.nodes.size() * sizeof(KdNode)));
        VASTRAY_TRY(put(layout.leafRefs, tree.leafRefs.data(), tree.leafRefs.size() * 4));
        VASTRAY_TRY(put(layout.positions, chunk.positions.data(), chunk.positions.size() * 12));
        VASTRAY_TRY(put(layout.indices, chunk.indices.data(), chunk.indices.size() * 4));
        ChunkSlot entry{};
        const uint64_t base = b.address();
        entry.nodes = base + layout.nodes, entry.leafRefs = base + layout.leafRefs;
        entry.positions = base + layout.positions, entry.indices = base + layout.indices;
        if (attributes_.singleSided) {
            // One byte per triangle, read four to a word: the bytes in order, zero padded.
            std::vector<uint8_t> padded((triangles + 3) / 4 * 4, 0);
            std::copy(singleSided.begin(), singleSided.end(), padded.begin());
            VASTRAY_TRY(put(layout.singleSided, padded.data(), padded.size()));
            entry.singleSided = base + layout.singleSided, entry.flags |= kSlotSingleSided;
        }
        if (attributes_.primitiveIds) {
            VASTRAY_TRY(put(layout.primitiveIds, chunk.primitiveIds.data(), triangles * 4));
            entry.primitiveIds = base + layout.primitiveIds, entry.flags |= kSlotPrimitiveIds;
        }
        if (attributes_.materialIds && !chunk.materialIds.empty()) {
            VASTRAY_TRY(put(layout.materialIds, chunk.materialIds.data(), triangles * 4));
            entry.materialIds = base + layout.materialIds, entry.flags |= kSlotMaterialIds;
        }
        entry.nodeCount = uint32_t(tree.nodes.size());
        entry.boundsLoX = tree.bounds.lo.x, entry.boundsLoY = tree.bounds.lo.y, entry.boundsLoZ = tree.bounds.lo.z;
        entry.boundsHiX = tree.bounds.hi.x, entry.boundsHiY = tree.bounds.hi.y, entry.boundsHiZ = tree.bounds.hi.z;
        VASTRAY_TRY(table_.upload(&entry, sizeof(entry), slot * sizeof(ChunkSlot)));
        uploaded_ += bytes + sizeof(entry);
        uploadSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return Status::ok();
    }

    Status trace(std::span<const Batch> batches) override {
        uint64_t total = 0;
        for (const Batch& b : batches) {
            if (b.slot >= slots_.size() || b.rays.size() != b.hits.size())
                return Status::error("trace: bad batch for slot " + std::to_string(b.slot));
            total += b.rays.size();
        }
        if (total > plan_.batchRays)
            return Status::error("trace: " + std::to_string(total) + " rays exceed the batch of " +
                                 std::to_string(plan_.batchRays));
        uint64_t at = 0;
        for (const Batch& b : batches) {
            const auto* src = reinterpret_cast<const uint8_t*>(b.rays.data());
            const uint64_t base = at * sizeof(StreamRayGpu);
            VASTRAY_TRY(copyInPieces(b.rays.size_bytes(),
                                     [&](uint64_t o, uint64_t n) { return rays_.upload(src + o, n, base + o); }));
            at += b.rays.size();
        }
        VASTRAY_TRY(timedSubmit([&](VkCommandBuffer cmd) {
            uint64_t first = 0;
            for (const Batch& b : batches) {
                for (uint64_t done = 0; done < b.rays.size(); done += kMaxRaysPerDispatch) {
                    const uint64_t count = std::min<uint64_t>(kMaxRaysPerDispatch, b.rays.size() - done);
                    StreamPushConstants pc{};
                    pc.slotTable = table_.address();
                    pc.rays = rays_.address() + (first + done) * sizeof(StreamRayGpu);
                    pc.hits = hits_.address() + (first + done) * sizeof(StreamHitGpu);
                    pc.slot = b.slot, pc.rayCount = uint32_t(count), pc.anyHit = b.anyHit ? 1u : 0u;
                    pipeline_->record(cmd, &pc, uint32_t((count + kTraceWorkgroupSize - 1) / kTraceWorkgroupSize));
                }
                first += b.rays.size();
            }
        }));
        at = 0;
        for (const Batch& b : batches) {
            auto* dst = reinterpret_cast<uint8_t*>(b.hits.data());
            const uint64_t base = at * sizeof(StreamHitGpu);
            VASTRAY_TRY(copyInPieces(b.hits.size_bytes(),
                                     [&](uint64_t o, uint64_t n) { return hits_.download(dst + o, n, base + o); }));
            at += b.rays.size();
        }
        return Status::ok();
    }

    // The walk writes a 64-byte record per ray into the hit buffer (48 bytes per batch ray).
    uint32_t maxWalkRays() const override {
        return plan_.slots >= chunkCount_ ? uint32_t(uint64_t(plan_.batchRays) * sizeof(StreamHitGpu) /
                                                                sizeof(StreamWalkGpu))
                                                     : 0;
    }

    Status walk(std::span<const StreamRay> rays, bool anyHit, std::span<const uint32_t> chunkSlot,
                std::span<StreamResult> results, std::span<uint8_t> touched) override {
        const size_t chunks = chunkCount_;
        if (rays.size() > maxWalkRays() || results.size() != rays.size() || chunkSlot.size() != chunks ||
            touched.size() != chunks)
            return Status::error("walk: " + std::to_string(rays.size()) + " rays do not fit the walk of " +
                                 std::to_string(maxWalkRays()) + ", or the chunk tables do not match the package");
        for (uint32_t slot : chunkSlot)
            if (slot != kEmptyCell && slot >= slots_.size()) return Status::error("walk: bad slot " + std::to_string(slot));
        if (rays.empty()) return Status::ok();
        VASTRAY_TRY(table_.upload(chunkSlot.data(), chunks * 4, tables_.chunkSlots));
        const std::vector<uint32_t> zeros(chunks, 0);
        VASTRAY_TRY(table_.upload(zeros.data(), chunks * 4, tables_.touched));
        const auto* src = reinterpret_cast<const uint8_t*>(rays.data());
        VASTRAY_TRY(copyInPieces(rays.size_bytes(), [&](uint64_t o, uint64_t n) { return rays_.upload(src + o, n, o); }));
        VASTRAY_TRY(timedSubmit([&](VkCommandBuffer cmd) {
            for (uint64_t done = 0; done < rays.size(); done += kMaxRaysPerDispatch) {
                const uint64_t count = std::min<uint64_t>(kMaxRaysPerDispatch, rays.size() - done);
                StreamWalkPushConstants pc{};
                pc.slotTable = table_.address();
                pc.rays = rays_.address() + done * sizeof(StreamRayGpu);
                pc.results = hits_.address() + done * sizeof(StreamWalkGpu);
                pc.topNodes = table_.address() + tables_.topNodes;
                pc.chunkSlots = table_.address() + tables_.chunkSlots, pc.touched = table_.address() + tables_.touched;
                pc.rayCount = uint32_t(count), pc.anyHit = anyHit ? 1u : 0u;
                pc.topNodeCount = topNodeCount_, pc.chunkCount = chunkCount_;
                pc.boundsLoX = bounds_.lo.x, pc.boundsLoY = bounds_.lo.y, pc.boundsLoZ = bounds_.lo.z;
                pc.boundsHiX = bounds_.hi.x, pc.boundsHiY = bounds_.hi.y, pc.boundsHiZ = bounds_.hi.z;
                walkPipeline_->record(cmd, &pc, uint32_t((count + kTraceWorkgroupSize - 1) / kTraceWorkgroupSize));
            }
        }));
        auto* dst = reinterpret_cast<uint8_t*>(results.data());
        VASTRAY_TRY(copyInPieces(results.size_bytes(), [&](uint64_t o, uint64_t n) { return hits_.download(dst + o, n, o); }));
        std::vector<uint32_t> flags(chunks);
        VASTRAY_TRY(table_.download(flags.data(), chunks * 4, tables_.touched));
        for (size_t c = 0; c < chunks; ++c)
            if (flags[c]) touched[c] = 1;
        return Status::ok();
    }

private:
    template <typename Record>
    Status timedSubmit(Record&& record) {
        const auto start = std::chrono::steady_clock::now();
        Status status = device_.submit(record);
        deviceSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return status;
    }

    // Out-of-range references would read outside the slot on the device: reject them here.
    Status validate(const DecodedChunk& c, std::span<const uint8_t> singleSided) const {
        const KdTree& t = c.kdTree;
        const uint64_t triangles = c.indices.size() / 3;
        if (attributes_.singleSided && singleSided.size() != triangles)
            return Status::error("single-sided flags do not match the triangle count");
        if (attributes_.primitiveIds && c.primitiveIds.size() != triangles)
            return Status::error("primitive ids do not match the triangle count");
        if (attributes_.materialIds && !c.materialIds.empty() && c.materialIds.size() != triangles)
            return Status::error("material ids do not match the triangle count");
        // A chunk from the package reader has had the same checks on the decode worker
        // (ChunkBlob.cpp), off the load path; only hand-made chunks are checked here.
        return c.validated ? Status::ok() : validateChunkGeometry(t, c.positions.size(), c.indices);
    }

    VulkanDevice& device_;
    PoolPlan plan_;
    ChunkAttributes attributes_;
    TableLayout tables_;  // in table_
    Aabb bounds_;         // the package's: the top-level tree's bounds
    uint32_t topNodeCount_, chunkCount_;
    std::unique_ptr<ComputePipeline> pipeline_, walkPipeline_;
    std::vector<GpuBuffer> slots_;
    GpuBuffer table_, rays_, hits_;
    uint64_t allocated_ = 0, uploaded_ = 0;
    double uploadSeconds_ = 0, deviceSeconds_ = 0;
};

}  // namespace

Result<PoolPlan> planPool(const PackageInfo& package, const ChunkAttributes& attributes, uint64_t budget) {
    PoolPlan plan;
    uint64_t largest = 0;
    for (const ChunkInfo& c : package.chunks) largest = std::max(largest, chunkLayout(c, attributes).totalBytes);
    plan.slotBytes = largest;
    const uint64_t slotAllocation = granules(largest);
    const uint32_t chunks = uint32_t(std::max<size_t>(package.chunks.size(), 1));
    auto tableBytes = [&](uint64_t slots) { return granules(tableLayout(slots, package).totalBytes); };
    plan.minimumBytes = slotAllocation + batchBytes(kMinBatchRays) + tableBytes(1);
    if (budget < plan.minimumBytes)
        return Status::error("--memory-budget " + formatBytes(budget) + " is below this scene's minimum of " +
                             formatBytes(plan.minimumBytes) + " = " + std::to_string(plan.minimumBytes) +
                             " bytes (one chunk slot of " + formatBytes(slotAllocation) + " plus a batch of " +
                             std::to_string(kMinBatchRays) + " rays of " + formatBytes(batchBytes(kMinBatchRays)) +
                             " plus tables of " + formatBytes(tableBytes(1)) + ")");
    // A quarter of the budget for rays (within [kMinBatchRays, kMaxBatchRays]), the rest for slots;
    // slots beyond the chunk count are useless, so what they would take goes back to the rays.
    uint64_t rays = std::clamp<uint64_t>(budget / 4 / kRayBytes, kMinBatchRays, kMaxBatchRays);
    while (rays > kMinBatchRays && batchBytes(rays) + slotAllocation + tableBytes(1) > budget) rays /= 2;
    rays = std::max<uint64_t>(rays, kMinBatchRays);
    const uint64_t available = budget - batchBytes(rays);  // >= one slot and a one-slot table
    uint64_t slots = available >= tableBytes(chunks) + slotAllocation
                         ? (available - tableBytes(chunks)) / slotAllocation
                         : 1;
    slots = std::min<uint64_t>(slots, chunks);
    const uint64_t left = budget - slots * slotAllocation - tableBytes(slots);
    while (rays < kMaxBatchRays && batchBytes(rays * 2) <= left) rays *= 2;
    plan.slots = uint32_t(slots);
    plan.batchRays = uint32_t(rays);
    plan.rayBytes = batchBytes(rays);
    plan.tableBytes = tableBytes(slots);
    plan.totalBytes = slots * slotAllocation + plan.rayBytes + plan.tableBytes;
    return plan;
}

Result<std::unique_ptr<ChunkBackend>> createVulkanChunkBackend(VulkanDevice& device, const PackageInfo& package,
                                                               const ChunkAttributes& attributes, uint64_t budget) {
    auto plan = planPool(package, attributes, budget);
    if (!plan) return plan.status();
    auto backend = std::make_unique<VulkanChunkBackend>(device, package, *plan, attributes);
    VASTRAY_TRY(backend->init(package));
    if (backend->peakDeviceBytes() > budget)
        return Status::error("the device rounded the pool up to " + formatBytes(backend->peakDeviceBytes()) +
                             ", above the budget of " + formatBytes(budget));
    return std::unique_ptr<ChunkBackend>(std::move(backend));
}

}  // namespace vastray::gpu
