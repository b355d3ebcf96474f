#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <new>
#include <string>

#include "package/PackageFormat.h"
#include "package/PackageHeader.h"
#include "package/TextureSection.h"
#include "package/VolumeBricks.h"
#include "vastray/core/Checksum.h"
#include "vastray/core/FilePath.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {

namespace {

// The top-level tree: children after their parent, every chunk in exactly one leaf.
Status validateTopTree(const std::vector<KdNode>& nodes, uint32_t chunkCount) {
    if (nodes.empty()) return Status::error("top-level tree is empty");
    std::vector<uint8_t> parents(nodes.size(), 0), chunkSeen(chunkCount, 0);
    std::vector<uint16_t> depth(nodes.size(), 0);
    for (size_t i = 0; i < nodes.size(); ++i) {
        const KdNode& node = nodes[i];
        if (i > 0 && parents[i] != 1) return Status::error("top-level node " + std::to_string(i) + " is not in the tree");
        if (node.isLeaf()) {
            const uint32_t chunk = node.firstRef();
            if (chunk == kEmptyCell) continue;
            if (chunk >= chunkCount || chunkSeen[chunk]++)
                return Status::error("top-level leaf " + std::to_string(i) + " names an invalid chunk");
            continue;
        }
        const uint64_t above = node.aboveChild();
        if (i + 1 >= nodes.size() || above <= i + 1 || above >= nodes.size() || !std::isfinite(node.split()) ||
            depth[i] >= 64)
            return Status::error("top-level node " + std::to_string(i) + " is malformed");
        for (size_t child : {i + 1, size_t(above)}) {
            parents[child]++;
            depth[child] = uint16_t(depth[i] + 1);
        }
    }
    for (uint32_t c = 0; c < chunkCount; ++c)
        if (!chunkSeen[c]) return Status::error("chunk " + std::to_string(c) + " is in no cell");
    return Status::ok();
}

// Blobs lie after the directory, in order, without overlap, inside the file; the volumes' data
// after them, in order. Returns where the last of them ends: the end of the file before version
// 10, the start of the texture pages from version 10 (the caller checks which).
Result<uint64_t> validateDirectory(const std::vector<ChunkInfo>& chunks, const std::vector<PackageVolume>& volumes,
                                   uint64_t blobsOffset, uint64_t fileBytes) {
    uint64_t next = blobsOffset;
    for (const ChunkInfo& c : chunks) {
        const std::string name = "chunk " + std::to_string(c.id) + ": ";
        if (c.offset != next || c.size > fileBytes - c.offset) return Status::error(name + "blob outside the file");
        const uint64_t minimum = format::kChunkHeaderBytes + uint64_t(c.triangleCount) * 8 +
                                 uint64_t(c.bvhNodeCount) * sizeof(Bvh4Node);
        if (c.size < minimum) return Status::error(name + "counts larger than its blob could hold");
        if (c.triangleCount == 0 || c.triangleCount > kBvh4MaxTriangles || c.bvhNodeCount == 0 || c.cell.isEmpty())
            return Status::error(name + "empty or invalid cell");
        VASTRAY_TRY(checkStoredBox(name + "cell bounds", c.cell));
        next = c.offset + c.size;
    }
    for (size_t i = 0; i < volumes.size(); ++i) {
        const PackageVolume& v = volumes[i];
        if (v.offset != next || v.size > fileBytes - v.offset)
            return Status::error("volume " + std::to_string(i) + ": data outside the file");
        next = v.offset + v.size;
    }
    return next;
}

}  // namespace

PackageReader::~PackageReader() = default;

bool isPackagePath(const std::string& path) { return lowerExtension(path) == ".vast"; }

