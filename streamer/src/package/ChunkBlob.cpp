#include "package/ChunkBlob.h"

#include <bit>
#include <cmath>
#include <string>

#include "package/ByteIo.h"
#include "package/ChunkCodec.h"
#include "package/PackageFormat.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {
namespace {

struct ChunkBlobHeader {
    uint32_t triangleCount = 0, vertexCount = 0, kdNodeCount = 0, kdRefCount = 0, geometryBytes = 0, flags = 0;
    Aabb kdBounds;
    uint32_t kdMaxDepth = 0;
};

Result<ChunkBlobHeader> readBlobHeader(ByteReader& in) {
    char magic[4];
    uint32_t version = 0;
    ChunkBlobHeader h;
    in.get(magic);
    in.get(version);
    in.get(h.triangleCount);
    in.get(h.vertexCount);
    in.get(h.kdNodeCount);
    in.get(h.kdRefCount);
    in.get(h.geometryBytes);
    in.get(h.flags);
    in.get(h.kdBounds.lo);
    in.get(h.kdBounds.hi);
    in.get(h.kdMaxDepth);
    if (!in.ok() || std::memcmp(magic, format::kChunkMagic, 4) != 0) return Status::error("bad chunk header");
    if (version != format::kChunkVersion) return Status::error("unsupported chunk version " + std::to_string(version));
    if (h.flags & ~format::kChunkKnownFlags) return Status::error("chunk has unknown flags " + std::to_string(h.flags));
    in.skip(format::kChunkHeaderBytes - in.position());
    return h;
}

// Every node's children lie inside the array and after it (so the tree has no cycles), every
// leaf's refs lie inside the ref array, and the depth fits the traversal stack.
Status validateKdTree(const KdTree& tree, uint32_t triangleCount) {
    const size_t n = tree.nodes.size();
    if (n == 0) return Status::error("KD-tree has no nodes");
    std::vector<uint8_t> depth(n, 0), parents(n, 0);
    for (size_t i = 0; i < n; ++i) {
        const KdNode& node = tree.nodes[i];
        if (i > 0 && parents[i] != 1) return Status::error("KD node " + std::to_string(i) + " is not in the tree");
        if (node.isLeaf()) {
            if (uint64_t(node.firstRef()) + node.primitiveCount() > tree.leafRefs.size())
                return Status::error("KD leaf " + std::to_string(i) + " refs out of range");
            continue;
        }
        const uint64_t above = node.aboveChild();
        if (i + 1 >= n || above <= i + 1 || above >= n || !std::isfinite(node.split()))
            return Status::error("KD node " + std::to_string(i) + " is malformed");
        if (uint32_t(depth[i]) + 1 > kMaxKdDepth) return Status::error("KD-tree deeper than " + std::to_string(kMaxKdDepth));
        for (size_t child : {i + 1, size_t(above)}) {
            depth[child] = uint8_t(depth[i] + 1);
            parents[child]++;
        }
    }
    for (uint32_t ref : tree.leafRefs)
        if (ref >= triangleCount) return Status::error("KD ref " + std::to_string(ref) + " out of range");
    return Status::ok();
}

}  // namespace

std::vector<uint8_t> serializeChunkBlob(const std::vector<uint8_t>& geometry, GeometryCodec codec, uint32_t vertexCount,
                                        const std::vector<uint32_t>& primitiveIds,
                                        const std::vector<uint32_t>& materialIds, const KdTree& kdTree) {
    ByteWriter out;
    out.putBytes(format::kChunkMagic, 4);
    out.put(format::kChunkVersion);
    out.put(uint32_t(primitiveIds.size()));
    out.put(vertexCount);
    out.put(uint32_t(kdTree.nodes.size()));
    out.put(uint32_t(kdTree.leafRefs.size()));
    out.put(uint32_t(geometry.size()));
    out.put((materialIds.empty() ? 0u : format::kChunkHasMaterialIds) |
            (codec == GeometryCodec::Meshopt ? format::kChunkMeshoptGeometry : 0u));
    out.put(kdTree.bounds.lo);
    out.put(kdTree.bounds.hi);
    out.put(uint32_t(kdTree.maxDepth));
    out.padTo(format::kChunkHeaderBytes);
    out.putArray(geometry);
    out.putArray(primitiveIds);
    out.putArray(materialIds);
    out.putArray(kdTree.nodes);
    out.putArray(kdTree.leafRefs);
    return std::move(out.bytes());
}

