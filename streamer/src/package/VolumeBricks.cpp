#include "package/VolumeBricks.h"

#include <algorithm>
#include <cstring>
#include <new>

#include "package/ByteIo.h"
#include "package/PackageFormat.h"
#include "package/PackageHeader.h"
#include "vastray/core/Checksum.h"
#include "vastray/core/VolumeLeaf.h"

namespace vastray {
namespace {

bool inRange(float value) { return value >= 0.0f && value <= kMaxVolumeDensity; }

// The first value of `values` outside [0, 1e18] (NaN included), or -1.
int64_t firstOutOfRange(const float* values) {
    for (uint32_t i = 0; i < kVolumeBrickVoxels; ++i)
        if (!inRange(values[i])) return i;
    return -1;
}

}  // namespace

Status PackageVolumeBricks::readBrick(uint32_t volume, uint32_t brick, float* density, float* emission,
                                      uint8_t* leaves) const {
    if (volume >= volumes_.size())
        return Status::error("volume " + std::to_string(volume) + " does not exist (" + std::to_string(volumes_.size()) +
                             " volumes)");
    const StoredVolumeBricks& v = volumes_[volume];
    const std::string name = v.name + "brick " + std::to_string(brick);
    if (brick >= v.checksum.size())
        return Status::error(name + " does not exist (" + std::to_string(v.checksum.size()) + " bricks)");
    const uint64_t bytes = format::volumeBrickBytes(v.version, v.codec, v.emission), offset = v.firstBrick + brick * bytes;
    alignas(16) uint8_t stored[2 * std::max<uint64_t>(kMaxVolumeLeafBytes, 4 * kVolumeBrickVoxels)];
    if (!file_->read(offset, bytes, stored))
        return Status::error(name + ": cannot read its " + std::to_string(bytes) + " bytes at offset " +
                             std::to_string(offset) + " (the file is shorter than its package says, or unreadable)");
    if (const uint64_t computed = checksum64(stored, bytes); computed != v.checksum[brick])
        return checksumMismatch(name + ":", v.checksum[brick], computed);
    float voxels[2 * kVolumeBrickVoxels];
    if (v.version >= format::kFirstLeafBricksVersion) {
        const uint32_t leafBytes = volumeLeafBytes(v.codec);
        for (uint32_t grid = 0; grid < (v.emission ? 2u : 1u); ++grid)
            if (const std::string problem = decodeVolumeLeaf(v.codec, stored + grid * leafBytes, voxels + grid * kVolumeBrickVoxels);
                !problem.empty())
                return Status::error(name + (grid ? " emission" : "") + " (a NanoVDB " + volumeCodecName(v.codec) +
                                     " leaf): " + problem);
        if (leaves) std::memcpy(leaves, stored, bytes);
    } else {
        std::memcpy(voxels, stored, bytes);
    }
    if (const int64_t bad = firstOutOfRange(voxels); bad >= 0)
        return Status::error(name + " voxel " + std::to_string(bad) + " has density " + std::to_string(voxels[bad]) +
                             " (not in [0, 1e18])");
    // The majorants were computed from the recorded maximum: a brick must not exceed it (nor be
    // below it, so that they are the ones the voxels give).
    const float largest = *std::max_element(voxels, voxels + kVolumeBrickVoxels);
    if (largest != v.maximum[brick])
        return Status::error(name + ": its largest density " + std::to_string(largest) +
                             " is not the one its brick index records (" + std::to_string(v.maximum[brick]) + ")");
    std::memcpy(density, voxels, 4 * kVolumeBrickVoxels);
    if (v.emission) {
        const float* glow = voxels + kVolumeBrickVoxels;
        if (const int64_t bad = firstOutOfRange(glow); bad >= 0)
            return Status::error(name + " emission voxel " + std::to_string(bad) + " has the value " +
                                 std::to_string(glow[bad]) + " (not in [0, 1e18])");
        std::memcpy(emission, glow, 4 * kVolumeBrickVoxels);
    }
    return Status::ok();
}

Status readVolumeTable(const PackageFile& file, uint32_t version, const PackageVolume& p, const std::string& name,
                       Volume& volume, StoredVolumeBricks& bricks) {
    const uint64_t cells = p.volume.cellCount(), count = p.brickCount;
    const uint64_t tableBytes = format::volumeTableBytes(format::kFirstBrickwiseVersion, cells, count);
    std::vector<uint8_t> table;
    try {
        table.reserve(tableBytes);
        volume.brickOf.reserve(cells);
        volume.majorant.reserve(cells);
        bricks.checksum.reserve(count);
        bricks.maximum.reserve(count);
    } catch (const std::bad_alloc&) {
        return Status::error(name + "out of host memory for its brick table of " + std::to_string(tableBytes) + " bytes");
    }
    if (!file.read(p.offset, tableBytes, table)) return Status::error(name + "cannot read its brick table");
    if (const uint64_t computed = checksum64(table.data(), table.size()); computed != p.checksum)
        return checksumMismatch(name + "brick table", p.checksum, computed);
    ByteReader in(table.data(), table.size());
    in.getArray(volume.brickOf, cells);
    bricks.checksum.resize(count);
    bricks.maximum.resize(count);
    for (uint64_t b = 0; b < count; ++b) {
        uint32_t reserved = 0;
        in.get(bricks.checksum[b]), in.get(bricks.maximum[b]), in.get(reserved);
        const std::string brick = name + "brick " + std::to_string(b) + ": ";
        if (reserved != 0) return Status::error(brick + "reserved index field is not 0");
        if (!inRange(bricks.maximum[b]))
            return Status::error(brick + "largest density " + std::to_string(bricks.maximum[b]) + " is not in [0, 1e18]");
    }
    if (!in.ok()) return Status::error(name + "truncated brick table");
    if (const std::string problem = checkBrickTable(volume.brickOf, count); !problem.empty())
        return Status::error(name + problem);
    computeVolumeMajorants(volume, bricks.maximum);
    bricks.name = name;
    bricks.firstBrick = p.offset + tableBytes;
    bricks.emission = p.hasEmission;
    bricks.version = version;
    bricks.codec = p.volume.codec;
    return Status::ok();
}

}  // namespace vastray
