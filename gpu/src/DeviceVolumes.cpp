#include "DeviceVolumes.h"

#include <algorithm>
#include <numeric>
#include <string>

#include "PoolLayout.h"
#include "vastray/core/ByteSize.h"

namespace vastray::gpu {
namespace {

std::vector<VolumeShape> shapesOf(std::span<const Volume> volumes) {
    std::vector<VolumeShape> shapes;
    for (const Volume& v : volumes) shapes.push_back({v.cellCount(), v.brickCount(), !v.emissionVoxels.empty()});
    return shapes;
}

// The paged buffer and the readback of its counters (DeviceVolumes::readback).
uint64_t pagedBytes(std::span<const VolumeShape> shapes, uint64_t slots) {
    uint64_t bricks = 0;
    for (const VolumeShape& s : shapes) bricks += s.bricks;
    return granules(pagedVolumeLayout(shapes, slots).totalBytes) + granules(4 * (bricks + slots));
}

// The most slots whose paged layout fits `bytes` (0 when not even the tables do).
uint64_t slotsFitting(std::span<const VolumeShape> shapes, uint64_t bytes) {
    const uint64_t base = pagedBytes(shapes, 0);
    if (bytes < base) return 0;
    bool emission = false;
    for (const VolumeShape& s : shapes) emission = emission || s.emission;
    const uint64_t perSlot = 4ull * kVolumeBrickVoxels * (emission ? 2 : 1) + 8;
    uint64_t slots = (bytes - base) / perSlot;
    while (slots > 0 && pagedBytes(shapes, slots) > bytes) slots -= std::max<uint64_t>(1, slots / 1024);
    return slots;
}

}  // namespace

uint64_t volumesInCoreBytes(std::span<const Volume> volumes) {
    const std::vector<VolumeShape> shapes = shapesOf(volumes);
    return shapes.empty() ? 0 : granules(volumeLayout(shapes).totalBytes);
}

uint64_t volumesMinimumBytes(std::span<const Volume> volumes) {
    const std::vector<VolumeShape> shapes = shapesOf(volumes);
    return shapes.empty() ? 0 : std::min(volumesInCoreBytes(volumes), pagedBytes(shapes, kMinVolumeSlots));
}

Status DeviceVolumes::prepare(const std::shared_ptr<const std::vector<Volume>>& volumes, uint64_t bytes,
                              StreamingStats& stats) {
    const bool none = !volumes || volumes->empty();
    if (none || volumes != volumes_ || buffer_.allocatedBytes() > bytes) {
        buffer_ = GpuBuffer();
        readback_ = GpuBuffer();
        volumes_.reset();
        slots_ = 0;
        if (!none) {
            const std::vector<VolumeShape> shapes = shapesOf(*volumes);
            Status built = Status::ok();
            if (volumesInCoreBytes(*volumes) <= bytes) {
                built = buildInCore(*volumes, stats);
            } else if (const uint64_t slots = std::min<uint64_t>(slotsFitting(shapes, bytes), kNoBrick - 1);
                       slots >= kMinVolumeSlots) {
                built = buildPaged(*volumes, uint32_t(slots), stats);
            } else {
                built = Status::error("the volumes need " + formatBytes(volumesInCoreBytes(*volumes)) +
                                      " of device memory in core, or " +
                                      formatBytes(pagedBytes(shapes, kMinVolumeSlots)) +
                                      " paged through the fewest brick slots (" + std::to_string(kMinVolumeSlots) +
                                      "); the pool kept " + formatBytes(bytes) + " for them");
            }
            if (!built) {
                buffer_ = GpuBuffer();
                readback_ = GpuBuffer();
                slots_ = 0;
                return built;
            }
            volumes_ = volumes;
        }
    }
    stats.volumeBrickSlots = slots_;
    return Status::ok();
}

Status DeviceVolumes::writeRecords(const std::vector<Volume>& volumes, std::span<const uint64_t> brickOf,
                                   std::span<const uint64_t> majorant, std::span<const uint64_t> voxels,
                                   std::span<const uint64_t> emission) {
    const uint64_t base = buffer_.address();
    std::vector<WavefrontVolume> records;
    uint32_t bricks = 0;
    for (size_t i = 0; i < volumes.size(); ++i) {
        const Volume& v = volumes[i];
        WavefrontVolume& r = records.emplace_back();
        r.brickOf = base + brickOf[i], r.majorant = base + majorant[i], r.voxels = base + voxels[i];
        r.emissionVoxels = v.emissionVoxels.empty() ? 0 : base + emission[i];
        std::copy(v.worldToIndex.begin(), v.worldToIndex.end(), r.worldToIndex);
        r.originX = v.origin[0], r.originY = v.origin[1], r.originZ = v.origin[2];
        r.cellsX = v.brickCells[0], r.cellsY = v.brickCells[1], r.cellsZ = v.brickCells[2];
        r.albedoR = v.material.albedo[0], r.albedoG = v.material.albedo[1], r.albedoB = v.material.albedo[2];
        r.densityScale = v.material.densityScale, r.anisotropy = v.material.anisotropy;
        r.emitR = v.material.emission[0], r.emitG = v.material.emission[1], r.emitB = v.material.emission[2];
        r.brickBase = bricks;
        bricks += uint32_t(v.brickCount());
    }
    return buffer_.upload(records.data(), records.size() * sizeof(WavefrontVolume), 0);
}

Status DeviceVolumes::allocate(const std::vector<Volume>& volumes, uint64_t bytes) {
    for (size_t i = 0; i < volumes.size(); ++i)
        if (volumes[i].majorant.size() != volumes[i].cellCount() || volumes[i].brickOf.size() != volumes[i].cellCount())
            return Status::error("volume " + std::to_string(i) + " has no majorants or brick table");
    auto buffer = device_.createBuffer(bytes);
    if (!buffer) return buffer.status().withContext("volumes: ");
    buffer_ = std::move(buffer).value();
    return Status::ok();
}

Status DeviceVolumes::buildInCore(const std::vector<Volume>& volumes, StreamingStats& stats) {
    const VolumeLayout layout = volumeLayout(shapesOf(volumes));
    VASTRAY_TRY(allocate(volumes, layout.totalBytes));
    for (size_t i = 0; i < volumes.size(); ++i) {
        const Volume& v = volumes[i];
        if (!v.emissionVoxels.empty())
            VASTRAY_TRY(buffer_.upload(v.emissionVoxels.data(), v.emissionVoxels.size() * 4, layout.emission[i]));
        VASTRAY_TRY(buffer_.upload(v.brickOf.data(), v.brickOf.size() * 4, layout.brickOf[i]));
        VASTRAY_TRY(buffer_.upload(v.majorant.data(), v.majorant.size() * 4, layout.majorant[i]));
        if (!v.voxels.empty())  // a grid whose active values are all 0 has no bricks
            VASTRAY_TRY(buffer_.upload(v.voxels.data(), v.voxels.size() * 4, layout.voxels[i]));
        stats.hostToDeviceBytes += (v.brickOf.size() + v.majorant.size() + v.voxels.size() + v.emissionVoxels.size()) * 4;
    }
    return writeRecords(volumes, layout.brickOf, layout.majorant, layout.voxels, layout.emission);
}

Status DeviceVolumes::buildPaged(const std::vector<Volume>& volumes, uint32_t slots, StreamingStats& stats) {
    const PagedVolumeLayout layout = pagedVolumeLayout(shapesOf(volumes), slots);
    VASTRAY_TRY(allocate(volumes, layout.totalBytes));
    uint64_t bricks = 0;
    for (const Volume& v : volumes) bricks += v.brickCount();
    auto readback = device_.createBuffer(4 * (bricks + slots), VulkanDevice::MemoryUse::Readback);
    if (!readback) return readback.status().withContext("volume brick counters: ");
    readback_ = std::move(readback).value();
    slots_ = slots;
    brickVolume_.clear(), brickCell_.clear(), volumeFirstBrick_.clear(), tableOffset_.clear();
    for (size_t i = 0; i < volumes.size(); ++i) {
        const Volume& v = volumes[i];
        const uint32_t first = uint32_t(brickVolume_.size());
        volumeFirstBrick_.push_back(first);
        tableOffset_.push_back(layout.brickOf[i]);
        brickVolume_.resize(first + v.brickCount(), uint32_t(i));
        brickCell_.resize(first + v.brickCount(), 0);
        // Every brick starts absent: its cell holds kBrickAbsent | brick.
        std::vector<uint32_t> table(v.brickOf.size());
        for (uint64_t c = 0; c < table.size(); ++c) {
            const uint32_t brick = v.brickOf[c];
            table[c] = brick == kNoBrick ? kNoBrick : kBrickAbsent | brick;
            if (brick != kNoBrick) brickCell_[first + brick] = uint32_t(c);
        }
        VASTRAY_TRY(buffer_.upload(table.data(), table.size() * 4, layout.brickOf[i]));
        VASTRAY_TRY(buffer_.upload(v.majorant.data(), v.majorant.size() * 4, layout.majorant[i]));
        stats.hostToDeviceBytes += (table.size() + v.majorant.size()) * 4;
    }
    brickSlot_.assign(brickVolume_.size(), kNoBrick);
    slotBrick_.assign(slots, kNoBrick);
    slotLastUse_.assign(slots, 0);
    densityOffset_ = layout.density, emissionOffset_ = layout.emission;
    demandOffset_ = layout.demand, usedOffset_ = layout.used;
    const std::vector<uint32_t> none(std::max<uint64_t>(brickVolume_.size(), slots), kNoBrick);
    VASTRAY_TRY(buffer_.upload(none.data(), brickVolume_.size() * 4, demandOffset_));
    VASTRAY_TRY(buffer_.upload(none.data(), uint64_t(slots) * 4, usedOffset_));
    const std::vector<uint64_t> density(volumes.size(), layout.density), emission(volumes.size(), layout.emission);
    return writeRecords(volumes, layout.brickOf, layout.majorant, density, emission);
}

// Priorities: the lowest path that asked for a brick or read a slot's brick this step (kNoBrick:
// none). The pool keeps the bricks of the lowest paths: an absent brick replaces a slot only
// when its path is lower than every path that read the slot, so the lowest waiting path gets
// every brick it reads (when they fit the pool at all) and finishes; the render cannot stall.
// Among slots no path read, empty ones go first, then the least recently used.
Result<uint64_t> DeviceVolumes::page(std::span<const uint32_t> demand, std::span<const uint32_t> used,
                                     StreamingStats& stats) {
    if (!paged() || demand.size() != brickVolume_.size() || used.size() != slots_)
        return Status::error("volume paging: demand or used counters of the wrong size");
    ++tick_;
    for (uint32_t s = 0; s < slots_; ++s)
        if (used[s] != kNoBrick) slotLastUse_[s] = tick_;
    std::vector<uint32_t> wanted;
    for (uint32_t b = 0; b < demand.size(); ++b)
        if (demand[b] != kNoBrick && brickSlot_[b] == kNoBrick) wanted.push_back(b);
    std::sort(wanted.begin(), wanted.end(), [&](uint32_t a, uint32_t b) {
        return demand[a] != demand[b] ? demand[a] < demand[b] : a < b;
    });
    // Victims in order: empty, unread (least recently used first), then read by the highest paths.
    std::vector<uint32_t> victims(slots_);
    std::iota(victims.begin(), victims.end(), 0u);
    auto rank = [&](uint32_t s) {
        if (slotBrick_[s] == kNoBrick) return std::pair<uint64_t, uint64_t>(0, 0);
        if (used[s] == kNoBrick) return std::pair<uint64_t, uint64_t>(1, slotLastUse_[s]);
        return std::pair<uint64_t, uint64_t>(2, uint64_t(kNoBrick) - used[s]);
    };
    std::sort(victims.begin(), victims.end(), [&](uint32_t a, uint32_t b) {
        const auto ra = rank(a), rb = rank(b);
        return ra != rb ? ra < rb : a < b;
    });
    const uint64_t brickBytes = 4ull * kVolumeBrickVoxels;
    auto setCell = [&](uint32_t brick, uint32_t entry) {
        return buffer_.upload(&entry, 4, tableOffset_[brickVolume_[brick]] + 4ull * brickCell_[brick]);
    };
    uint64_t loads = 0;
    for (size_t i = 0; i < wanted.size() && i < victims.size(); ++i) {
        const uint32_t slot = victims[i], brick = wanted[i];
        if (slotBrick_[slot] != kNoBrick && used[slot] != kNoBrick && used[slot] <= demand[brick]) break;
        if (const uint32_t old = slotBrick_[slot]; old != kNoBrick) {
            brickSlot_[old] = kNoBrick;
            VASTRAY_TRY(setCell(old, kBrickAbsent | (old - volumeFirstBrick_[brickVolume_[old]])));
        }
        const Volume& v = (*volumes_)[brickVolume_[brick]];
        const uint64_t local = brick - volumeFirstBrick_[brickVolume_[brick]];
        VASTRAY_TRY(buffer_.upload(v.voxels.data() + local * kVolumeBrickVoxels, brickBytes, densityOffset_ + slot * brickBytes));
        if (!v.emissionVoxels.empty())
            VASTRAY_TRY(buffer_.upload(v.emissionVoxels.data() + local * kVolumeBrickVoxels, brickBytes,
                                       emissionOffset_ + slot * brickBytes));
        stats.hostToDeviceBytes += brickBytes * (v.emissionVoxels.empty() ? 1 : 2) + 4;
        brickSlot_[brick] = slot, slotBrick_[slot] = brick, slotLastUse_[slot] = tick_;
        VASTRAY_TRY(setCell(brick, slot));
        ++loads;
    }
    stats.volumeBrickLoads += loads;
    return loads;
}

}  // namespace vastray::gpu