Result<std::unique_ptr<PackageReader>> PackageReader::open(const std::string& path) {
    std::unique_ptr<PackageReader> reader(new PackageReader());
    reader->path_ = path;
    reader->file_ = std::make_shared<PackageFile>();
    // O_NONBLOCK: a FIFO without a writer must not block the open; fstat then refuses it.
    reader->file_->fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (reader->file_->fd < 0) return Status::error(path + ": cannot open: " + std::strerror(errno));
    struct stat st {};
    if (::fstat(reader->file_->fd, &st) != 0) return Status::error(path + ": cannot stat: " + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) return Status::error(path + ": is not a regular file (a FIFO, device or directory)");
    const uint64_t fileSize = uint64_t(st.st_size);
    auto fail = [&](const Status& status) { return status.withContext(path + ": "); };

    std::vector<uint8_t> bytes;
    if (fileSize < format::kHeaderBytes || !reader->file_->read(0, format::kHeaderBytes, bytes))
        return fail(Status::error("file is too short to be a package"));
    PackageInfo& info = reader->info_;
    auto layout = parseHeader(bytes.data(), bytes.size(), info);
    if (!layout) return fail(layout.status());
    if (info.fileBytes != fileSize)
        return fail(Status::error("file is " + std::to_string(fileSize) + " bytes, header says " +
                                  std::to_string(info.fileBytes) + " (truncated or appended to)"));
    const SectionLayout& l = *layout;
    const uint64_t materialsBytes = uint64_t(l.materialCount) * format::materialBytes(info.formatVersion);
    const uint64_t treeBytes = uint64_t(l.topNodeCount) * sizeof(KdNode);
    const uint64_t directoryBytes = uint64_t(l.chunkCount) * format::kDirectoryEntryBytes;
    const uint64_t cameraBytes = uint64_t(l.cameraCount) * format::kCameraBytes;
    const uint64_t volumeBytes = uint64_t(l.volumeCount) * format::kVolumeRecordBytes;
    // Version 3 has no volume records: they would start where the blobs do.
    const uint64_t volumesOffset = info.formatVersion >= 4 ? l.volumesOffset : l.camerasOffset + cameraBytes;
    const uint64_t lightsOffset = volumesOffset + volumeBytes;
    const uint64_t lightsBytes = format::lightsSectionBytes(info.formatVersion, l.lightCount);
    // The emitters (version 12): their count heads their section; it is checked once the
    // sections' offsets agree with it.
    const uint64_t emittersOffset = lightsOffset + lightsBytes;
    uint32_t emitterCount = 0;
    std::vector<uint8_t> emittersHead;
    if (info.formatVersion >= format::kFirstEmittersVersion) {
        if (emittersOffset > fileSize || !reader->file_->read(emittersOffset, format::kEmittersHeadBytes, emittersHead))
            return fail(Status::error("cannot read the emitters' count"));
        std::memcpy(&emitterCount, emittersHead.data(), 4);
    }
    const uint64_t emittersBytes = format::emittersSectionBytes(info.formatVersion, emitterCount);
    const uint64_t textureHeadOffset = emittersOffset + emittersBytes;
    const uint64_t textureHeadBytes = format::textureHeadBytes(info.formatVersion);
    if (l.materialsOffset != format::kHeaderBytes || l.treeOffset != l.materialsOffset + materialsBytes ||
        l.directoryOffset != l.treeOffset + treeBytes || l.camerasOffset != l.directoryOffset + directoryBytes ||
        volumesOffset != l.camerasOffset + cameraBytes || l.blobsOffset != textureHeadOffset + textureHeadBytes ||
        l.blobsOffset > fileSize)
        return fail(Status::error("section offsets are inconsistent"));
    if (!emittersHead.empty())
        if (auto count = parseEmittersHead(emittersHead); !count) return fail(count.status());
    // The texture head first: the materials name its textures.
    TextureHead textureHead;
    textureHead.tableOffset = fileSize;
    if (textureHeadBytes > 0) {
        if (!reader->file_->read(textureHeadOffset, textureHeadBytes, bytes))
            return fail(Status::error("cannot read the texture head"));
        auto head = parseTextureHead(bytes.data(), bytes.size());
        if (!head) return fail(head.status());
        textureHead = *head;
        if (textureHead.tableOffset > fileSize || textureHead.tableBytes != fileSize - textureHead.tableOffset)
            return fail(Status::error("textures: the table at " + std::to_string(textureHead.tableOffset) + " (" +
                                      std::to_string(textureHead.tableBytes) + " bytes) does not end the " +
                                      std::to_string(fileSize) + "-byte file"));
    }

    auto readSection = [&](uint64_t offset, uint64_t size, uint64_t checksum, const char* name) -> Status {
        if (!reader->file_->read(offset, size, bytes)) return Status::error(std::string("cannot read ") + name);
        if (const uint64_t computed = checksum64(bytes.data(), bytes.size()); computed != checksum)
            return checksumMismatch(name, checksum, computed);
        return Status::ok();
    };
    if (auto s = readSection(l.materialsOffset, materialsBytes, l.materialsChecksum, "materials"); !s) return fail(s);
    auto materials = parseMaterials(bytes, l.materialCount, info.formatVersion, textureHead.count);
    if (!materials) return fail(materials.status());
    info.materials = std::move(*materials);
    if (auto s = readSection(l.treeOffset, treeBytes, l.treeChecksum, "top-level tree"); !s) return fail(s);
    info.topTree.resize(l.topNodeCount);
    std::memcpy(info.topTree.data(), bytes.data(), treeBytes);
    if (auto s = readSection(l.directoryOffset, directoryBytes, l.directoryChecksum, "chunk directory"); !s) return fail(s);
    auto chunks = parseDirectory(bytes, l.chunkCount, info.formatVersion);
    if (!chunks) return fail(chunks.status());
    info.chunks = std::move(*chunks);
    if (auto s = readSection(l.camerasOffset, cameraBytes, l.camerasChecksum, "cameras"); !s) return fail(s);
    auto cameras = parseCameras(bytes, l.cameraCount);
    if (!cameras) return fail(cameras.status());
    info.cameras = std::move(*cameras);
    if (info.formatVersion >= 4) {
        if (auto s = readSection(volumesOffset, volumeBytes, l.volumesChecksum, "volume records"); !s) return fail(s);
        auto volumes = parseVolumeRecords(bytes, l.volumeCount, info.formatVersion);
        if (!volumes) return fail(volumes.status());
        info.volumes = std::move(*volumes);
    }
    if (info.formatVersion >= format::kFirstLightsVersion) {
        if (!reader->file_->read(lightsOffset, lightsBytes, bytes)) return fail(Status::error("cannot read lights"));
        auto lights = parseLights(bytes, l.lightCount);
        if (!lights) return fail(lights.status());
        info.lights = std::move(*lights);
    }
    if (emittersBytes > 0) {
        if (!reader->file_->read(emittersOffset, emittersBytes, bytes)) return fail(Status::error("cannot read emitters"));
        auto emitters = parseEmitters(bytes, emitterCount, info.materials, textureHead.count, info.formatVersion);
        if (!emitters) return fail(emitters.status());
        info.emitters = std::move(*emitters);
    }
    auto dataEnd = validateDirectory(info.chunks, info.volumes, l.blobsOffset, fileSize);
    if (!dataEnd) return fail(dataEnd.status());
    if (*dataEnd > textureHead.tableOffset || (textureHead.count == 0 && *dataEnd != fileSize))
        return fail(Status::error("file size disagrees with the chunk directory and volume records"));
    info.textureDataOffset = *dataEnd;
    info.textureDataBytes = textureHead.tableOffset - *dataEnd;
    if (textureHead.count > 0) {
        if (!reader->file_->read(textureHead.tableOffset, textureHead.tableBytes, bytes))
            return fail(Status::error("cannot read the texture table"));
        auto table = parseTextureTable(bytes.data(), bytes.size(), textureHead.count, info.textureDataBytes, path);
        if (!table) return table.status();
        info.textures = std::move(table->textures);
        info.texturePages = std::move(table->entries);
    }
    if (auto s = validateTopTree(info.topTree, l.chunkCount); !s) return fail(s);
    uint64_t references = 0;
    for (const ChunkInfo& c : info.chunks) references += c.triangleCount;
    if (references != info.referenceCount) return fail(Status::error("reference count disagrees with the directory"));
    return reader;
}

