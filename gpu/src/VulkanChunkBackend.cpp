#include "vastray/gpu/VulkanChunkBackend.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <span>
#include <vector>

#include "ChunkUploader.h"
#include "ChunkValidation.h"
#include "DeviceTextures.h"
#include "DeviceVolumes.h"
#include "shared/StreamTypes.h"
#include "vastray/core/ByteSize.h"
#include "vastray/core/VolumeLeaf.h"
#include "vastray/core/EnvironmentMap.h"
#include "vastray/core/RenderMemory.h"
#include "vastray/core/Volume.h"
#include "shared/TraceTypes.h"
#include "PoolLayout.h"
#include "Wavefront.h"

namespace vastray::gpu {
namespace {

static_assert(kTraceStackSize == kMaxKdDepth, "the walk's stack must hold the deepest top-level tree");
static_assert(kBvh4StackSize == 3 * (kBvh4MaxDepth + 1), "the chunk traversal's stack must hold the deepest BVH");
static_assert(kWalkNoHit == kMissPrimId && kWalkNoHit == kEmptyCell);

// Device bytes of one path of a wave: its state, and at most one tile pixel's sum and outputs
// when those are in device memory.
// With `uvs` (ChunkAttributes::uvs) a path also keeps its hit's texture coordinates, and with
// tangents too its triangle's UV derivatives.
uint64_t rayBytes(bool outputInDeviceMemory, const ChunkAttributes& a) {
    return kBytesPerPath + (a.uvs ? kBytesPerPathUv : 0) + (a.uvs && a.tangents ? kBytesPerPathFrame : 0) +
           (outputInDeviceMemory ? kBytesPerTilePixel : 0);
}

// Device bytes of the wavefront's buffers for `paths` paths: device-local state, and the tile
// outputs the host reads when they are in device memory.
uint64_t batchBytes(uint64_t paths, bool outputInDeviceMemory, uint64_t counterBytes, const ChunkAttributes& a) {
    return granules(stateLayout(paths, a.uvs, a.tangents).totalBytes) +
           (outputInDeviceMemory ? granules(outputLayout(paths, counterBytes).totalBytes) : 0);
}

class VulkanChunkBackend final : public ChunkBackend {
public:
    VulkanChunkBackend(VulkanDevice& device, const PackageInfo& package, const PoolPlan& plan,
                       const ChunkAttributes& attributes, const ChunkUploadOptions& upload, ChunkUploadMode mode)
        : device_(device), plan_(plan), attributes_(attributes), upload_(upload), mode_(mode),
          tables_(tableLayout(plan.slots, package)), bounds_(package.bounds),
          topNodeCount_(uint32_t(package.topTree.size())), chunkCount_(uint32_t(package.chunks.size())),
          volumes_(device), textures_(device) {}

    ~VulkanChunkBackend() override {
        if (uploader_) {
            (void)uploader_->finish();  // the last copies' device times
            figures_ = uploader_->figures();
        }
        if (ChunkUploadFigures* to = upload_.figures) {
            to->hostCopySeconds += figures_.hostCopySeconds, to->dmaSeconds += figures_.dmaSeconds;
            to->stagingWaitSeconds += figures_.stagingWaitSeconds;
            to->dmaBytes += figures_.dmaBytes, to->dmaCopies += figures_.dmaCopies;
            to->dmaSubmits += figures_.dmaSubmits, to->stagingHits += figures_.stagingHits;
            to->stagedOnDecode += figures_.stagedOnDecode, to->stageSeconds += figures_.stageSeconds;
            to->dmaTimed = figures_.dmaTimed, to->stagingBytes = figures_.stagingBytes;
        }
    }

