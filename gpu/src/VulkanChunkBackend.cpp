#include "vastray/gpu/VulkanChunkBackend.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <span>
#include <vector>

#include "ChunkValidation.h"
#include "shared/StreamTypes.h"
#include "vastray/core/ByteSize.h"
#include "shared/TraceTypes.h"
#include "PoolLayout.h"
#include "Wavefront.h"

namespace vastray::gpu {
namespace {

static_assert(kTraceStackSize == kMaxKdDepth, "the walk's stack must hold the deepest top-level tree");
static_assert(kBvh4StackSize == 3 * (kBvh4MaxDepth + 1), "the chunk traversal's stack must hold the deepest BVH");
static_assert(kWalkNoHit == kMissPrimId && kWalkNoHit == kEmptyCell);

// Devices round allocations up (to 64 KiB at most on the devices we know); planning with that
// granularity keeps the allocated total under the budget.
constexpr uint64_t kAllocationGranule = 64 * 1024;
// Device bytes of one path of a wave: its state, and at most one tile pixel's sum and outputs
// when those are in device memory.
uint64_t rayBytes(bool outputInDeviceMemory) { return kBytesPerPath + (outputInDeviceMemory ? kBytesPerTilePixel : 0); }

// One array of a chunk to copy into its slot.
struct SlotCopy {
    uint64_t offset;  // in the slot
    const void* data;
    uint64_t size;
};

// Copies a chunk's arrays into a mapped slot in 256 KiB pieces on all cores, all arrays in one
// parallel loop: one core writing through a write-combined mapping manages a few GB/s, well
// below what PCIe takes (most arrays of a 4 MiB chunk are under 1 MiB, so larger pieces left
// them to one core), and a loop per array paid its start and join for each (PERF_NOTES 40).
Status copyToSlot(GpuBuffer& slot, std::span<const SlotCopy> copies) {
    constexpr uint64_t kPiece = 256 << 10;
    struct Piece {
        const SlotCopy* copy;
        uint64_t at, size;
    };
    std::vector<Piece> pieces;
    for (const SlotCopy& c : copies)
        for (uint64_t at = 0; at < c.size; at += kPiece) pieces.push_back({&c, at, std::min(kPiece, c.size - at)});
    auto run = [&](const Piece& p) {
        return p.copy->size == 0 ||
               slot.upload(static_cast<const uint8_t*>(p.copy->data) + p.at, p.size, p.copy->offset + p.at).isOk();
    };
    std::atomic<bool> failed{false};
    if (pieces.size() == 1) failed = !run(pieces[0]);
    else if (pieces.size() > 1)
        tbb::parallel_for(size_t(0), pieces.size(), [&](size_t i) {
            if (!run(pieces[i])) failed = true;
        });
    return failed ? Status::error("copy to the device failed") : Status::ok();
}

uint64_t granules(uint64_t bytes) { return (std::max<uint64_t>(bytes, 1) + kAllocationGranule - 1) / kAllocationGranule * kAllocationGranule; }
// Device bytes of the wavefront's buffers for `paths` paths: device-local state, and the tile
// outputs the host reads when they are in device memory.
uint64_t batchBytes(uint64_t paths, bool outputInDeviceMemory) {
    return granules(stateLayout(paths).totalBytes) + (outputInDeviceMemory ? granules(outputLayout(paths).totalBytes) : 0);
}

class VulkanChunkBackend final : public ChunkBackend {
public:
    VulkanChunkBackend(VulkanDevice& device, const PackageInfo& package, const PoolPlan& plan,
                       const ChunkAttributes& attributes)
        : device_(device), plan_(plan), attributes_(attributes), tables_(tableLayout(plan.slots, package)),
          bounds_(package.bounds),
          topNodeCount_(uint32_t(package.topTree.size())), chunkCount_(uint32_t(package.chunks.size())) {}

