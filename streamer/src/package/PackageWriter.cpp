#include "package/PackageWriter.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "package/ByteIo.h"
#include "package/PackageFormat.h"
#include "package/PackageHeader.h"
#include "vastray/core/Checksum.h"

namespace vastray {
namespace {

class TempFile {
public:
    explicit TempFile(std::string path) : path_(std::move(path)) { file_ = std::fopen(path_.c_str(), "wb"); }
    ~TempFile() {
        if (file_) std::fclose(file_);
        if (!committed_) std::remove(path_.c_str());
    }
    bool isOpen() const { return file_ != nullptr; }
    bool write(const std::vector<uint8_t>& bytes) {
        return bytes.empty() || std::fwrite(bytes.data(), 1, bytes.size(), file_) == bytes.size();
    }
    // Flushes, closes and renames onto `target`.
    Status commit(const std::string& target) {
        const bool flushed = std::fflush(file_) == 0;
        const bool closed = std::fclose(file_) == 0;
        file_ = nullptr;
        if (!flushed || !closed) return Status::error(target + ": write failed: " + std::strerror(errno));
        std::error_code error;
        std::filesystem::rename(path_, target, error);
        if (error) return Status::error(target + ": cannot rename temporary file: " + error.message());
        committed_ = true;
        return Status::ok();
    }

private:
    std::string path_;
    std::FILE* file_ = nullptr;
    bool committed_ = false;
};

// A volume's data (format version 6): its cell table; its brick index, per brick the XXH64 of
// its bytes, its largest density and a reserved 0; then each brick's densities and emission.
std::vector<uint8_t> serializeVolumeData(const Volume& v) {
    const uint64_t bricks = v.brickCount(), brickBytes = format::volumeBrickBytes(v.hasEmission());
    ByteWriter out;
    out.putArray(v.brickOf);
    std::vector<uint8_t> brick(brickBytes);
    for (uint64_t b = 0; b < bricks; ++b) {
        const float* density = v.voxels.data() + b * kVolumeBrickVoxels;
        std::memcpy(brick.data(), density, 4 * kVolumeBrickVoxels);
        if (v.hasEmission())
            std::memcpy(brick.data() + 4 * kVolumeBrickVoxels, v.emissionVoxels.data() + b * kVolumeBrickVoxels,
                        4 * kVolumeBrickVoxels);
        out.put(checksum64(brick.data(), brick.size()));
        out.put(*std::max_element(density, density + kVolumeBrickVoxels));
        out.put(uint32_t(0));
    }
    for (uint64_t b = 0; b < bricks; ++b) {
        out.putBytes(v.voxels.data() + b * kVolumeBrickVoxels, 4 * kVolumeBrickVoxels);
        if (v.hasEmission()) out.putBytes(v.emissionVoxels.data() + b * kVolumeBrickVoxels, 4 * kVolumeBrickVoxels);
    }
    return std::move(out.bytes());
}

}  // namespace

Status writePackage(const std::string& path, PackageInfo& info, const std::vector<std::vector<uint8_t>>& blobs) {
    const std::vector<uint8_t> materials = serializeMaterials(info.materials);
    std::vector<uint8_t> tree(info.topTree.size() * sizeof(KdNode));
    std::memcpy(tree.data(), info.topTree.data(), tree.size());

    SectionLayout layout;
    layout.materialCount = uint32_t(info.materials.size());
    layout.topNodeCount = uint32_t(info.topTree.size());
    layout.chunkCount = uint32_t(info.chunks.size());
    layout.materialsOffset = format::kHeaderBytes;
    layout.treeOffset = layout.materialsOffset + materials.size();
    layout.directoryOffset = layout.treeOffset + tree.size();
    const std::vector<uint8_t> cameras = serializeCameras(info.cameras);
    layout.cameraCount = uint32_t(info.cameras.size());
    layout.camerasOffset = layout.directoryOffset + uint64_t(info.chunks.size()) * format::kDirectoryEntryBytes;
    layout.camerasChecksum = checksum64(cameras.data(), cameras.size());
    layout.volumeCount = uint32_t(info.volumes.size());
    layout.volumesOffset = layout.camerasOffset + cameras.size();
    const std::vector<uint8_t> lights = serializeLights(info.lights);
    layout.lightCount = uint32_t(info.lights.size());
    layout.blobsOffset = layout.volumesOffset + uint64_t(layout.volumeCount) * format::kVolumeRecordBytes + lights.size();
    uint64_t offset = layout.blobsOffset;
    for (size_t i = 0; i < info.chunks.size(); ++i) {
        info.chunks[i].offset = offset;
        info.chunks[i].size = blobs[i].size();
        info.chunks[i].checksum = checksum64(blobs[i].data(), blobs[i].size());
        offset += blobs[i].size();
    }
    std::vector<std::vector<uint8_t>> volumeData;
    for (PackageVolume& p : info.volumes) {
        volumeData.push_back(serializeVolumeData(p.volume));
        p.brickCount = uint32_t(p.volume.brickCount());
        p.hasEmission = p.volume.hasEmission();
        p.offset = offset, p.size = volumeData.back().size();
        p.checksum = checksum64(volumeData.back().data(),
                                format::volumeTableBytes(format::kVersion, p.volume.cellCount(), p.brickCount));
        offset += p.size;
    }
    const std::vector<uint8_t> volumes = serializeVolumeRecords(info.volumes);
    layout.volumesChecksum = checksum64(volumes.data(), volumes.size());
    info.fileBytes = offset;
    info.formatVersion = format::kVersion;
    const std::vector<uint8_t> directory = serializeDirectory(info.chunks);
    layout.materialsChecksum = checksum64(materials.data(), materials.size());
    layout.treeChecksum = checksum64(tree.data(), tree.size());
    layout.directoryChecksum = checksum64(directory.data(), directory.size());

    TempFile file(path + ".tmp");
    if (!file.isOpen()) return Status::error(path + ": cannot create: " + std::strerror(errno));
    bool ok = file.write(serializeHeader(info, layout)) && file.write(materials) && file.write(tree) &&
              file.write(directory) && file.write(cameras) && file.write(volumes) &&
              file.write(lights);
    for (size_t i = 0; ok && i < blobs.size(); ++i) ok = file.write(blobs[i]);
    for (size_t i = 0; ok && i < volumeData.size(); ++i) ok = file.write(volumeData[i]);
    if (!ok) return Status::error(path + ": write failed: " + std::strerror(errno));
    return file.commit(path);
}

}  // namespace vastray