    Status init(const PackageInfo& package) {
        grid_ = package.grid;
        if (attributes_.packedPositions && !grid_.packsPositions())
            return Status::error("packed positions asked for, but the package's quantization grid (" +
                                 std::to_string(grid_.bits) +
                                 " bits) does not allow them (QuantizationGrid::packsPositions)");
        // The kernels compile while the pools are made; the shade variant guessed from the scene
        // and the default options (path integrator, the default sky's sun, no environment map).
        uint32_t codecs = 0;
        for (const PackageVolume& v : package.volumes) codecs |= 1u << uint32_t(v.volume.codec);
        wavefront_ = Wavefront::start(device_, plan_.slots >= chunkCount_, attributes_.packedPositions,
                                      shadeConstants(package.materials, false, true, attributes_.normals,
                                                     attributes_.colors, false, codecs,
                                                     !package.lights.empty(),
                                                     attributes_.uvs && !package.textures.empty(),
                                                     attributes_.uvs && attributes_.tangents,
                                                     !package.emitters.empty(), plan_.stateInHostMemory));
        const bool dma = mode_ == ChunkUploadMode::Dma;
        for (uint32_t s = 0; s < plan_.slots; ++s) {
            auto slot = device_.createBuffer(plan_.slotBytes, dma ? VulkanDevice::MemoryUse::DeviceOnly
                                                                  : VulkanDevice::MemoryUse::DeviceLocal);
            if (!slot) return slot.status().withContext("chunk slot " + std::to_string(s) + ": ");
            slots_.push_back(std::move(slot).value());
        }
        if (dma) {
            // In host memory: the options' size (one block per chunk at most); in device memory:
            // what the plan kept of the budget for it.
            const uint64_t staging = plan_.stagingBytes > 0 ? plan_.stagingBytes : upload_.stagingBytes;
            auto uploader =
                ChunkUploader::create(device_, staging, plan_.slotBytes, chunkCount_, upload_.submitBytes,
                                      upload_.copiesSeenLate);
            if (!uploader) return uploader.status();
            uploader_ = std::move(uploader).value();
            if (plan_.stagingBytes > 0) allocated_ += uploader_->stagingAllocatedBytes();
        }
        auto table = device_.createBuffer(tables_.totalBytes);
        if (!table) return table.status();
        table_ = std::move(table).value();
        if (topNodeCount_ > 0)
            VASTRAY_TRY(table_.upload(package.topTree.data(), topNodeCount_ * sizeof(KdNode), tables_.topNodes));
        // Path state in host memory outside the device's heaps is not the device's (PoolPlan; its
        // memory lies where the read-back memory does: createVulkanChunkBackend).
        const bool stateCounted = !plan_.stateInHostMemory || plan_.outputInDeviceMemory;
        auto state = device_.createBuffer(stateLayout(plan_.batchRays, attributes_.uvs, attributes_.tangents).totalBytes,
                                          plan_.stateInHostMemory ? VulkanDevice::MemoryUse::Staging
                                                                  : VulkanDevice::MemoryUse::DeviceLocal);
        if (!state) return state.status().withContext("the wave's path state: ");
        state_ = std::move(state).value();
        if (plan_.stateInHostMemory) {  // the walk's atomics stay on the device (PoolPlan::rayBytes)
            auto walkBits = device_.createBuffer(walkBitsBytes(plan_.batchRays));
            if (!walkBits) return walkBits.status().withContext("the wave's walk bits: ");
            walkBits_ = std::move(walkBits).value();
        }
        auto output = device_.createBuffer(outputLayout(plan_.outputPixels, stepCounterBytes(tables_)).totalBytes,
                                           VulkanDevice::MemoryUse::Readback);
        if (!output) return output.status();
        output_ = std::move(output).value();
        allocated_ += table_.allocatedBytes() + (stateCounted ? state_.allocatedBytes() : 0) + walkBits_.allocatedBytes() +
                     (plan_.outputInDeviceMemory ? output_.allocatedBytes() : 0);
        for (const GpuBuffer& b : slots_) allocated_ += b.allocatedBytes();
        // The budget less what init allocated (the plan counts whole granules; the device may round
        // up or not) and the reserve: what the volumes may take besides their reserve.
        const uint64_t budget = plan_.totalBytes + plan_.spareBytes;
        spare_ = budget - std::min(budget, allocated_ + plan_.reservedBytes);
        const std::vector<ChunkSlot> empty(plan_.slots, ChunkSlot{});
        VASTRAY_TRY(table_.upload(empty.data(), empty.size() * sizeof(ChunkSlot)));
        const std::vector<uint32_t> none(chunkCount_, kEmptyCell);
        VASTRAY_TRY(table_.upload(none.data(), none.size() * 4, tables_.chunkSlots));
        return wavefront_->ready();
    }

    std::string name() const override { return "vulkan"; }
    uint32_t slotCount() const override { return plan_.slots; }
    uint64_t bytesUploaded() const override { return uploaded_; }
    // Everything is allocated up front but the environment map's buffer (within the plan's reserve).
    uint64_t peakDeviceBytes() const override { return std::max(peak_, allocated_); }
    double uploadSeconds() const override { return uploadSeconds_; }
    double deviceSeconds() const override { return deviceSeconds_; }