    Status init(const PackageInfo& package) {
        auto wavefront = Wavefront::create(device_);
        if (!wavefront) return wavefront.status();
        wavefront_ = std::move(wavefront).value();
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
        auto state = device_.createBuffer(stateLayout(plan_.batchRays).totalBytes);
        if (!state) return state.status();
        state_ = std::move(state).value();
        auto output = device_.createBuffer(outputLayout(plan_.batchRays).totalBytes, VulkanDevice::MemoryUse::Readback);
        if (!output) return output.status();
        output_ = std::move(output).value();
        allocated_ = table_.allocatedBytes() + state_.allocatedBytes() +
                     (plan_.outputInDeviceMemory ? output_.allocatedBytes() : 0);
        for (const GpuBuffer& b : slots_) allocated_ += b.allocatedBytes();
        const std::vector<ChunkSlot> empty(plan_.slots, ChunkSlot{});
        VASTRAY_TRY(table_.upload(empty.data(), empty.size() * sizeof(ChunkSlot)));
        const std::vector<uint32_t> none(chunkCount_, kEmptyCell);
        return table_.upload(none.data(), none.size() * 4, tables_.chunkSlots);
    }

    std::string name() const override { return "vulkan"; }
    uint32_t slotCount() const override { return plan_.slots; }
    uint64_t bytesUploaded() const override { return uploaded_; }
    uint64_t peakDeviceBytes() const override { return allocated_; }  // everything is allocated up front
    double uploadSeconds() const override { return uploadSeconds_; }
    double deviceSeconds() const override { return deviceSeconds_; }

    Status load(uint32_t slot, const DecodedChunk& chunk, std::span<const uint8_t> singleSided) override {
        if (slot >= slots_.size()) return Status::error("slot " + std::to_string(slot) + " does not exist");
        const auto start = std::chrono::steady_clock::now();
        const Bvh4& tree = chunk.bvh;
        const uint64_t triangles = chunk.indices.size() / 3;
        // Constant time for the package reader's chunks (DecodedChunk::validated); a pass over
        // the arrays only for hand-made ones.
        VASTRAY_TRY(validate(chunk, singleSided).withContext("chunk " + std::to_string(chunk.id) + ": "));
        for (const auto* words : {&chunk.normals, &chunk.colors})
            if (!words->empty() && words->size() != chunk.positions.size())
                return Status::error("chunk " + std::to_string(chunk.id) + " has " + std::to_string(words->size()) +
                                     " attribute words for " + std::to_string(chunk.positions.size()) + " vertices");
        const ChunkLayout layout =
            chunkLayout(tree.nodes.size(), chunk.positions.size(), triangles, attributes_);
        if (layout.totalBytes > plan_.slotBytes)
            return Status::error("chunk " + std::to_string(chunk.id) + " needs " + std::to_string(layout.totalBytes) +
                                 " bytes, more than a slot's " + std::to_string(plan_.slotBytes) +
                                 " (the package directory understates it: damaged package?)");
        GpuBuffer& b = slots_[slot];
        uint64_t bytes = 0;
        std::vector<SlotCopy> copies;
        std::vector<uint8_t> padded;
        auto put = [&](uint64_t offset, const void* data, uint64_t size) {
            bytes += size;
            copies.push_back({offset, data, size});
        };
        put(layout.nodes, tree.nodes.data(), tree.nodes.size() * sizeof(Bvh4Node));
        put(layout.positions, chunk.positions.data(), chunk.positions.size() * 12);
        put(layout.indices, chunk.indices.data(), chunk.indices.size() * 4);
        ChunkSlot entry{};
        const uint64_t base = b.address();
        entry.nodes = base + layout.nodes;
        entry.positions = base + layout.positions, entry.indices = base + layout.indices;
        if (attributes_.singleSided) {
            // One byte per triangle, read four to a word: the bytes in order, zero padded.
            padded.assign((triangles + 3) / 4 * 4, 0);
            std::copy(singleSided.begin(), singleSided.end(), padded.begin());
            put(layout.singleSided, padded.data(), padded.size());
            entry.singleSided = base + layout.singleSided, entry.flags |= kSlotSingleSided;
        }
        if (attributes_.primitiveIds) {
            put(layout.primitiveIds, chunk.primitiveIds.data(), triangles * 4);
            entry.primitiveIds = base + layout.primitiveIds, entry.flags |= kSlotPrimitiveIds;
        }
        if (attributes_.materialIds && !chunk.materialIds.empty()) {
            put(layout.materialIds, chunk.materialIds.data(), triangles * 4);
            entry.materialIds = base + layout.materialIds, entry.flags |= kSlotMaterialIds;
        }
        if (attributes_.normals && !chunk.normals.empty()) {
            put(layout.normals, chunk.normals.data(), chunk.normals.size() * 4);
            entry.normals = base + layout.normals, entry.flags |= kSlotNormals;
        }
        if (attributes_.colors && !chunk.colors.empty()) {
            put(layout.colors, chunk.colors.data(), chunk.colors.size() * 4);
            entry.colors = base + layout.colors, entry.flags |= kSlotColors;
        }
        VASTRAY_TRY(copyToSlot(b, copies).withContext("chunk " + std::to_string(chunk.id) + ": "));
        entry.nodeCount = uint32_t(tree.nodes.size());
        entry.boundsLoX = tree.bounds.lo.x, entry.boundsLoY = tree.bounds.lo.y, entry.boundsLoZ = tree.bounds.lo.z;
        entry.boundsHiX = tree.bounds.hi.x, entry.boundsHiY = tree.bounds.hi.y, entry.boundsHiZ = tree.bounds.hi.z;
        VASTRAY_TRY(table_.upload(&entry, sizeof(entry), slot * sizeof(ChunkSlot)));
        uploaded_ += bytes + sizeof(entry);
        uploadSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return Status::ok();
    }