Result<std::vector<uint8_t>> PackageReader::readChunkBlob(uint32_t id) const {
    if (id >= info_.chunks.size())
        return Status::error(path_ + ": chunk " + std::to_string(id) + " does not exist (" +
                             std::to_string(info_.chunks.size()) + " chunks)");
    const ChunkInfo& chunk = info_.chunks[id];
    std::vector<uint8_t> blob;
    if (!file_->read(chunk.offset, chunk.size, blob))
        return Status::error(path_ + ": chunk " + std::to_string(id) + ": read failed");
    if (const uint64_t computed = checksum64(blob.data(), blob.size()); computed != chunk.checksum)
        return checksumMismatch(path_ + ": chunk " + std::to_string(id) + ":", chunk.checksum, computed);
    return blob;
}

Status PackageReader::readTexturePage(uint32_t texture, uint32_t page, uint8_t* out) const {
    if (texture >= info_.textures.size() || page >= info_.textures[texture].layout.pageCount)
        return Status::error(path_ + ": texture " + std::to_string(texture) + " page " + std::to_string(page) +
                             " does not exist");
    const TexturePageEntry& e = info_.texturePages[info_.textures[texture].firstEntry + page];
    std::vector<uint8_t> frame;
    if (!file_->read(info_.textureDataOffset + e.offset, e.size, frame))
        return Status::error(path_ + ": texture " + std::to_string(texture) + " page " + std::to_string(page) +
                             ": read failed");
    return vastray::readTexturePage(info_.textures, info_.texturePages, texture, page, frame.data(), frame.size(),
                                    out, path_);
}