    Status load(uint32_t slot, const DecodedChunk& chunk, std::span<const uint8_t> singleSided) override {
        if (slot >= slots_.size()) return Status::error("slot " + std::to_string(slot) + " does not exist");
        const auto start = std::chrono::steady_clock::now();
        SlotArrays arrays;
        VASTRAY_TRY(slotArrays(chunk, singleSided, arrays));
        const ChunkLayout& layout = arrays.layout;
        GpuBuffer& b = slots_[slot];
        if (uploader_) {
            VASTRAY_TRY(uploader_->upload(chunk.id, b, arrays.copies, layout.totalBytes)
                            .withContext("chunk " + std::to_string(chunk.id) + ": "));
        } else {
            const auto copyStart = std::chrono::steady_clock::now();
            VASTRAY_TRY(copyPieces(b, 0, arrays.copies).withContext("chunk " + std::to_string(chunk.id) + ": "));
            const auto copied = std::chrono::steady_clock::now() - copyStart;
            figures_.hostCopySeconds += std::chrono::duration<double>(copied).count();
        }
        const Bvh4& tree = chunk.bvh;
        const uint64_t base = b.address();
        ChunkSlot entry{};
        entry.flags = arrays.flags;
        entry.nodes = base + layout.nodes;
        entry.positions = base + layout.positions, entry.indices = base + layout.indices;
        const auto at = [&](uint32_t flag, uint64_t offset) { return (arrays.flags & flag) ? base + offset : 0; };
        entry.singleSided = at(kSlotSingleSided, layout.singleSided);
        entry.primitiveIds = at(kSlotPrimitiveIds, layout.primitiveIds);
        entry.materialIds = at(kSlotMaterialIds, layout.materialIds);
        entry.normals = at(kSlotNormals, layout.normals);
        entry.colors = at(kSlotColors, layout.colors);
        entry.uvs = at(kSlotUvs, layout.uvs);
        entry.nodeCount = uint32_t(tree.nodes.size());
        entry.boundsLoX = tree.bounds.lo.x, entry.boundsLoY = tree.bounds.lo.y, entry.boundsLoZ = tree.bounds.lo.z;
        entry.boundsHiX = tree.bounds.hi.x, entry.boundsHiY = tree.bounds.hi.y, entry.boundsHiZ = tree.bounds.hi.z;
        VASTRAY_TRY(table_.upload(&entry, sizeof(entry), slot * sizeof(ChunkSlot)));
        uploaded_ += arrays.bytes + sizeof(entry);
        uploadSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return Status::ok();
    }

    // DMA with ChunkUploadOptions::stageOnDecode: the chunk's arrays into a staging block of their
    // own now, on the calling (decoding) thread, while unused blocks are left; load() then finds
    // them staged. Reads only what init() set, so any number of threads may call it beside load().
    bool stagesChunks() const override { return uploader_ && upload_.stageOnDecode; }
    Status stage(const DecodedChunk& chunk, std::span<const uint8_t> singleSided) override {
        if (!uploader_ || !upload_.stageOnDecode) return Status::ok();
        SlotArrays arrays;
        VASTRAY_TRY(slotArrays(chunk, singleSided, arrays));
        return uploader_->stage(chunk.id, arrays.copies, arrays.layout.totalBytes)
            .withContext("chunk " + std::to_string(chunk.id) + ": ");
    }