uint64_t DecodedChunk::residentBytes() const {
    return positions.size() * 12 + indices.size() * 4 + primitiveIds.size() * 4 + materialIds.size() * 4 +
           kdTree.nodes.size() * 8 + kdTree.leafRefs.size() * 4;
}

Result<DecodedChunk> decodeChunkBlob(const std::vector<uint8_t>& blob, const ChunkInfo& info,
                                     const QuantizationGrid& grid, uint32_t materialCount,
                                     uint64_t importedTriangles) {
    ByteReader in(blob.data(), blob.size());
    auto header = readBlobHeader(in);
    if (!header) return header.status();
    const ChunkBlobHeader& h = *header;
    if (h.triangleCount != info.triangleCount || h.vertexCount != info.vertexCount ||
        h.kdNodeCount != info.kdNodeCount || h.kdRefCount != info.kdRefCount)
        return Status::error("chunk header disagrees with the directory");
    const bool hasMaterials = (h.flags & format::kChunkHasMaterialIds) != 0;
    const uint64_t expected = uint64_t(format::kChunkHeaderBytes) + h.geometryBytes +
                              uint64_t(h.triangleCount) * (hasMaterials ? 8 : 4) + uint64_t(h.kdNodeCount) * 8 +
                              uint64_t(h.kdRefCount) * 4;
    if (expected != blob.size()) return Status::error("chunk size disagrees with its counts");

    const GeometryCodec codec =
        (h.flags & format::kChunkMeshoptGeometry) ? GeometryCodec::Meshopt : GeometryCodec::Draco;
    auto geometry = decodeChunkGeometry(in.current(), h.geometryBytes, grid.bits == 0, codec);
    if (!geometry) return geometry.status();
    in.skip(h.geometryBytes);
    if (geometry->indices.size() != size_t(h.triangleCount) * 3 || geometry->vertexWords.size() != size_t(h.vertexCount) * 3)
        return Status::error(std::string(geometryCodecName(codec)) + " stream disagrees with the chunk's counts");

    DecodedChunk chunk;
    chunk.id = info.id;
    chunk.indices = std::move(geometry->indices);
    for (uint32_t index : chunk.indices)
        if (index >= h.vertexCount) return Status::error("vertex index out of range");
    chunk.positions.resize(h.vertexCount);
    for (size_t v = 0; v < h.vertexCount; ++v) chunk.positions[v] = grid.position(&geometry->vertexWords[3 * v]);
    in.getArray(chunk.primitiveIds, h.triangleCount);
    if (hasMaterials) in.getArray(chunk.materialIds, h.triangleCount);
    in.getArray(chunk.kdTree.nodes, h.kdNodeCount);
    in.getArray(chunk.kdTree.leafRefs, h.kdRefCount);
    chunk.kdTree.bounds = h.kdBounds;
    chunk.kdTree.maxDepth = h.kdMaxDepth;
    for (uint32_t id : chunk.primitiveIds)
        if (id >= importedTriangles) return Status::error("primitive id " + std::to_string(id) + " out of range");
    for (uint32_t m : chunk.materialIds)
        if (m >= materialCount) return Status::error("material id " + std::to_string(m) + " out of range");
    VASTRAY_TRY(validateKdTree(chunk.kdTree, h.triangleCount));
    chunk.validated = true;
    return chunk;
}

}  // namespace vastray