Result<DecodedChunk> PackageReader::readChunk(uint32_t id) const {
    auto blob = readChunkBlob(id);
    if (!blob) return blob.status();
    // Primitive ids index the imported mesh, which still had the triangles quantization dropped.
    auto chunk = decodeChunkBlob(*blob, info_.chunks[id], info_.grid, uint32_t(info_.materials.size()),
                                 info_.triangleCount + info_.collapsedDropped);
    if (!chunk) return chunk.status().withContext(path_ + ": chunk " + std::to_string(id) + ": ");
    return chunk;
}

Result<std::vector<Volume>> PackageReader::readWholeVolumes() const {
    std::vector<Volume> volumes;
    std::vector<uint8_t> data;
    for (size_t i = 0; i < info_.volumes.size(); ++i) {
        const PackageVolume& p = info_.volumes[i];
        const std::string name = path_ + ": volume " + std::to_string(i) + " '" + p.volume.name + "': ";
        // The data and the volume's arrays: twice its size in host memory while it is read.
        try {
            data.reserve(p.size);
            volumes.reserve(info_.volumes.size());
        } catch (const std::bad_alloc&) {
            return Status::error(name + "out of host memory for its " + std::to_string(p.size) + " bytes");
        }
        if (!file_->read(p.offset, p.size, data)) return Status::error(name + "read failed");
        if (const uint64_t computed = checksum64(data.data(), data.size()); computed != p.checksum)
            return checksumMismatch(name + "data", p.checksum, computed);
        Volume& v = volumes.emplace_back(p.volume);
        const uint64_t tableBytes = 4 * v.cellCount();
        try {
            v.brickOf.resize(v.cellCount());
            v.voxels.resize(uint64_t(p.brickCount) * kVolumeBrickVoxels);
            v.emissionVoxels.resize(p.hasEmission ? v.voxels.size() : 0);
            v.majorant.reserve(v.cellCount());
        } catch (const std::bad_alloc&) {
            return Status::error(name + "out of host memory for its " + std::to_string(p.size) + " bytes");
        }
        std::memcpy(v.brickOf.data(), data.data(), tableBytes);
        if (!v.voxels.empty()) std::memcpy(v.voxels.data(), data.data() + tableBytes, v.voxels.size() * 4);
        if (!v.emissionVoxels.empty())  // (memcpy of an empty vector's null data is undefined)
            std::memcpy(v.emissionVoxels.data(), data.data() + tableBytes + v.voxels.size() * 4,
                        v.emissionVoxels.size() * 4);
        if (const std::string problem = checkVolume(v); !problem.empty()) return Status::error(name + problem);
        computeVolumeMajorants(v);
    }
    return volumes;
}

