#pragma once
// A render's density volumes on the device (core/Volume.h; the shading kernel reads them through
// WavefrontVolume records, common/Volume.glsl). In core every brick is in one buffer
// (VolumeLayout). When the bytes the budget kept for them cannot hold every brick, the volumes
// are paged (PagedVolumeLayout): the cell tables and majorants stay resident, the bricks go into
// a pool of slots, and between the wavefront's paging steps page() turns the kernels' per-brick
// demand counters into loads of the bricks parked walks wait for. docs/RENDERING.md, "Volumes out
// of core".
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "PoolLayout.h"
#include "vastray/core/Result.h"
#include "vastray/core/Volume.h"
#include "vastray/gpu/VulkanDevice.h"
#include "vastray/streamer/StreamingRenderer.h"

namespace vastray::gpu {

// A pool holds at least this many bricks: a trilinear read needs 8, a ray through a cloud more.
constexpr uint64_t kMinVolumeSlots = 64;
// Paged volumes keep the leaves they read from the package (Volume::bricks) or encoded from the
// voxels in memory in a host cache of at most this many bytes (at least a pool's worth), so that
// a brick paged in again is not read and checked again; least recently used first out (clock).
constexpr uint64_t kVolumeHostCacheBytes = 1ull << 30;

// The one place the volumes' device bytes are counted (the backend's reserve and DeviceVolumes
// alike): in core (VolumeLayout); paged through `slots` brick slots with the park records of
// waves of `paths` paths and the counters' readback; the least of in core and paged through
// kMinVolumeSlots. 0 without volumes.
std::vector<VolumeShape> volumeShapes(std::span<const Volume> volumes);
uint64_t inCoreVolumeBytes(std::span<const VolumeShape> shapes);
uint64_t pagedVolumeBytes(std::span<const VolumeShape> shapes, uint64_t slots, uint64_t paths);
uint64_t minimumVolumeBytes(std::span<const VolumeShape> shapes, uint64_t paths);

// The paging regions of one volume for a pool of `slots` brick slots (at least 27): boxes of
// brick cells cut in two across the longest axis until the box grown by one cell on every side
// holds at most `slots` stored bricks; the cut leaves half the box's stored bricks on either
// side, or 1/k of them before it, k the pools the grown box would fill, whichever way gives the
// fewer regions (ties: the fewer bricks, then halves). Every stored brick lies in one box, its
// home (home: per brick of the volume, its region); a region's `bricks` are the stored bricks
// of its grown box (the volume's brick numbers): with them resident, a walk parked at a cell
// whose bricks have their home there can sample that cell (its trilinear reads touch the cell
// and the cells after it, all within one cell of any of them). DeviceVolumes::page loads one
// when the pool has no slot for the bricks walks wait for.
struct VolumeRegions {
    std::vector<uint32_t> home;
    std::vector<std::vector<uint32_t>> bricks;
};
VolumeRegions volumeRegions(const Volume& volume, uint32_t slots);

class DeviceVolumes {
public:
    // hostCacheBytes: the host brick cache's bound (kVolumeHostCacheBytes; at least a pool's worth
    // is kept whatever it says). slotLimit: the most slots a pool takes (0: as many as the bytes
    // hold; a test's pool of a known size).
    explicit DeviceVolumes(VulkanDevice& device, uint64_t hostCacheBytes = kVolumeHostCacheBytes, uint32_t slotLimit = 0)
        : device_(device), hostCacheBytes_(hostCacheBytes), slotLimit_(slotLimit) {}

    // Puts `volumes` (none: empty or null) on the device in at most `bytes`: every brick when they
    // fit, else a pool of as many brick slots as fit besides the park records of waves of up to
    // `paths` paths (an error below kMinVolumeSlots). Kept while the next render uses the same
    // volumes and they still fit.
    Status prepare(const std::shared_ptr<const std::vector<Volume>>& volumes, uint64_t bytes, uint64_t paths,
                   StreamingStats& stats);

    const GpuBuffer* buffer() const { return volumes_ ? &buffer_ : nullptr; }
    // Paged: host-cached memory the demand counters are copied into after each paging step (the
    // host reads device memory through its mapping slowly).
    const GpuBuffer* readback() const { return paged() ? &readback_ : nullptr; }
    uint64_t allocatedBytes() const { return buffer_.allocatedBytes() + readback_.allocatedBytes(); }
    bool paged() const { return volumes_ && slots_ > 0; }
    uint32_t slotCount() const { return slots_; }        // 0: in core
    uint64_t brickCount() const { return brickVolume_.size(); }  // all volumes' bricks
    uint64_t demandOffset() const { return demandOffset_; }      // in buffer(): demandCount() uint (paged)
    // The demand counters (paged): per brick the parked walks waiting for it, per brick those
    // asking for it ahead, per slot whether a parked walk keeps it (common/Volume.glsl).
    uint64_t demandCount() const { return paged() ? 2 * brickCount() + slots_ : 0; }
    uint64_t parkOffset() const { return parkOffset_; }          // in buffer(): VolumePark per path (paged)
    uint64_t parkBytes() const { return parkBytes_; }