    Status renderOnDevice(const DeviceRenderJob& job, ChunkPager& pager, RenderImage& image,
                          StreamingStats& stats) override {
        WavefrontBuffers b;
        b.table = &table_, b.tables = tables_, b.state = &state_, b.output = &output_;
        b.pathCapacity = job.maxPathsPerWave > 0 ? std::min(plan_.batchRays, job.maxPathsPerWave) : plan_.batchRays;
        b.bounds = bounds_;
        b.topNodeCount = topNodeCount_, b.chunkCount = chunkCount_;
        b.normals = attributes_.normals, b.colors = attributes_.colors;
        return wavefront_->render(b, job, pager, image, stats, deviceSeconds_);
    }

private:
    // Out-of-range references would read outside the slot on the device: reject them here.
    Status validate(const DecodedChunk& c, std::span<const uint8_t> singleSided) const {
        const uint64_t triangles = c.indices.size() / 3;
        if (attributes_.singleSided && singleSided.size() != triangles)
            return Status::error("single-sided flags do not match the triangle count");
        if (attributes_.primitiveIds && c.primitiveIds.size() != triangles)
            return Status::error("primitive ids do not match the triangle count");
        if (attributes_.materialIds && !c.materialIds.empty() && c.materialIds.size() != triangles)
            return Status::error("material ids do not match the triangle count");
        // A chunk from the package reader has had the same checks on the decode worker
        // (ChunkBlob.cpp), off the load path; only hand-made chunks are checked here.
        return c.validated ? Status::ok() : validateChunkGeometry(c.bvh, c.positions.size(), c.indices);
    }

