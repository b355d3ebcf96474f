#include "DeviceVolumes.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <array>
#include <numeric>
#include <string>

#include "PoolLayout.h"
#include "vastray/core/Blackbody.h"
#include "vastray/core/ByteSize.h"
#include "vastray/core/VolumeLeaf.h"

namespace vastray::gpu {
namespace {

// The blackbody table (core/Blackbody.h) after a layout's last byte, in a scene with an emission
// grid: VolumeShape does not tell a temperature grid from a radiance one, so such a scene counts
// the table's 48 KiB (12 bricks with emission) either way; a scene without one pays nothing.
uint64_t blackbodyBytes(std::span<const VolumeShape> shapes) {
    for (const VolumeShape& s : shapes)
        if (s.emission) return 12ull * kBlackbodyTableSize;
    return 0;
}

// How much the pager wants an absent brick: kWaitScore per parked walk waiting for it, 1 per walk
// asking for it ahead (common/Volume.glsl's requestBrick).
constexpr uint64_t kWaitScore = 4;

// A step loads a region rather than the waited bricks when those would take more than this
// fraction's inverse of the slots free of kept bricks: scattered waited bricks filling most of
// the free slots serve each walk a cell, where a region serves its walks a box. On lavapipe
// (bench/volume_cloud clouds of 1,998 and 14,076 bricks, a fifth to a half of them resident, 4
// and 16 spp, 64x64 to 128x128 pixels) 3 took 0.4-36 % fewer loads and 2-40 % fewer steps than 1
// (a region only when the waited bricks outnumber the free slots) in all ten renders measured;
// in a build that kept 40 % of the budget for the volumes, 2 and 4 did about as well, 1.4 worse,
// 5 more loads at 4 spp, and a third of the whole pool instead of the free slots took 3 % more
// steps over eight of them.
constexpr uint64_t kRegionAboveFreeShare = 3;
uint64_t askWeight(std::span<const uint32_t> waits, std::span<const uint32_t> ahead, uint32_t brick) {
    return kWaitScore * waits[brick] + ahead[brick];
}

// The most slots whose paged layout fits `bytes` (0 when not even the tables do).
uint64_t slotsFitting(std::span<const VolumeShape> shapes, uint64_t bytes, uint64_t paths) {
    const uint64_t base = pagedVolumeBytes(shapes, 0, paths);
    if (bytes < base) return 0;
    bool emission = false;
    for (const VolumeShape& s : shapes) emission = emission || s.emission;
    // The bytes grow with the slots (in whole granules): the most that fit, by bisection.
    const uint64_t perSlot = volumeSlotBytes(shapes) * (emission ? 2 : 1);
    uint64_t fits = 0, over = bytes / perSlot + 1;  // (over: more than `bytes` in the pool alone)
    while (over - fits > 1) {
        const uint64_t middle = fits + (over - fits) / 2;
        (pagedVolumeBytes(shapes, middle, paths) <= bytes ? fits : over) = middle;
    }
    return fits;
}

}  // namespace

std::vector<VolumeShape> volumeShapes(std::span<const Volume> volumes) {
    std::vector<VolumeShape> shapes;
    for (const Volume& v : volumes)
        shapes.push_back({v.cellCount(), v.brickCount(), v.hasEmission(), volumeDeviceLeafBytes(deviceVolumeCodec(v))});
    return shapes;
}

uint64_t inCoreVolumeBytes(std::span<const VolumeShape> shapes) {
    return shapes.empty() ? 0 : granules(volumeLayout(shapes).totalBytes + blackbodyBytes(shapes));
}

uint64_t pagedVolumeBytes(std::span<const VolumeShape> shapes, uint64_t slots, uint64_t paths) {
    uint64_t bricks = 0;
    for (const VolumeShape& s : shapes) bricks += s.bricks;
    // The demand counters' readback: 2 per brick, 1 per slot.
    return granules(pagedVolumeLayout(shapes, slots, paths).totalBytes + blackbodyBytes(shapes)) +
           granules(8 * bricks + 4 * slots);
}

namespace {

// Stored bricks in a box of brick cells in O(1): a summed-volume table, (n + 1)^3 entries.
class BrickCounts {
public:
    using Box = std::array<std::array<int64_t, 3>, 2>;  // [lo, hi) per axis