    Status renderOnDevice(const DeviceRenderJob& job, ChunkPager& pager, RenderImage& image,
                          StreamingStats& stats) override {
        WavefrontBuffers b;
        b.table = &table_, b.tables = tables_, b.state = &state_, b.output = &output_;
        if (plan_.stateInHostMemory) b.walkBits = &walkBits_;
        b.pathCapacity = job.maxPathsPerWave > 0 ? std::min(plan_.batchRays, job.maxPathsPerWave) : plan_.batchRays;
        b.outputPixels = plan_.outputPixels;
        b.outOfCore = plan_.slots < chunkCount_;
        b.bounds = bounds_;
        stats.wavePaths = b.pathCapacity;
        stats.streamWindowTiles = 0;  // renderStreamed sets it
        stats.pathStateHostBytes = plan_.stateInHostMemory ? state_.allocatedBytes() : 0;
        b.topNodeCount = topNodeCount_, b.chunkCount = chunkCount_;
        b.normals = attributes_.normals, b.colors = attributes_.colors, b.uvs = attributes_.uvs;
        b.frames = attributes_.uvs && attributes_.tangents;
        b.packedPositions = attributes_.packedPositions;
        if (b.packedPositions)
            b.grid = {float(grid_.origin[0]), float(grid_.origin[1]), float(grid_.origin[2]), float(grid_.step())};
        b.uploader = uploader_.get();
        VASTRAY_TRY(prepareEnvironment(job.options->environment, job.options->volumes, stats));
        VASTRAY_TRY(prepareVolumes(job.options->volumes, stats));
        VASTRAY_TRY(prepareTextures(job, stats));
        b.environment = environment_ ? &environmentBuffer_ : nullptr;
        b.volumes = volumes_.buffer() ? &volumes_ : nullptr;
        b.textures = textures_.present() ? &textures_ : nullptr;
        return wavefront_->render(b, job, pager, image, stats, deviceSeconds_);
    }

private:
    // A chunk's arrays as a slot holds them (ChunkLayout), the copies that write them (pointing
    // into the chunk, and into `padded` for the single-sided bytes) and the slot entry's flags.
    struct SlotArrays {
        ChunkLayout layout;
        std::vector<SlotCopy> copies;
        std::vector<uint8_t> padded;
        uint64_t bytes = 0;
        uint32_t flags = 0;
    };
    Status slotArrays(const DecodedChunk& chunk, std::span<const uint8_t> singleSided, SlotArrays& out) const {
        const Bvh4& tree = chunk.bvh;
        const uint64_t triangles = chunk.indices.size() / 3;
        // Constant time for the package reader's chunks (DecodedChunk::validated); a pass over
        // the arrays only for hand-made ones.
        VASTRAY_TRY(validate(chunk, singleSided).withContext("chunk " + std::to_string(chunk.id) + ": "));
        for (size_t words : {chunk.normals.size(), chunk.colors.size(), chunk.uvs.size()})
            if (words != 0 && words != chunk.positions.size())
                return Status::error("chunk " + std::to_string(chunk.id) + " has " + std::to_string(words) +
                                     " attribute values for " + std::to_string(chunk.positions.size()) + " vertices");
        out.layout = chunkLayout(tree.nodes.size(), chunk.positions.size(), triangles, chunk.indexDeltas16,
                                 chunk.longTriangles.size(), attributes_);
        const ChunkLayout& layout = out.layout;
        if (layout.totalBytes > plan_.slotBytes)
            return Status::error("chunk " + std::to_string(chunk.id) + " needs " + std::to_string(layout.totalBytes) +
                                 " bytes, more than a slot's " + std::to_string(plan_.slotBytes) +
                                 " (the package directory understates it: damaged package?)");
        std::vector<SlotCopy>& copies = out.copies;
        auto put = [&](uint64_t offset, const void* data, uint64_t size) {
            out.bytes += size;
            copies.push_back({offset, data, size});
        };
        put(layout.nodes, tree.nodes.data(), tree.nodes.size() * sizeof(Bvh4Node));
        if (attributes_.packedPositions) {
            const uint64_t size = devicePositionBytes(chunk.positions.size(), true);
            out.bytes += size;
            copies.push_back({layout.positions, chunk.positions.data(), size, nullptr, &grid_});
        } else {
            put(layout.positions, chunk.positions.data(), chunk.positions.size() * 12);
        }
        if (chunk.indexDeltas16) {
            const uint64_t size = deviceIndexBytes(triangles, true, chunk.longTriangles.size());
            out.bytes += size;
            copies.push_back({layout.indices, chunk.indices.data(), size, &chunk.longTriangles});
            out.flags |= kSlotIndexDeltas16;
        } else {
            put(layout.indices, chunk.indices.data(), chunk.indices.size() * 4);
        }
        if (attributes_.singleSided) {
            // One byte per triangle, read four to a word: the bytes in order, zero padded.
            out.padded.assign((triangles + 3) / 4 * 4, 0);
            std::copy(singleSided.begin(), singleSided.end(), out.padded.begin());
            put(layout.singleSided, out.padded.data(), out.padded.size());
            out.flags |= kSlotSingleSided;
        }
        if (attributes_.primitiveIds) {
            put(layout.primitiveIds, chunk.primitiveIds.data(), triangles * 4);
            out.flags |= kSlotPrimitiveIds;
        }
        if (attributes_.materialIds && !chunk.materialIds.empty()) {
            put(layout.materialIds, chunk.materialIds.data(), triangles * 4);
            out.flags |= kSlotMaterialIds;
        }
        if (attributes_.normals && !chunk.normals.empty()) {
            put(layout.normals, chunk.normals.data(), chunk.normals.size() * 4);
            out.flags |= kSlotNormals;
        }
        if (attributes_.colors && !chunk.colors.empty()) {
            put(layout.colors, chunk.colors.data(), chunk.colors.size() * 4);
            out.flags |= kSlotColors;
        }
        if (attributes_.uvs && !chunk.uvs.empty()) {
            put(layout.uvs, chunk.uvs.data(), chunk.uvs.size() * 8);
            out.flags |= kSlotUvs;
        }
        return Status::ok();
    }