    VulkanDevice& device_;
    PoolPlan plan_;
    ChunkAttributes attributes_;
    TableLayout tables_;  // in table_
    Aabb bounds_;         // the package's: the top-level tree's bounds
    uint32_t topNodeCount_, chunkCount_;
    std::unique_ptr<Wavefront> wavefront_;
    std::vector<GpuBuffer> slots_;
    GpuBuffer table_, state_, output_;
    uint64_t allocated_ = 0, uploaded_ = 0;
    double uploadSeconds_ = 0, deviceSeconds_ = 0;
};

}  // namespace

Result<PoolPlan> planPool(const PackageInfo& package, const ChunkAttributes& attributes, uint64_t budget,
                          bool outputInDeviceMemory, double waveShareOutOfCore) {
    if (!(waveShareOutOfCore > 0 && waveShareOutOfCore < 1))
        return Status::error("the wave's share of an out-of-core budget must be in (0, 1), not " +
                             std::to_string(waveShareOutOfCore));
    PoolPlan plan;
    plan.outputInDeviceMemory = outputInDeviceMemory;
    auto batchBytes = [outputInDeviceMemory](uint64_t paths) { return gpu::batchBytes(paths, outputInDeviceMemory); };
    const uint64_t kRayBytes = rayBytes(outputInDeviceMemory);
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
                             " bytes (one chunk slot of " + formatBytes(slotAllocation) + " plus a wave of " +
                             std::to_string(kMinBatchRays) + " paths of " + formatBytes(batchBytes(kMinBatchRays)) +
                             " plus tables of " + formatBytes(tableBytes(1)) + ")");
    // A quarter of the budget for the wave (within [kMinBatchRays, kMaxBatchRays]), the rest for
    // slots; slots beyond the chunk count are useless, so what they would take goes back to the
    // wave. When the slots cannot hold every chunk, the wave gets waveShareOutOfCore (half by
    // default): every wave pages the scene through the slots again, so out of core fewer, larger
    // waves mean fewer loads, and fewer slots only mean more walk passes per stream (PERF_NOTES 25).
    auto split = [&](double share, uint64_t& rays, uint64_t& slots) {
        rays = std::clamp<uint64_t>(uint64_t(double(budget) * share) / kRayBytes, kMinBatchRays, kMaxBatchRays);
        while (rays > kMinBatchRays && batchBytes(rays) + slotAllocation + tableBytes(1) > budget) rays /= 2;
        rays = std::max<uint64_t>(rays, kMinBatchRays);
        const uint64_t available = budget - batchBytes(rays);  // >= one slot and a one-slot table
        slots = available >= tableBytes(chunks) + slotAllocation ? (available - tableBytes(chunks)) / slotAllocation
                                                                 : 1;
        slots = std::min<uint64_t>(slots, chunks);
    };
    uint64_t rays = 0, slots = 0;
    split(0.25, rays, slots);
    if (slots < chunks) split(waveShareOutOfCore, rays, slots);
    const uint64_t left = budget - slots * slotAllocation - tableBytes(slots);
    while (rays * 2 <= kGrowBatchRays && batchBytes(rays * 2) <= left) rays *= 2;
    plan.slots = uint32_t(slots);
    plan.batchRays = uint32_t(rays);
    plan.rayBytes = batchBytes(rays);
    plan.tableBytes = tableBytes(slots);
    plan.totalBytes = slots * slotAllocation + plan.rayBytes + plan.tableBytes;
    return plan;
}

Result<std::unique_ptr<ChunkBackend>> createVulkanChunkBackend(VulkanDevice& device, const PackageInfo& package,
                                                               const ChunkAttributes& attributes, uint64_t budget,
                                                               double waveShareOutOfCore) {
    auto plan = planPool(package, attributes, budget, device.readbackInDeviceMemory(), waveShareOutOfCore);
    if (!plan) return plan.status();
    auto backend = std::make_unique<VulkanChunkBackend>(device, package, *plan, attributes);
    VASTRAY_TRY(backend->init(package));
    if (backend->peakDeviceBytes() > budget)
        return Status::error("the device rounded the pool up to " + formatBytes(backend->peakDeviceBytes()) +
                             ", above the budget of " + formatBytes(budget));
    return std::unique_ptr<ChunkBackend>(std::move(backend));
}

}  // namespace vastray::gpu
