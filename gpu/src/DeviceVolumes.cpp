#include "DeviceVolumes.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <array>
#include <numeric>
#include <string>

#include "PoolLayout.h"
#include "vastray/core/ByteSize.h"

namespace vastray::gpu {
namespace {

// The most slots whose paged layout fits `bytes` (0 when not even the tables do).
uint64_t slotsFitting(std::span<const VolumeShape> shapes, uint64_t bytes, uint64_t paths) {
    const uint64_t base = pagedVolumeBytes(shapes, 0, paths);
    if (bytes < base) return 0;
    bool emission = false;
    for (const VolumeShape& s : shapes) emission = emission || s.emission;
    const uint64_t perSlot = 4ull * kVolumeBrickVoxels * (emission ? 2 : 1);
    uint64_t slots = (bytes - base) / perSlot;
    while (slots > 0 && pagedVolumeBytes(shapes, slots, paths) > bytes) slots -= std::max<uint64_t>(1, slots / 1024);
    return slots;
}

}  // namespace

std::vector<VolumeShape> volumeShapes(std::span<const Volume> volumes) {
    std::vector<VolumeShape> shapes;
    for (const Volume& v : volumes) shapes.push_back({v.cellCount(), v.brickCount(), !v.emissionVoxels.empty()});
    return shapes;
}

uint64_t inCoreVolumeBytes(std::span<const VolumeShape> shapes) {
    return shapes.empty() ? 0 : granules(volumeLayout(shapes).totalBytes);
}

uint64_t pagedVolumeBytes(std::span<const VolumeShape> shapes, uint64_t slots, uint64_t paths) {
    uint64_t bricks = 0;
    for (const VolumeShape& s : shapes) bricks += s.bricks;
    return granules(pagedVolumeLayout(shapes, slots, paths).totalBytes) + granules(8 * bricks);
}

uint64_t minimumVolumeBytes(std::span<const VolumeShape> shapes, uint64_t paths) {
    return shapes.empty() ? 0 : std::min(inCoreVolumeBytes(shapes), pagedVolumeBytes(shapes, kMinVolumeSlots, paths));
}

Status DeviceVolumes::prepare(const std::shared_ptr<const std::vector<Volume>>& volumes, uint64_t bytes,
                              uint64_t paths, StreamingStats& stats) {
    const bool none = !volumes || volumes->empty();
    if (none || volumes != volumes_ || allocatedBytes() > bytes) {
        buffer_ = GpuBuffer();
        readback_ = GpuBuffer();
        volumes_.reset();
        slots_ = 0;
        if (!none) {
            const std::vector<VolumeShape> shapes = volumeShapes(*volumes);
            Status built = Status::ok();
            if (inCoreVolumeBytes(shapes) <= bytes) {
                built = buildInCore(*volumes, stats);
            } else if (const uint64_t slots = std::min<uint64_t>(slotsFitting(shapes, bytes, paths), kNoBrick - 1);
                       slots >= kMinVolumeSlots) {
                built = buildPaged(*volumes, uint32_t(slots), paths, stats);
            } else {
                built = Status::error("the volumes need " + formatBytes(inCoreVolumeBytes(shapes)) +
                                      " of device memory in core, or " +
                                      formatBytes(pagedVolumeBytes(shapes, kMinVolumeSlots, paths)) +
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
    const VolumeLayout layout = volumeLayout(volumeShapes(volumes));
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

Status DeviceVolumes::buildPaged(const std::vector<Volume>& volumes, uint32_t slots, uint64_t paths,
                                 StreamingStats& stats) {
    const PagedVolumeLayout layout = pagedVolumeLayout(volumeShapes(volumes), slots, paths);
    VASTRAY_TRY(allocate(volumes, layout.totalBytes));
    uint64_t bricks = 0;
    for (const Volume& v : volumes) bricks += v.brickCount();
    auto readback = device_.createBuffer(8 * bricks, VulkanDevice::MemoryUse::Readback);
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
    densityOffset_ = layout.density, emissionOffset_ = layout.emission;
    demandOffset_ = layout.demand, parkOffset_ = layout.park, parkBytes_ = kVolumeParkBytes * paths;
    const std::vector<uint32_t> none(brickVolume_.size(), kNoBrick);
    const std::vector<uint32_t> zeros(brickVolume_.size(), 0);
    VASTRAY_TRY(buffer_.upload(none.data(), brickVolume_.size() * 4, demandOffset_));
    VASTRAY_TRY(buffer_.upload(zeros.data(), zeros.size() * 4, demandOffset_ + brickVolume_.size() * 4));
    const std::vector<uint64_t> density(volumes.size(), layout.density), emission(volumes.size(), layout.emission);
    return writeRecords(volumes, layout.brickOf, layout.majorant, density, emission);
}

Status DeviceVolumes::copyBrick(uint32_t brick, uint32_t slot) {
    const uint64_t brickBytes = 4ull * kVolumeBrickVoxels;
    const Volume& v = (*volumes_)[brickVolume_[brick]];
    const uint64_t local = brick - volumeFirstBrick_[brickVolume_[brick]];
    VASTRAY_TRY(buffer_.upload(v.voxels.data() + local * kVolumeBrickVoxels, brickBytes, densityOffset_ + slot * brickBytes));
    if (!v.emissionVoxels.empty())
        VASTRAY_TRY(buffer_.upload(v.emissionVoxels.data() + local * kVolumeBrickVoxels, brickBytes,
                                   emissionOffset_ + slot * brickBytes));
    return Status::ok();
}

// The region policy: the pool's worth of bricks nearest (in brick cells, Chebyshev distance,
// same volume) to the absent brick the most parked walks wait for (the highest weight; ties:
// the lowest asking path, then the lowest brick) become resident, nearest first, in the slots of
// bricks outside that region. Walks then cross the whole region before they park again, and
// every step loads the brick most waited for, so the walks parked at it go on: a render cannot
// stall. (Loading the most asked-for bricks one by one instead turned the pool over every step
// with little progress: PERF_NOTES 52.)
Result<uint64_t> DeviceVolumes::page(std::span<const uint32_t> demand, StreamingStats& stats) {
    const uint64_t bricks = brickVolume_.size();
    if (!paged() || demand.size() != 2 * bricks) return Status::error("volume paging: demand counters of the wrong size");
    const std::span<const uint32_t> lowestPath = demand.first(bricks), weight = demand.subspan(bricks);
    uint32_t center = kNoBrick;
    for (uint32_t b = 0; b < bricks; ++b) {
        if (lowestPath[b] == kNoBrick || brickSlot_[b] != kNoBrick) continue;
        if (center == kNoBrick || weight[b] > weight[center] ||
            (weight[b] == weight[center] && lowestPath[b] < lowestPath[center]))
            center = b;
    }
    if (center == kNoBrick) return uint64_t(0);
    const uint32_t volume = brickVolume_[center];
    const std::array<uint32_t, 3> cells = (*volumes_)[volume].brickCells;
    auto xyz = [&](uint32_t b) {
        const uint64_t c = brickCell_[b];
        return std::array<int64_t, 3>{int64_t(c % cells[0]), int64_t(c / cells[0] % cells[1]),
                                      int64_t(c / (uint64_t(cells[0]) * cells[1]))};
    };
    const auto at = xyz(center);
    std::vector<std::pair<uint64_t, uint32_t>> region;  // (distance, brick)
    const uint32_t first = volumeFirstBrick_[volume];
    region.reserve((*volumes_)[volume].brickCount());
    for (uint32_t b = first; b < first + (*volumes_)[volume].brickCount(); ++b) {
        const auto p = xyz(b);
        region.push_back({uint64_t(std::max({std::abs(p[0] - at[0]), std::abs(p[1] - at[1]), std::abs(p[2] - at[2])})), b});
    }
    const size_t keep = std::min<size_t>(region.size(), slots_);
    std::nth_element(region.begin(), region.begin() + (keep - 1), region.end());
    region.resize(keep);
    std::sort(region.begin(), region.end());
    std::vector<uint8_t> inRegion(bricks, 0);
    for (const auto& entry : region) inRegion[entry.second] = 1;
    std::vector<uint32_t> free;
    for (uint32_t s = 0; s < slots_; ++s)
        if (slotBrick_[s] == kNoBrick || !inRegion[slotBrick_[s]]) free.push_back(s);
    // Which brick goes to which slot, and the cell tables, first; then the voxels on all cores
    // (one core's writes through the device mapping were most of a step's time).
    std::vector<std::pair<uint32_t, uint32_t>> moves;  // (brick, slot)
    for (const auto& [distance, brick] : region) {
        if (brickSlot_[brick] != kNoBrick) continue;
        if (moves.size() == free.size()) break;
        const uint32_t slot = free[moves.size()];
        if (const uint32_t old = slotBrick_[slot]; old != kNoBrick) {
            brickSlot_[old] = kNoBrick;
            const uint32_t absent = kBrickAbsent | (old - volumeFirstBrick_[brickVolume_[old]]);
            VASTRAY_TRY(buffer_.upload(&absent, 4, tableOffset_[brickVolume_[old]] + 4ull * brickCell_[old]));
        }
        brickSlot_[brick] = slot, slotBrick_[slot] = brick;
        VASTRAY_TRY(buffer_.upload(&slot, 4, tableOffset_[brickVolume_[brick]] + 4ull * brickCell_[brick]));
        moves.push_back({brick, slot});
        stats.hostToDeviceBytes += 4ull * kVolumeBrickVoxels * ((*volumes_)[brickVolume_[brick]].emissionVoxels.empty() ? 1 : 2) + 4;
    }
    std::atomic<bool> failed{false};
    tbb::parallel_for(tbb::blocked_range<size_t>(0, moves.size(), 64), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i != r.end(); ++i)
            if (!copyBrick(moves[i].first, moves[i].second)) failed = true;
    });
    if (failed) return Status::error("volume paging: copying bricks into their slots failed");
    stats.volumeBrickLoads += moves.size();
    return uint64_t(moves.size());
}

}  // namespace vastray::gpu