    // The environment map's arrays in their own buffer (EnvironmentLayout), in the bytes the plan
    // kept for it; kept while the next render uses the same map.
    Status prepareEnvironment(const Environment& environment, const std::shared_ptr<const std::vector<Volume>>& volumes,
                              StreamingStats& stats) {
        if (environment.map == environment_) return Status::ok();
        uint64_t oldMap = 0;
        if (environment_) {
            oldMap = environmentBuffer_.allocatedBytes();
            allocated_ -= oldMap;
            environmentBuffer_ = GpuBuffer();
            environment_.reset();
        }
        if (!environment.map) return Status::ok();
        const EnvironmentMap& map = *environment.map;
        VASTRAY_TRY(checkReserve(environment, volumes));
        const EnvironmentLayout layout = environmentLayout(map.width, map.height);
        // Kept volumes hold what the last map left of the reserve and the spare: before a larger
        // map is allocated they give it back (prepareVolumes builds them again in what this map
        // leaves), so that the map and the volumes never hold more than the budget together.
        if (layout.totalBytes > oldMap && volumes_.allocatedBytes() > 0) {
            allocated_ -= volumes_.allocatedBytes();
            VASTRAY_TRY(volumes_.prepare(nullptr, 0, plan_.batchRays, stats));
        }
        auto buffer = device_.createBuffer(layout.totalBytes);
        if (!buffer) return buffer.status().withContext("environment map: ");
        environmentBuffer_ = std::move(buffer).value();
        VASTRAY_TRY(environmentBuffer_.upload(map.rgb.data(), map.rgb.size() * 4, layout.rgb));
        VASTRAY_TRY(environmentBuffer_.upload(map.density.data(), map.density.size() * 4, layout.density));
        VASTRAY_TRY(environmentBuffer_.upload(map.marginalCdf.data(), map.marginalCdf.size() * 4, layout.marginal));
        VASTRAY_TRY(environmentBuffer_.upload(map.conditionalCdf.data(), map.conditionalCdf.size() * 4,
                                              layout.conditional));
        stats.hostToDeviceBytes += map.deviceBytes();
        allocated_ += environmentBuffer_.allocatedBytes();
        peak_ = std::max(peak_, allocated_);
        environment_ = environment.map;
        return Status::ok();
    }

    // The map and the volumes (paged through the fewest brick slots when that is less) fit the
    // bytes the plan kept for them.
    Status checkReserve(const Environment& environment, const std::shared_ptr<const std::vector<Volume>>& volumes) const {
        const uint64_t map = environmentBytes(environment),
                       grids = volumes ? minimumVolumeBytes(volumeShapes(*volumes), plan_.batchRays) : 0;
        if (map + grids <= plan_.reservedBytes - plan_.textureBytes) return Status::ok();
        return Status::error((map ? "the environment map needs " + formatBytes(map) + (grids ? " and " : "") : std::string("")) +
                             (grids ? "the volumes need at least " + formatBytes(grids) : std::string()) +
                             " of device memory; the pool kept " + formatBytes(plan_.reservedBytes - plan_.textureBytes) +
                             " for them (createVulkanChunkBackend's reservedBytes)");
    }

    // The volumes in the bytes the plan kept besides the map's, and in what the plan left of the
    // budget (spare_: more brick slots, fewer region turnovers when paged): in core when they fit,
    // else paged (DeviceVolumes); kept while the next render uses the same ones.
    Status prepareVolumes(const std::shared_ptr<const std::vector<Volume>>& volumes, StreamingStats& stats) {
        VASTRAY_TRY(checkReserve(Environment{}, volumes));
        const uint64_t map = environment_ ? environmentBuffer_.allocatedBytes() : 0;
        allocated_ -= volumes_.allocatedBytes();
        const uint64_t kept = plan_.reservedBytes - plan_.textureBytes + spare_;
        const Status s = volumes_.prepare(volumes, kept - std::min(map, kept), plan_.batchRays, stats);
        allocated_ += volumes_.allocatedBytes();
        peak_ = std::max(peak_, allocated_);
        return s;
    }

    // The package's textures in the bytes the plan kept for them (in core, or paged through a
    // pool of page slots: DeviceTextures); kept from one render to the next.
    Status prepareTextures(const DeviceRenderJob& job, StreamingStats& stats) {
        allocated_ -= textures_.allocatedBytes();
        const Status s = textures_.prepare(job.textures, job.readTexturePage, plan_.textureBytes, stats,
                                           cutoutTextures(job.materials, job.textures.size()));
        allocated_ += textures_.allocatedBytes();
        peak_ = std::max(peak_, allocated_);
        return s;
    }

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
        if (c.validated) return Status::ok();
        if (c.indexDeltas16 && c.longTriangles != longTriangles(c.indices))
            return Status::error("its long triangles are not those of its indices (indexDeltas16)");
        if (attributes_.packedPositions)
            for (size_t v = 0; v < c.positions.size(); ++v)
                if (!grid_.packsExactly(c.positions[v]))
                    return Status::error("vertex " + std::to_string(v) + " does not lie on the package's grid "
                                         "(packed positions)");
        return validateChunkGeometry(c.bvh, c.positions.size(), c.indices);
    }