Result<std::shared_ptr<const std::vector<Volume>>> PackageReader::openVolumes() const {
    if (info_.formatVersion < format::kFirstBrickwiseVersion) {
        auto whole = readWholeVolumes();
        if (!whole) return whole.status();
        return std::make_shared<const std::vector<Volume>>(std::move(whole).value());
    }
    auto volumes = std::make_shared<std::vector<Volume>>();
    std::vector<StoredVolumeBricks> stored(info_.volumes.size());
    for (size_t i = 0; i < info_.volumes.size(); ++i) {
        const PackageVolume& p = info_.volumes[i];
        Volume& v = volumes->emplace_back(p.volume);
        VASTRAY_TRY(readVolumeTable(*file_, info_.formatVersion, p, path_ + ": volume " + std::to_string(i) + " '" + p.volume.name + "': ",
                                    v, stored[i]));
    }
    auto source = std::make_shared<const PackageVolumeBricks>(file_, std::move(stored),
                                                              info_.formatVersion >= format::kFirstLeafBricksVersion);
    for (size_t i = 0; i < volumes->size(); ++i) {
        Volume& v = (*volumes)[i];
        v.bricks = {source, uint32_t(i), info_.volumes[i].brickCount, info_.volumes[i].hasEmission};
    }
    return std::shared_ptr<const std::vector<Volume>>(std::move(volumes));
}

Result<std::shared_ptr<const std::vector<Volume>>> PackageReader::readVolumes() const {
    if (info_.formatVersion < format::kFirstBrickwiseVersion) return openVolumes();
    auto opened = openVolumes();
    if (!opened) return opened.status();
    auto volumes = std::make_shared<std::vector<Volume>>(**opened);
    for (size_t i = 0; i < volumes->size(); ++i) {
        Volume& v = (*volumes)[i];
        const uint64_t bricks = v.brickCount();
        try {
            v.voxels.resize(bricks * kVolumeBrickVoxels);
            v.emissionVoxels.resize(v.hasEmission() ? v.voxels.size() : 0);
        } catch (const std::bad_alloc&) {
            return Status::error(path_ + ": volume " + std::to_string(i) + " '" + v.name + "': out of host memory for its " +
                                 std::to_string(info_.volumes[i].size) + " bytes");
        }
        for (uint64_t b = 0; b < bricks; ++b)
            VASTRAY_TRY(readVolumeBrick(v, b, v.voxels.data() + b * kVolumeBrickVoxels,
                                        v.emissionVoxels.empty() ? nullptr : v.emissionVoxels.data() + b * kVolumeBrickVoxels));
        v.bricks = {};  // in memory now, decoded: exact
        v.codec = VolumeCodec::Float;
    }
    return std::shared_ptr<const std::vector<Volume>>(std::move(volumes));
}

std::vector<std::string> PackageReader::verify() const {
    std::vector<std::string> problems;
    for (const ChunkInfo& chunk : info_.chunks) {
        auto decoded = readChunk(chunk.id);
        if (!decoded) problems.push_back(decoded.message());
    }
    if (auto volumes = readVolumes(); !volumes) problems.push_back(volumes.message());
    std::vector<uint8_t> page(kTexturePageBytes);
    for (uint32_t t = 0; t < info_.textures.size(); ++t)
        for (uint32_t p = 0; p < info_.textures[t].layout.pageCount; ++p)
            if (Status s = readTexturePage(t, p, page.data()); !s) problems.push_back(s.message());
    return problems;
}

}  // namespace vastray