    // Paged, between steps while the device is idle: loads the bricks parked walks wait for
    // (`demand`: the counters, demandCount(); the policy in DeviceVolumes.cpp). Bricks not in
    // memory are read from their package on worker threads. Returns the loads: at least one when
    // a walk waits. A brick that fails to read fails the step (naming the package, the volume and
    // the brick) and drops the volumes: the next prepare builds them anew.
    Result<uint64_t> page(std::span<const uint32_t> demand, StreamingStats& stats);
    uint64_t hostCacheBricks() const { return entryBrick_.size(); }

private:
    Status buildInCore(const std::vector<Volume>& volumes, StreamingStats& stats);
    Status buildPaged(const std::vector<Volume>& volumes, uint32_t slots, uint64_t paths, StreamingStats& stats);
    Status allocate(const std::vector<Volume>& volumes, uint64_t bytes);
    // Uploads every brick of volume `i` (in memory, or read from its package in batches) to
    // `voxels` and `emission` (0: none) in buffer_.
    Status uploadAllBricks(const Volume& volume, uint64_t voxels, uint64_t emission, StreamingStats& stats);
    // A brick paged into a slot this step, and where its leaves (and the emission's: null without)
    // are in host memory.
    struct Move {
        uint32_t brick = 0, slot = 0;
        const uint8_t* density = nullptr;
        const uint8_t* emission = nullptr;
    };
    // The slots page() fills this step, in order: the empty ones, then those of bricks no parked
    // walk keeps, least recently used first.
    std::vector<uint32_t> slotsToFill(std::span<const uint32_t> kept);
    // The absent bricks of the region (volumeRegions) whose absent bricks walks ask for most among
    // those some walk waits in, and as many slots for them: empty ones, then those of bricks
    // outside it (when the waited bricks would take more than a third of the slots not kept).
    std::pair<std::vector<uint32_t>, std::vector<uint32_t>> regionLoads(std::span<const uint32_t> waits,
                                                                        std::span<const uint32_t> ahead);
    // Puts `bricks` (absent) into `slots` (one each, in order) and reads and copies their leaves.
    Result<uint64_t> load(std::span<const uint32_t> bricks, std::span<const uint32_t> slots, StreamingStats& stats);
    // Sets the move's host pointers: a host cache entry (a new entry also goes to `reads` as
    // (brick, entry): its leaves are read from the package, or encoded from the voxels in memory,
    // before the copies).
    Status placeInHost(Move& move, std::vector<std::pair<uint32_t, uint32_t>>& reads);
    uint32_t takeCacheEntry();
    Status copyBrick(const Move& move);
    // The blackbody table (core/Blackbody.h) at `offset` in buffer_ when a volume has a
    // temperature grid.
    Status uploadBlackbody(const std::vector<Volume>& volumes, uint64_t offset, StreamingStats& stats);
    // The WavefrontVolume records, each volume's arrays at these offsets in buffer_, its leaves
    // `slotBytes` apart (0: its own codec's leaf bytes) (`blackbody`: the table's, for volumes
    // with a temperature grid).
    Status writeRecords(const std::vector<Volume>& volumes, std::span<const uint64_t> brickOf,
                        std::span<const uint64_t> majorant, std::span<const uint64_t> voxels,
                        std::span<const uint64_t> emission, uint64_t slotBytes, uint64_t blackbody);

    VulkanDevice& device_;
    uint64_t hostCacheBytes_;
    uint32_t slotLimit_;
    std::shared_ptr<const std::vector<Volume>> volumes_;  // the volumes in buffer_
    GpuBuffer buffer_, readback_;
    uint32_t slots_ = 0;
    // Paged: per brick of all volumes its volume, its cell, its slot (kNoBrick: absent) and its
    // home region; per volume its first brick and where its cell table lies; per slot its brick
    // and the last step that loaded it or found it kept; per region (all volumes') the bricks it
    // makes resident (numbered among all volumes').
    std::vector<uint32_t> brickVolume_, brickCell_, brickSlot_, brickRegion_, volumeFirstBrick_, slotBrick_;
    std::vector<uint64_t> slotUsed_;
    std::vector<std::vector<uint32_t>> regionBricks_;
    std::vector<uint64_t> tableOffset_;
    uint64_t densityOffset_ = 0, emissionOffset_ = 0, demandOffset_ = 0, parkOffset_ = 0, parkBytes_ = 0;
    uint64_t slotBytes_ = 0;  // a pool slot: the largest leaf of the volumes' codecs
    // The host brick cache (paged): per entry cacheStride_ bytes (the density's whole leaf, then
    // the emission's; the largest codec's), the brick it holds, the step that last used it and its clock bit; per brick
    // its entry (kNoBrick: none).
    std::unique_ptr<uint8_t[]> cache_;
    uint64_t cacheStride_ = 0;
    std::vector<uint32_t> entryBrick_, brickEntry_;
    std::vector<uint64_t> entryStep_;
    std::vector<uint8_t> entryReferenced_;
    uint32_t hand_ = 0;
    uint64_t step_ = 0;
};

}  // namespace vastray::gpu