    VulkanDevice& device_;
    PoolPlan plan_;
    ChunkAttributes attributes_;
    ChunkUploadOptions upload_;
    ChunkUploadMode mode_;  // Mapped or Dma
    TableLayout tables_;  // in table_
    Aabb bounds_;         // the package's: the top-level tree's bounds
    QuantizationGrid grid_;  // the package's: packs positions with attributes_.packedPositions
    uint32_t topNodeCount_, chunkCount_;
    std::unique_ptr<Wavefront> wavefront_;
    std::vector<GpuBuffer> slots_;
    GpuBuffer table_, state_, walkBits_, output_;
    std::shared_ptr<const EnvironmentMap> environment_;  // the map in environmentBuffer_
    GpuBuffer environmentBuffer_;
    DeviceVolumes volumes_;  // the render's volumes, in core or paged
    DeviceTextures textures_;  // the package's textures, in core or paged (plan_.textureBytes)
    std::unique_ptr<ChunkUploader> uploader_;  // Dma; destroyed first: its copies write the slots
    ChunkUploadFigures figures_;
    uint64_t allocated_ = 0, peak_ = 0, uploaded_ = 0;
    uint64_t spare_ = 0;  // the budget less what init allocated and the reserve
    double uploadSeconds_ = 0, deviceSeconds_ = 0;
};

}  // namespace

Result<PoolPlan> planPool(const PackageInfo& package, const ChunkAttributes& attributes, uint64_t budget,
                          bool outputInDeviceMemory, double waveShareOutOfCore, uint64_t stagingInDeviceMemory,
                          uint64_t reservedBytes, uint32_t hostStatePaths, uint32_t maxOutOfCorePaths) {
    if (!(waveShareOutOfCore > 0 && waveShareOutOfCore < 1))
        return Status::error("the wave's share of an out-of-core budget must be in (0, 1), not " +
                             std::to_string(waveShareOutOfCore));
    if (maxOutOfCorePaths < kMinBatchRays || maxOutOfCorePaths > kMaxBatchRays)
        return Status::error("the out-of-core wave's cap must be within " + std::to_string(kMinBatchRays) + " and " +
                             std::to_string(kMaxBatchRays) + " paths, not " + std::to_string(maxOutOfCorePaths));
    PoolPlan plan;
    plan.outputInDeviceMemory = outputInDeviceMemory;
    const uint64_t counterBytes = stepCounterBytes(tableLayout(1, package));
    auto batchBytes = [=](uint64_t paths) {
        return gpu::batchBytes(paths, outputInDeviceMemory, counterBytes, attributes);
    };
    const uint64_t kRayBytes = rayBytes(outputInDeviceMemory, attributes);
    uint64_t largest = 0;
    for (const ChunkInfo& c : package.chunks) largest = std::max(largest, chunkLayout(c, attributes).totalBytes);
    plan.slotBytes = largest;
    const uint64_t slotAllocation = granules(largest);
    const uint32_t chunks = uint32_t(std::max<size_t>(package.chunks.size(), 1));
    auto tableBytes = [&](uint64_t slots) { return granules(tableLayout(slots, package).totalBytes); };
    const uint64_t staging =
        stagingInDeviceMemory ? std::clamp<uint64_t>(granules(stagingInDeviceMemory), 2 * slotAllocation,
                                                     std::max<uint64_t>(chunks, 2) * slotAllocation)
                              : 0;
    const uint64_t textures = textureReserveBytes(package, budget);
    const uint64_t reserved = (reservedBytes > 0 ? granules(reservedBytes) : 0) + textures;
    // The wave's device bytes: its path state, or with the state in host memory its walk bits (a
    // byte a path apart on the device) and, where host memory is the device's, the state too.
    auto waveBytes = [&](uint64_t rays, bool hostState) {
        return hostState ? granules(walkBitsBytes(rays)) + (outputInDeviceMemory ? batchBytes(rays) : 0) : batchBytes(rays);
    };
    const uint64_t minimumWave = std::max(batchBytes(kMinBatchRays), hostStatePaths > 0 ? waveBytes(kMinBatchRays, true) : 0);
    plan.minimumBytes = slotAllocation + minimumWave + tableBytes(1) + staging + reserved;
    if (budget < plan.minimumBytes)
        return Status::error("--memory-budget " + formatBytes(budget) + " is below this scene's minimum of " +
                             formatBytes(plan.minimumBytes) + " = " + std::to_string(plan.minimumBytes) +
                             " bytes (one chunk slot of " + formatBytes(slotAllocation) + " plus a wave of " +
                             std::to_string(kMinBatchRays) + " paths of " + formatBytes(minimumWave) +
                             " plus tables of " + formatBytes(tableBytes(1)) +
                             (staging ? " plus a staging area of " + formatBytes(staging) : std::string()) +
                             (reserved ? " plus the environment map's, volumes' and textures' " + formatBytes(reserved) : std::string()) + ")");
    budget -= staging + reserved;  // the rest is split between the wave and the slots
    // A quarter of the budget for the wave (within [kMinBatchRays, kMaxBatchRays]), the rest for
    // slots; slots beyond the chunk count are useless, so what they would take goes back to the
    // wave. When the slots cannot hold every chunk, the wave gets waveShareOutOfCore (half by
    // default): every wave pages the scene through the slots again, so out of core fewer, larger
    // waves mean fewer loads, and fewer slots only mean more walk passes per stream (PERF_NOTES 25);
    // but at most kMaxOutOfCoreBatchRays paths, beyond which more slots pay more (PERF_NOTES 63).
    // A wave halved until the budget holds it besides one slot (kMinBatchRays at least), and the
    // slots what a wave of `waveBytes` leaves (at least one, never more than the chunks).
    auto fitWave = [&](uint64_t rays, bool hostState) {
        while (rays > kMinBatchRays && waveBytes(rays, hostState) + slotAllocation + tableBytes(1) > budget) rays /= 2;
        return std::max<uint64_t>(rays, kMinBatchRays);
    };
    auto slotsBeside = [&](uint64_t waveBytes) {
        const uint64_t available = budget - waveBytes;  // >= one slot and a one-slot table
        const uint64_t slots = available >= tableBytes(chunks) + slotAllocation
                                   ? (available - tableBytes(chunks)) / slotAllocation
                                   : 1;
        return std::min<uint64_t>(slots, chunks);
    };
    auto split = [&](double share, uint64_t maxRays, uint64_t& rays, uint64_t& slots) {
        rays = fitWave(std::clamp<uint64_t>(uint64_t(double(budget) * share) / kRayBytes, kMinBatchRays, maxRays), false);
        slots = slotsBeside(batchBytes(rays));
    };
    uint64_t rays = 0, slots = 0;
    split(0.25, kMaxBatchRays, rays, slots);
    if (slots < chunks && hostStatePaths > 0) {
        // The state in host memory: where that memory is the device's it counts (and the wave
        // shrinks to what the budget holds besides a slot); else the slots take the budget but
        // for the walk bits (a byte a path).
        plan.stateInHostMemory = true;
        rays = fitWave(std::clamp<uint64_t>(hostStatePaths, kMinBatchRays, kMaxBatchRays), true);
        slots = slotsBeside(waveBytes(rays, true));
    } else if (slots < chunks) {
        split(waveShareOutOfCore, maxOutOfCorePaths, rays, slots);
    }
    const uint64_t left = budget - slots * slotAllocation - tableBytes(slots);
    while (!plan.stateInHostMemory && rays * 2 <= kGrowBatchRays && batchBytes(rays * 2) <= left) rays *= 2;
    plan.slots = uint32_t(slots);
    plan.batchRays = uint32_t(rays);
    plan.outputPixels = slots < chunks && !outputInDeviceMemory ? kOutOfCoreOutputScale * rays : rays;
    plan.rayBytes = waveBytes(rays, plan.stateInHostMemory);
    plan.tableBytes = tableBytes(slots);
    plan.stagingBytes = staging;
    plan.reservedBytes = reserved;
    plan.textureBytes = textures;
    plan.totalBytes = slots * slotAllocation + plan.rayBytes + plan.tableBytes + staging + reserved;
    plan.spareBytes = budget - (slots * slotAllocation + plan.rayBytes + plan.tableBytes);
    return plan;
}

