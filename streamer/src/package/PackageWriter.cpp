#include "package/PackageWriter.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sys/types.h>

#include "package/ByteIo.h"
#include "package/PackageFormat.h"
#include "package/PackageHeader.h"
#include "package/TextureSection.h"
#include "vastray/core/Checksum.h"

namespace vastray {
namespace {

// Bricks read and written at once: 256 KiB of densities (512 KiB with emission).
constexpr uint64_t kWriteBatchBricks = 128;

class TempFile {
public:
    explicit TempFile(std::string path) : path_(std::move(path)) { file_ = std::fopen(path_.c_str(), "wb"); }
    ~TempFile() {
        if (file_) std::fclose(file_);
        if (!committed_) std::remove(path_.c_str());
    }
    bool isOpen() const { return file_ != nullptr; }
    bool write(const void* bytes, size_t size) { return size == 0 || std::fwrite(bytes, 1, size, file_) == size; }
    bool write(const std::vector<uint8_t>& bytes) { return write(bytes.data(), bytes.size()); }
    // Overwrites bytes written before at `offset`, and goes back to the end.
    bool writeAt(uint64_t offset, const std::vector<uint8_t>& bytes) {
        return fseeko(file_, off_t(offset), SEEK_SET) == 0 && write(bytes) && fseeko(file_, 0, SEEK_END) == 0;
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

Status writeFailed(const std::string& path) { return Status::error(path + ": write failed: " + std::strerror(errno)); }

// Writes a volume's data (format version 14) at the file's end: its cell table; its brick index,
// per brick the XXH64 of its bytes, its largest density (of the values its leaves decode to) and
// a reserved 0; then each brick's leaves in the volume's codec, the density's and the emission's.
// The bricks are read (readVolumeLeaves: a package's leaves verbatim, else encoded from the
// voxels read) and written kWriteBatchBricks at a time, so that only the table, the index and one
// batch are in memory; the index, known when every brick is written, is written over the zeros
// that held its place. Sets p's checksum.
Status writeVolumeData(TempFile& file, const std::string& path, PackageVolume& p) {
    const Volume& v = p.volume;
    const bool emission = v.hasEmission();
    const uint64_t bricks = v.brickCount(), brickBytes = format::volumeBrickBytes(format::kVersion, v.codec, emission);
    const std::vector<std::array<int32_t, 3>> origins = volumeBrickOrigins(v);
    ByteWriter table;
    table.putArray(v.brickOf);
    const uint64_t indexAt = p.offset + table.bytes().size();
    table.bytes().resize(format::volumeTableBytes(format::kVersion, v.cellCount(), bricks));
    if (!file.write(table.bytes())) return writeFailed(path);
    std::vector<uint8_t> batch(kWriteBatchBricks * brickBytes);
    std::vector<float> values(2 * kVolumeBrickVoxels);
    ByteWriter index;
    for (uint64_t first = 0; first < bricks; first += kWriteBatchBricks) {
        const uint64_t count = std::min<uint64_t>(kWriteBatchBricks, bricks - first);
        for (uint64_t b = 0; b < count; ++b) {
            uint8_t* leaves = batch.data() + b * brickBytes;
            VASTRAY_TRY(readVolumeLeaves(v, v.codec, first + b, origins[first + b], values.data(),
                                         emission ? values.data() + kVolumeBrickVoxels : nullptr, leaves));
            index.put(checksum64(leaves, brickBytes));
            index.put(*std::max_element(values.data(), values.data() + kVolumeBrickVoxels));
            index.put(uint32_t(0));
        }
        if (!file.write(batch.data(), count * brickBytes)) return writeFailed(path);
    }
    if (!file.writeAt(indexAt, index.bytes())) return writeFailed(path);
    std::memcpy(table.bytes().data() + (indexAt - p.offset), index.bytes().data(), index.bytes().size());
    p.checksum = checksum64(table.bytes().data(), table.bytes().size());
    return Status::ok();
}

}  // namespace

Status writePackage(const std::string& path, PackageInfo& info, const std::vector<std::vector<uint8_t>>& blobs,
                    const std::vector<TextureInput>& textures) {
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
    const std::vector<uint8_t> emitters = serializeEmitters(info.emitters);
    const uint64_t textureHeadOffset = layout.volumesOffset +
                                       uint64_t(layout.volumeCount) * format::kVolumeRecordBytes + lights.size() +
                                       emitters.size();
    layout.blobsOffset = textureHeadOffset + format::textureHeadBytes(format::kVersion);
    uint64_t offset = layout.blobsOffset;
    for (size_t i = 0; i < info.chunks.size(); ++i) {
        info.chunks[i].offset = offset;
        info.chunks[i].size = blobs[i].size();
        info.chunks[i].checksum = checksum64(blobs[i].data(), blobs[i].size());
        offset += blobs[i].size();
    }
    for (PackageVolume& p : info.volumes) {
        p.brickCount = uint32_t(p.volume.brickCount());
        p.hasEmission = p.volume.hasEmission();
        p.offset = offset;
        p.size = format::volumeDataBytes(format::kVersion, p.volume.cellCount(), p.brickCount, p.volume.codec,
                                         p.hasEmission);
        p.checksum = 0;  // known once its bricks are written
        offset += p.size;
    }
    info.fileBytes = offset;
    info.formatVersion = format::kVersion;
    const std::vector<uint8_t> directory = serializeDirectory(info.chunks);
    layout.materialsChecksum = checksum64(materials.data(), materials.size());
    layout.treeChecksum = checksum64(tree.data(), tree.size());
    layout.directoryChecksum = checksum64(directory.data(), directory.size());

    TempFile file(path + ".tmp");
    if (!file.isOpen()) return Status::error(path + ": cannot create: " + std::strerror(errno));
    // The header and the volume records hold the volumes' checksums: written again at the end.
    bool ok = file.write(serializeHeader(info, layout)) && file.write(materials) && file.write(tree) &&
              file.write(directory) && file.write(cameras) && file.write(serializeVolumeRecords(info.volumes)) &&
              file.write(lights) && file.write(emitters) && file.write(std::vector<uint8_t>(format::textureHeadBytes(format::kVersion), 0));
    for (size_t i = 0; ok && i < blobs.size(); ++i) ok = file.write(blobs[i]);
    if (!ok) return writeFailed(path);
    for (PackageVolume& p : info.volumes) VASTRAY_TRY(writeVolumeData(file, path, p));
    // The textures' pages, one texture at a time, then their table, which ends the file.
    TextureSectionWriter section;
    for (const TextureInput& t : textures) {
        auto pyramid = t.build();
        if (!pyramid) return pyramid.status();
        VASTRAY_TRY(section.add(t.name, *pyramid).withContext(path + ": "));
        if (!file.write(section.data())) return writeFailed(path);
        section.data().clear();
    }
    const std::vector<uint8_t> table = section.tableBytes();
    const uint64_t tableOffset = info.fileBytes + section.table().dataBytes;
    if (!file.write(table) ||
        !file.writeAt(textureHeadOffset, serializeTextureHead({uint32_t(textures.size()), tableOffset, table.size()})))
        return writeFailed(path);
    info.textureDataOffset = info.fileBytes;
    info.textureDataBytes = section.table().dataBytes;
    info.textures = section.table().textures;
    info.texturePages = section.table().entries;
    info.fileBytes = tableOffset + table.size();
    const std::vector<uint8_t> volumes = serializeVolumeRecords(info.volumes);
    layout.volumesChecksum = checksum64(volumes.data(), volumes.size());
    if (!file.writeAt(layout.volumesOffset, volumes) || !file.writeAt(0, serializeHeader(info, layout)))
        return writeFailed(path);
    return file.commit(path);
}

}  // namespace vastray