    explicit BrickCounts(const Volume& volume)
        : n_{volume.brickCells[0], volume.brickCells[1], volume.brickCells[2]},
          sum_(uint64_t(n_[0] + 1) * (n_[1] + 1) * (n_[2] + 1), 0) {
        for (int64_t z = 0; z < n_[2]; ++z)
            for (int64_t y = 0; y < n_[1]; ++y)
                for (int64_t x = 0; x < n_[0]; ++x)
                    at(x + 1, y + 1, z + 1) =
                        (volume.brickOf[uint64_t(x + n_[0] * (y + n_[1] * z))] != kNoBrick ? 1u : 0u) +
                        at(x, y + 1, z + 1) + at(x + 1, y, z + 1) + at(x + 1, y + 1, z) - at(x, y, z + 1) -
                        at(x, y + 1, z) - at(x + 1, y, z) + at(x, y, z);
    }
    const std::array<int64_t, 3>& cells() const { return n_; }
    uint64_t count(const Box& b) const {
        const auto& [l, h] = b;
        return uint64_t(at(h[0], h[1], h[2])) - at(l[0], h[1], h[2]) - at(h[0], l[1], h[2]) - at(h[0], h[1], l[2]) +
               at(l[0], l[1], h[2]) + at(l[0], h[1], l[2]) + at(h[0], l[1], l[2]) - at(l[0], l[1], l[2]);
    }
    Box grown(Box b) const {
        for (int a = 0; a < 3; ++a)
            b[0][a] = std::max<int64_t>(0, b[0][a] - 1), b[1][a] = std::min(n_[a], b[1][a] + 1);
        return b;
    }

private:
    uint64_t index(int64_t x, int64_t y, int64_t z) const {
        return uint64_t(x + (n_[0] + 1) * (y + (n_[1] + 1) * z));
    }
    uint32_t& at(int64_t x, int64_t y, int64_t z) { return sum_[index(x, y, z)]; }
    uint32_t at(int64_t x, int64_t y, int64_t z) const { return sum_[index(x, y, z)]; }
    std::array<int64_t, 3> n_;
    std::vector<uint32_t> sum_;
};

// One way of cutting the volume into regions (volumeRegions): a box whose grown box holds more
// than `slots` bricks is cut across its longest axis at the first plane with at least 1/parts of
// its bricks before it; parts is 2 (halves), or with `poolParts` the pools the grown box would
// fill (2 at least: a box of 2.2 pools gives three regions of about 0.73 of the pool, not four
// of 0.55).
VolumeRegions cutRegions(const Volume& volume, const BrickCounts& counts, uint32_t slots, bool poolParts) {
    using Box = BrickCounts::Box;
    const std::array<int64_t, 3>& n = counts.cells();
    VolumeRegions regions;
    regions.home.assign(volume.brickCount(), kNoBrick);
    std::vector<Box> boxes{Box{std::array<int64_t, 3>{0, 0, 0}, n}};
    while (!boxes.empty()) {
        const Box box = boxes.back();
        boxes.pop_back();
        const uint64_t inside = counts.count(box);
        if (inside == 0) continue;
        const Box outer = counts.grown(box);
        const uint64_t grownBricks = counts.count(outer);
        int axis = 0;
        for (int a = 1; a < 3; ++a)
            if (box[1][a] - box[0][a] > box[1][axis] - box[0][axis]) axis = a;
        if (grownBricks > slots && box[1][axis] - box[0][axis] > 1) {
            const uint64_t parts = poolParts ? std::max<uint64_t>(2, (grownBricks + slots - 1) / slots) : 2;
            int64_t lo = box[0][axis] + 1, hi = box[1][axis] - 1;  // the plane stays inside the box
            while (lo < hi) {
                const int64_t mid = (lo + hi) / 2;
                Box before = box;
                before[1][axis] = mid;
                if (parts * counts.count(before) >= inside) hi = mid;
                else lo = mid + 1;
            }
            Box first = box, second = box;
            first[1][axis] = lo, second[0][axis] = lo;
            boxes.push_back(second);
            boxes.push_back(first);
            continue;
        }
        // A box of one cell grows to at most 27: slots >= 27 always ends here.
        const uint32_t region = uint32_t(regions.bricks.size());
        std::vector<uint32_t>& bricks = regions.bricks.emplace_back();
        for (int64_t z = outer[0][2]; z < outer[1][2]; ++z)
            for (int64_t y = outer[0][1]; y < outer[1][1]; ++y)
                for (int64_t x = outer[0][0]; x < outer[1][0]; ++x) {
                    const uint32_t brick = volume.brickOf[uint64_t(x + n[0] * (y + n[1] * z))];
                    if (brick == kNoBrick) continue;
                    bricks.push_back(brick);
                    if (x >= box[0][0] && x < box[1][0] && y >= box[0][1] && y < box[1][1] && z >= box[0][2] &&
                        z < box[1][2])
                        regions.home[brick] = region;
                }
    }
    return regions;
}

uint64_t regionBricks(const VolumeRegions& regions) {
    uint64_t bricks = 0;
    for (const std::vector<uint32_t>& r : regions.bricks) bricks += r.size();
    return bricks;
}

}  // namespace

// Fewer regions serve more of the waiting walks each (a step makes one resident); which way of
// cutting gives fewer depends on the volume's shape and the pool, so both are tried (ties: the
// fewer bricks, then halves). PERF_NOTES 52's cloud at 582 slots: 7 regions against 8 halves
// (166 steps against 192 at 64x64, 4 spp); tests/gpu/DeviceVolumesTest.cpp has volumes where
// each wins.
VolumeRegions volumeRegions(const Volume& volume, uint32_t slots) {
    const BrickCounts counts(volume);
    VolumeRegions halves = cutRegions(volume, counts, slots, false);
    VolumeRegions pools = cutRegions(volume, counts, slots, true);
    const auto rank = [](const VolumeRegions& r) { return std::pair(r.bricks.size(), regionBricks(r)); };
    return rank(pools) < rank(halves) ? std::move(pools) : std::move(halves);
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
            } else if (const uint64_t slots = std::min<uint64_t>(slotsFitting(shapes, bytes, paths),
                                                                 slotLimit_ > 0 ? slotLimit_ : kNoBrick - 1);
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
                                   std::span<const uint64_t> emission, uint64_t slotBytes, uint64_t blackbody) {
    const uint64_t base = buffer_.address();
    std::vector<WavefrontVolume> records;
    uint32_t bricks = 0;
    for (size_t i = 0; i < volumes.size(); ++i) {
        const Volume& v = volumes[i];
        WavefrontVolume& r = records.emplace_back();
        r.brickOf = base + brickOf[i], r.majorant = base + majorant[i], r.voxels = base + voxels[i];
        r.emissionVoxels = v.hasEmission() ? base + emission[i] : 0;
        std::copy(v.worldToIndex.begin(), v.worldToIndex.end(), r.worldToIndex);
        r.originX = v.origin[0], r.originY = v.origin[1], r.originZ = v.origin[2];
        r.cellsX = v.brickCells[0], r.cellsY = v.brickCells[1], r.cellsZ = v.brickCells[2];
        r.albedoR = v.material.albedo[0], r.albedoG = v.material.albedo[1], r.albedoB = v.material.albedo[2];
        r.densityScale = v.material.densityScale, r.anisotropy = v.material.anisotropy;
        r.emitR = v.material.emission[0], r.emitG = v.material.emission[1], r.emitB = v.material.emission[2];
        r.brickBase = bricks;
        // Its leaves' stride (a multiple of 16) and codec in the low bits.
        const VolumeCodec codec = deviceVolumeCodec(v);
        r.leaves = uint32_t(slotBytes > 0 ? slotBytes : volumeDeviceLeafBytes(codec)) | uint32_t(codec);
        r.blackbody = v.hasEmission() && v.material.temperature ? base + blackbody : 0;
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

Status DeviceVolumes::uploadAllBricks(const Volume& v, uint64_t voxels, uint64_t emission, StreamingStats& stats) {
    const VolumeCodec codec = deviceVolumeCodec(v);
    const uint64_t leafBytes = volumeLeafBytes(codec), deviceBytes = volumeDeviceLeafBytes(codec), bricks = v.brickCount();
    const std::vector<std::array<int32_t, 3>> origins = volumeBrickOrigins(v);
    // Read (from the package, or encoded from memory) a batch at a time (35 MiB of host memory at
    // most: the whole leaves, then what the device keeps of them), on all cores.
    constexpr uint64_t kBatch = 4096;
    const uint64_t perBrick = leafBytes * (v.hasEmission() ? 2 : 1);
    std::vector<uint8_t> leaves(std::min(bricks, kBatch) * perBrick);
    std::vector<uint8_t> density(std::min(bricks, kBatch) * deviceBytes), glow(v.hasEmission() ? density.size() : 0);
    for (uint64_t first = 0; first < bricks; first += kBatch) {
        const uint64_t count = std::min(kBatch, bricks - first);
        std::vector<Status> failed(count);
        tbb::parallel_for(tbb::blocked_range<uint64_t>(0, count, 64), [&](const tbb::blocked_range<uint64_t>& r) {
            float values[2 * kVolumeBrickVoxels];
            for (uint64_t i = r.begin(); i != r.end(); ++i) {
                uint8_t* at = leaves.data() + i * perBrick;
                failed[i] = readVolumeLeaves(v, codec, first + i, origins[first + i], values,
                                             glow.empty() ? nullptr : values + kVolumeBrickVoxels, at);
                const uint8_t* kept = at + kVolumeLeafDeviceOffset;
                std::memcpy(density.data() + i * deviceBytes, kept, deviceBytes);
                if (!glow.empty()) std::memcpy(glow.data() + i * deviceBytes, kept + leafBytes, deviceBytes);
            }
        });
        for (const Status& f : failed) VASTRAY_TRY(f);
        if (v.bricks.source) stats.volumeBricksRead += count;
        VASTRAY_TRY(buffer_.upload(density.data(), count * deviceBytes, voxels + first * deviceBytes));
        if (!glow.empty()) VASTRAY_TRY(buffer_.upload(glow.data(), count * deviceBytes, emission + first * deviceBytes));
    }
    return Status::ok();
}

Status DeviceVolumes::uploadBlackbody(const std::vector<Volume>& volumes, uint64_t offset, StreamingStats& stats) {
    for (const Volume& v : volumes)
        if (v.hasEmission() && v.material.temperature) {
            const std::vector<float>& table = blackbodyTable();
            stats.hostToDeviceBytes += table.size() * 4;
            return buffer_.upload(table.data(), table.size() * 4, offset);
        }
    return Status::ok();
}

Status DeviceVolumes::buildInCore(const std::vector<Volume>& volumes, StreamingStats& stats) {
    const std::vector<VolumeShape> shapes = volumeShapes(volumes);
    const VolumeLayout layout = volumeLayout(shapes);
    VASTRAY_TRY(allocate(volumes, layout.totalBytes + blackbodyBytes(shapes)));
    VASTRAY_TRY(uploadBlackbody(volumes, layout.totalBytes, stats));
    for (size_t i = 0; i < volumes.size(); ++i) {
        const Volume& v = volumes[i];
        VASTRAY_TRY(uploadAllBricks(v, layout.voxels[i], layout.emission[i], stats));
        VASTRAY_TRY(buffer_.upload(v.brickOf.data(), v.brickOf.size() * 4, layout.brickOf[i]));
        VASTRAY_TRY(buffer_.upload(v.majorant.data(), v.majorant.size() * 4, layout.majorant[i]));
        stats.hostToDeviceBytes += (v.brickOf.size() + v.majorant.size()) * 4 +
                                   v.brickCount() * volumeDeviceLeafBytes(deviceVolumeCodec(v)) * (v.hasEmission() ? 2 : 1);
    }
    return writeRecords(volumes, layout.brickOf, layout.majorant, layout.voxels, layout.emission, 0, layout.totalBytes);
}

Status DeviceVolumes::buildPaged(const std::vector<Volume>& volumes, uint32_t slots, uint64_t paths,
                                 StreamingStats& stats) {
    const std::vector<VolumeShape> shapes = volumeShapes(volumes);
    const PagedVolumeLayout layout = pagedVolumeLayout(shapes, slots, paths);
    VASTRAY_TRY(allocate(volumes, layout.totalBytes + blackbodyBytes(shapes)));
    VASTRAY_TRY(uploadBlackbody(volumes, layout.totalBytes, stats));
    uint64_t bricks = 0;
    for (const Volume& v : volumes) bricks += v.brickCount();
    auto readback = device_.createBuffer(8 * bricks + 4ull * slots, VulkanDevice::MemoryUse::Readback);
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
    slotUsed_.assign(slots, 0);
    brickRegion_.assign(brickVolume_.size(), kNoBrick);
    regionBricks_.clear();
    for (size_t i = 0; i < volumes.size(); ++i) {
        VolumeRegions regions = volumeRegions(volumes[i], slots);
        const uint32_t first = volumeFirstBrick_[i], base = uint32_t(regionBricks_.size());
        for (uint64_t b = 0; b < regions.home.size(); ++b) brickRegion_[first + b] = base + regions.home[b];
        for (std::vector<uint32_t>& bricks : regions.bricks) {
            for (uint32_t& brick : bricks) brick += first;
            regionBricks_.push_back(std::move(bricks));
        }
    }
    // The host cache of whole leaves (read from the package, or encoded from the voxels in memory).
    bool glows = false;
    uint64_t leafBytes = 0;
    for (const Volume& v : volumes)
        glows = glows || v.hasEmission(), leafBytes = std::max<uint64_t>(leafBytes, volumeLeafBytes(deviceVolumeCodec(v)));
    slotBytes_ = volumeSlotBytes(shapes);
    cacheStride_ = leafBytes * (glows ? 2 : 1);
    const uint64_t entries = std::min<uint64_t>(brickVolume_.size(), std::max<uint64_t>(slots, hostCacheBytes_ / cacheStride_));
    // Not value-initialized: the pages of entries never used are never touched (host memory grows
    // with the bricks read, up to the bound).
    cache_.reset(entries > 0 ? new uint8_t[entries * cacheStride_] : nullptr);
    entryBrick_.assign(entries, kNoBrick), entryStep_.assign(entries, 0), entryReferenced_.assign(entries, 0);
    brickEntry_.assign(entries > 0 ? brickVolume_.size() : 0, kNoBrick);
    hand_ = 0, step_ = 0;
    densityOffset_ = layout.density, emissionOffset_ = layout.emission;
    demandOffset_ = layout.demand, parkOffset_ = layout.park, parkBytes_ = kVolumeParkBytes * paths;
    const std::vector<uint32_t> zeros(demandCount(), 0);  // no brick asked for
    VASTRAY_TRY(buffer_.upload(zeros.data(), zeros.size() * 4, demandOffset_));
    const std::vector<uint64_t> density(volumes.size(), layout.density), emission(volumes.size(), layout.emission);
    return writeRecords(volumes, layout.brickOf, layout.majorant, density, emission, slotBytes_, layout.totalBytes);
}

Status DeviceVolumes::copyBrick(const Move& move) {
    const uint64_t bytes = volumeDeviceLeafBytes(deviceVolumeCodec((*volumes_)[brickVolume_[move.brick]]));
    VASTRAY_TRY(buffer_.upload(move.density + kVolumeLeafDeviceOffset, bytes, densityOffset_ + move.slot * slotBytes_));
    if (move.emission)
        VASTRAY_TRY(buffer_.upload(move.emission + kVolumeLeafDeviceOffset, bytes, emissionOffset_ + move.slot * slotBytes_));
    return Status::ok();
}

// A cache entry for a brick read this step: a free one, else the next the clock finds that this
// step does not copy from and that was not used since the hand last passed it.
uint32_t DeviceVolumes::takeCacheEntry() {
    const uint32_t entries = uint32_t(entryBrick_.size());
    for (uint64_t tries = 0; tries < 3ull * entries; ++tries) {
        const uint32_t e = hand_;
        hand_ = (hand_ + 1) % entries;
        if (entryBrick_[e] == kNoBrick) return e;
        if (entryStep_[e] == step_) continue;
        if (entryReferenced_[e]) {
            entryReferenced_[e] = 0;
            continue;
        }
        brickEntry_[entryBrick_[e]] = kNoBrick, entryBrick_[e] = kNoBrick;
        return e;
    }
    return kNoBrick;
}

Status DeviceVolumes::placeInHost(Move& move, std::vector<std::pair<uint32_t, uint32_t>>& reads) {
    const Volume& v = (*volumes_)[brickVolume_[move.brick]];
    uint32_t e = brickEntry_[move.brick];
    if (e == kNoBrick) {
        e = takeCacheEntry();
        if (e == kNoBrick) return Status::error("volume paging: the host brick cache has no entry free");
        brickEntry_[move.brick] = e, entryBrick_[e] = move.brick;
        reads.push_back({move.brick, e});
    }
    entryStep_[e] = step_, entryReferenced_[e] = 1;
    move.density = cache_.get() + uint64_t(e) * cacheStride_;
    move.emission = v.hasEmission() ? move.density + volumeLeafBytes(deviceVolumeCodec(v)) : nullptr;
    return Status::ok();
}

// The demand policy: each step loads the absent bricks parked walks wait for, the most asked for
// first (askWeight), then those walks ask for ahead (the next cells along their rays: a step
// fewer for a walk that goes on), into the empty slots first, then into the slots of bricks no
// parked walk keeps (keepCell in common/Volume.glsl: the resident bricks a parked walk reads when
// it resumes), least recently used first. A brick a parked walk keeps is not evicted, so a walk's
// bricks gather until it goes on, and a brick no ray reaches is never read. When the bricks walks
// wait for would take more than 1/kRegionAboveFreeShare of those slots (walks all over a dense
// cloud), the step loads a region instead (regionLoads, in the slots of the bricks outside it):
// every walk waiting in it can go on, so a render cannot stall. PERF_NOTES 61 measured the choices
// (loading a region every step: PERF_NOTES 52; neighbours of the waited bricks besides the asks
// ahead: more bricks read, no fewer steps).
Result<uint64_t> DeviceVolumes::page(std::span<const uint32_t> demand, StreamingStats& stats) {
    const uint64_t bricks = brickVolume_.size();
    if (!paged() || demand.size() != demandCount())
        return Status::error("volume paging: demand counters of the wrong size");
    const std::span<const uint32_t> waits = demand.first(bricks), ahead = demand.subspan(bricks, bricks),
                                    kept = demand.subspan(2 * bricks);
    ++step_;
    std::vector<uint32_t> wanted, later;  // absent: waited for, asked for ahead only
    for (uint32_t b = 0; b < bricks; ++b)
        if (brickSlot_[b] == kNoBrick && waits[b] > 0) wanted.push_back(b);
        else if (brickSlot_[b] == kNoBrick && ahead[b] > 0) later.push_back(b);
    if (wanted.empty()) return uint64_t(0);
    const std::vector<uint32_t> slots = slotsToFill(kept);
    if (kRegionAboveFreeShare * wanted.size() > slots.size()) {
        const auto [region, outside] = regionLoads(waits, ahead);
        return load(region, outside, stats);
    }
    auto byWeight = [&](uint32_t a, uint32_t b) { return askWeight(waits, ahead, a) > askWeight(waits, ahead, b); };
    std::stable_sort(wanted.begin(), wanted.end(), byWeight);
    std::stable_sort(later.begin(), later.end(), byWeight);
    wanted.insert(wanted.end(), later.begin(), later.end());
    const size_t count = std::min(wanted.size(), slots.size());
    return load(std::span(wanted).first(count), std::span(slots).first(count), stats);
}

std::vector<uint32_t> DeviceVolumes::slotsToFill(std::span<const uint32_t> kept) {
    std::vector<uint32_t> empty, idle;
    for (uint32_t s = 0; s < slots_; ++s) {
        if (slotBrick_[s] == kNoBrick) empty.push_back(s);
        else if (kept[s] > 0) slotUsed_[s] = step_;
        else idle.push_back(s);
    }
    std::stable_sort(idle.begin(), idle.end(), [&](uint32_t a, uint32_t b) { return slotUsed_[a] < slotUsed_[b]; });
    empty.insert(empty.end(), idle.begin(), idle.end());
    return empty;
}

std::pair<std::vector<uint32_t>, std::vector<uint32_t>> DeviceVolumes::regionLoads(std::span<const uint32_t> waits,
                                                                                   std::span<const uint32_t> ahead) {
    std::vector<uint64_t> score(regionBricks_.size(), 0);
    std::vector<uint8_t> waited(regionBricks_.size(), 0);
    for (uint32_t b = 0; b < brickVolume_.size(); ++b) {
        if (brickSlot_[b] != kNoBrick || (waits[b] == 0 && ahead[b] == 0)) continue;
        score[brickRegion_[b]] += askWeight(waits, ahead, b);
        if (waits[b] > 0) waited[brickRegion_[b]] = 1;
    }
    uint32_t chosen = kNoBrick;
    for (uint32_t r = 0; r < score.size(); ++r)
        if (waited[r] && (chosen == kNoBrick || score[r] > score[chosen])) chosen = r;
    std::pair<std::vector<uint32_t>, std::vector<uint32_t>> loads;
    if (chosen == kNoBrick) return loads;
    std::vector<uint8_t> inRegion(brickVolume_.size(), 0);
    for (const uint32_t brick : regionBricks_[chosen]) {
        inRegion[brick] = 1;
        if (brickSlot_[brick] == kNoBrick) loads.first.push_back(brick);
    }
    // Empty slots first, then those of bricks outside the region in slot order (least recently
    // used first took 6 % more steps and 3 % more loads on PERF_NOTES 52's cloud).
    std::vector<uint32_t> outside;
    for (uint32_t s = 0; s < slots_; ++s)
        if (slotBrick_[s] == kNoBrick) loads.second.push_back(s);
        else if (!inRegion[slotBrick_[s]]) outside.push_back(s);
    loads.second.insert(loads.second.end(), outside.begin(), outside.end());
    loads.second.resize(std::min(loads.second.size(), loads.first.size()));
    return loads;
}

Result<uint64_t> DeviceVolumes::load(std::span<const uint32_t> bricks, std::span<const uint32_t> slots,
                                     StreamingStats& stats) {
    // Which brick goes to which slot, and the cell tables, first; then the voxels on all cores
    // (one core's writes through the device mapping were most of a step's time).
    if (bricks.size() > slots.size()) return Status::error("volume paging: a region holds more bricks than the pool");
    std::vector<Move> moves;
    std::vector<std::pair<uint32_t, uint32_t>> reads;  // (brick, cache entry): read from the package first
    for (size_t i = 0; i < bricks.size(); ++i) {
        const uint32_t brick = bricks[i], slot = slots[i];
        if (const uint32_t old = slotBrick_[slot]; old != kNoBrick) {
            brickSlot_[old] = kNoBrick;
            const uint32_t absent = kBrickAbsent | (old - volumeFirstBrick_[brickVolume_[old]]);
            VASTRAY_TRY(buffer_.upload(&absent, 4, tableOffset_[brickVolume_[old]] + 4ull * brickCell_[old]));
        }
        brickSlot_[brick] = slot, slotBrick_[slot] = brick, slotUsed_[slot] = step_;
        VASTRAY_TRY(buffer_.upload(&slot, 4, tableOffset_[brickVolume_[brick]] + 4ull * brickCell_[brick]));
        Move& move = moves.emplace_back(Move{brick, slot, nullptr, nullptr});
        if (Status placed = placeInHost(move, reads); !placed) {
            volumes_.reset();  // the cell tables name slots that will not be filled
            return placed;
        }
        stats.hostToDeviceBytes += volumeDeviceLeafBytes(deviceVolumeCodec((*volumes_)[brickVolume_[brick]])) * (move.emission ? 2 : 1) + 4;
    }
    // The bricks not in the host cache: from their package (pread, checksum, voxel checks), or
    // encoded from the voxels in memory.
    std::vector<Status> readFailed(reads.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, reads.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
        float values[2 * kVolumeBrickVoxels];
        for (size_t i = r.begin(); i != r.end(); ++i) {
            const auto [brick, entry] = reads[i];
            const uint32_t volume = brickVolume_[brick];
            const Volume& v = (*volumes_)[volume];
            readFailed[i] = readVolumeLeaves(v, deviceVolumeCodec(v), brick - volumeFirstBrick_[volume],
                                             volumeCellOrigin(v, brickCell_[brick]), values,
                                             v.hasEmission() ? values + kVolumeBrickVoxels : nullptr,
                                             cache_.get() + uint64_t(entry) * cacheStride_);
        }
    });
    for (const auto& [brick, entry] : reads)
        if ((*volumes_)[brickVolume_[brick]].bricks.source) ++stats.volumeBricksRead;
    for (const Status& f : readFailed)
        if (!f) {
            volumes_.reset();  // slots and cache entries name bricks they do not hold: built anew next time
            return f;
        }
    std::atomic<bool> failed{false};
    tbb::parallel_for(tbb::blocked_range<size_t>(0, moves.size(), 64), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i != r.end(); ++i)
            if (!copyBrick(moves[i])) failed = true;
    });
    if (failed) return Status::error("volume paging: copying bricks into their slots failed");
    stats.volumeBrickLoads += moves.size();
    return uint64_t(moves.size());
}

}  // namespace vastray::gpu