Result<PathStateMemory> parsePathStateMemory(std::string_view name) {
    if (name == "auto") return PathStateMemory::Auto;
    if (name == "device") return PathStateMemory::Device;
    if (name == "host") return PathStateMemory::Host;
    return Status::error("the path state's memory must be auto, device or host, not '" + std::string(name) + "'");
}

uint64_t residentChunkBytes(const PackageInfo& package, const ChunkAttributes& attributes) {
    uint64_t bytes = 0;
    for (const ChunkInfo& c : package.chunks) bytes += chunkLayout(c, attributes).totalBytes;
    return bytes;
}

Result<PathStateMemory> resolvePathStateMemory(PathStateMemory asked, bool separateMemory, const PackageInfo& package,
                                               const ChunkAttributes& attributes, uint64_t budget) {
    if (asked == PathStateMemory::Host && !package.volumes.empty())
        return Status::error("the path state cannot lie in host memory in a scene with volumes (their paged "
                             "tracking keeps per-path records in device memory); ask for auto or device");
    if (asked != PathStateMemory::Auto) return asked;
    const bool pays = separateMemory && package.volumes.empty() &&
                      double(residentChunkBytes(package, attributes)) > kHostStateOversubscription * double(budget);
    return pays ? PathStateMemory::Host : PathStateMemory::Device;
}

uint64_t defaultStagingBytes() {
    return std::clamp<uint64_t>(physicalHostBytes() / 16, 1ull << 30, 16ull << 30);
}

uint64_t environmentBytes(const Environment& environment) {
    return environment.map ? granules(environment.map->deviceBytes()) : 0;
}

namespace {
std::vector<VolumeShape> volumeShapes(const PackageInfo& package) {
    std::vector<VolumeShape> shapes;
    for (const PackageVolume& v : package.volumes)
        shapes.push_back({v.volume.cellCount(), v.brickCount, v.hasEmission, volumeDeviceLeafBytes(v.volume.codec)});
    return shapes;
}
}  // namespace

uint64_t volumeBytes(const PackageInfo& package) { return inCoreVolumeBytes(volumeShapes(package)); }

uint64_t textureBytes(const PackageInfo& package) { return inCoreTextureBytes(package.textures); }

uint64_t textureReserveBytes(const PackageInfo& package, uint64_t budget) {
    const uint64_t whole = inCoreTextureBytes(package.textures);
    const uint64_t share = uint64_t(double(budget) * kTextureShareOutOfCore) / kAllocationGranule * kAllocationGranule;
    if (whole <= share) return whole;
    const uint64_t pinned = pinnedPages(package.textures, cutoutTextures(package.materials, package.textures.size()));
    return std::max(share, pagedTextureBytes(package.textures, kMinTexturePageSlots + pinned));
}

uint64_t volumeReserveBytes(const PackageInfo& package, uint64_t budget) {
    const uint64_t whole = volumeBytes(package);
    const uint64_t share = uint64_t(double(budget) * kVolumeShareOutOfCore) / kAllocationGranule * kAllocationGranule;
    if (whole <= share) return whole;
    // The fewest slots, and the park records of a minimal wave (a larger wave takes slots).
    return std::max(share, pagedVolumeBytes(volumeShapes(package), kMinVolumeSlots, kMinBatchRays));
}

// DMA where the slots can live in memory the host does not map and the staging in system
// memory (a discrete GPU: PERF_NOTES 44); elsewhere (lavapipe, integrated GPUs: one memory) a
// copy through staging would only add one.
ChunkUploadMode resolveUploadMode(const VulkanDevice& device, ChunkUploadMode mode) {
    if (mode != ChunkUploadMode::Auto) return mode;
    return device.hasSeparateMemory() ? ChunkUploadMode::Dma : ChunkUploadMode::Mapped;
}

Result<std::unique_ptr<ChunkBackend>> createVulkanChunkBackend(VulkanDevice& device, const PackageInfo& package,
                                                               const ChunkAttributes& attributes, uint64_t budget,
                                                               double waveShareOutOfCore,
                                                               const ChunkUploadOptions& given,
                                                               uint64_t reservedBytes,
                                                               const PathStateOptions& pathState) {
    const ChunkUploadMode mode = resolveUploadMode(device, given.mode);
    ChunkUploadOptions upload = given;
    if (upload.stagingBytes == ChunkUploadOptions::kStagingAuto) upload.stagingBytes = defaultStagingBytes();
    const bool stagingInDevice = device.inDeviceMemory(VulkanDevice::MemoryUse::Staging);
    const uint64_t stagingInDeviceMemory = mode == ChunkUploadMode::Dma && stagingInDevice ? upload.stagingBytes : 0;
    // The plan counts a path state in host memory against the budget where the read-back memory
    // is the device's (PoolPlan::stateInHostMemory); that holds only where the state's memory type
    // (Staging) lies in the same kind of heap, as on every device we know. Elsewhere host memory
    // is not offered.
    const bool stateLikeOutput = stagingInDevice == device.readbackInDeviceMemory();
    if (pathState.memory == PathStateMemory::Host && !stateLikeOutput)
        return Status::error("the path state cannot lie in host memory on this device: its host-visible "
                             "memory types lie in different heaps (staging and read-back); ask for auto or device");
    auto memory = resolvePathStateMemory(pathState.memory, device.hasSeparateMemory() && stateLikeOutput, package,
                                         attributes, budget);
    if (!memory) return memory.status();
    auto plan = planPool(package, attributes, budget, device.readbackInDeviceMemory(), waveShareOutOfCore,
                         stagingInDeviceMemory, reservedBytes,
                         *memory == PathStateMemory::Host ? std::max<uint32_t>(pathState.hostPaths, 1) : 0,
                         pathState.deviceWaveCap);
    if (!plan) return plan.status();
    auto backend = std::make_unique<VulkanChunkBackend>(device, package, *plan, attributes, upload, mode);
    VASTRAY_TRY(backend->init(package));
    if (backend->peakDeviceBytes() > budget)
        return Status::error("the device rounded the pool up to " + formatBytes(backend->peakDeviceBytes()) +
                             ", above the budget of " + formatBytes(budget));
    return std::unique_ptr<ChunkBackend>(std::move(backend));
}

}  // namespace vastray::gpu
