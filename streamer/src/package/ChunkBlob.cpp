#include "package/ChunkBlob.h"

#include <bit>
#include <cmath>
#include <cstdio>
#include <string>

#include "package/ByteIo.h"
#include "package/ChunkCodec.h"
#include "package/PackageFormat.h"
#include "package/PackageHeader.h"
#include "vastray/core/VertexAttributes.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {
namespace {

struct ChunkBlobHeader {
    uint32_t triangleCount = 0, vertexCount = 0, bvhNodeCount = 0, reserved = 0, geometryBytes = 0, flags = 0;
    Aabb bvhBounds;
    uint32_t bvhMaxDepth = 0;
};

Result<ChunkBlobHeader> readBlobHeader(ByteReader& in) {
    char magic[4];
    uint32_t version = 0;
    ChunkBlobHeader h;
    in.get(magic);
    in.get(version);
    in.get(h.triangleCount);
    in.get(h.vertexCount);
    in.get(h.bvhNodeCount);
    in.get(h.reserved);
    in.get(h.geometryBytes);
    in.get(h.flags);
    in.get(h.bvhBounds.lo);
    in.get(h.bvhBounds.hi);
    in.get(h.bvhMaxDepth);
    if (!in.ok() || std::memcmp(magic, format::kChunkMagic, 4) != 0) return Status::error("bad chunk header");
    if (version != format::kChunkVersion) return Status::error("unsupported chunk version " + std::to_string(version));
    if (h.flags & ~format::kChunkKnownFlags) return Status::error("chunk has unknown flags " + std::to_string(h.flags));
    if (h.reserved != 0) return Status::error("chunk header's reserved field is not 0");
    // The blob's checksum held; its floats must still be sane (a NaN box makes every ray miss).
    VASTRAY_TRY(checkStoredBox("BVH bounds", h.bvhBounds));
    if (h.bvhMaxDepth > kBvh4MaxDepth)
        return Status::error("chunk's BVH depth " + std::to_string(h.bvhMaxDepth) + " exceeds " +
                             std::to_string(kBvh4MaxDepth));
    in.skip(format::kChunkHeaderBytes - in.position());
    return h;
}

// Applies the stored leaf order to the decoded faces; the order must be a permutation.
Status applyLeafOrder(const std::vector<uint32_t>& order, std::vector<uint32_t>& indices) {
    const size_t n = order.size();
    std::vector<uint8_t> seen(n, 0);
    std::vector<uint32_t> sorted(indices.size());
    for (size_t i = 0; i < n; ++i) {
        const uint32_t f = order[i];
        if (f >= n || seen[f]) return Status::error("leaf order entry " + std::to_string(i) + " is not a permutation");
        seen[f] = 1;
        for (int k = 0; k < 3; ++k) sorted[3 * i + k] = indices[3 * size_t(f) + k];
    }
    indices = std::move(sorted);
    return Status::ok();
}

}  // namespace

std::vector<uint8_t> serializeChunkBlob(const std::vector<uint8_t>& geometry, GeometryCodec codec, uint32_t vertexCount,
                                        const std::vector<uint32_t>& primitiveIds,
                                        const std::vector<uint32_t>& materialIds, const Bvh4& bvh,
                                        GeometryAttributes attributes) {
    ByteWriter out;
    out.putBytes(format::kChunkMagic, 4);
    out.put(format::kChunkVersion);
    out.put(uint32_t(primitiveIds.size()));
    out.put(vertexCount);
    out.put(uint32_t(bvh.nodes.size()));
    out.put(uint32_t(0));
    out.put(uint32_t(geometry.size()));
    out.put((materialIds.empty() ? 0u : format::kChunkHasMaterialIds) |
            (codec == GeometryCodec::Meshopt ? format::kChunkMeshoptGeometry : 0u) |
            (attributes.normals ? format::kChunkHasNormals : 0u) | (attributes.colors ? format::kChunkHasColors : 0u) |
            (attributes.uvs ? format::kChunkHasUvs : 0u));
    out.put(bvh.bounds.lo);
    out.put(bvh.bounds.hi);
    out.put(uint32_t(bvh.maxDepth));
    out.padTo(format::kChunkHeaderBytes);
    out.putArray(geometry);
    out.putArray(primitiveIds);
    out.putArray(materialIds);
    out.putArray(bvh.nodes);
    out.putArray(bvh.order);
    return std::move(out.bytes());
}

std::vector<uint32_t> longTriangles(const std::vector<uint32_t>& indices) {
    auto fits = [](uint32_t from, uint32_t to) {
        const int64_t delta = int64_t(to) - int64_t(from);
        return delta >= -kMaxIndexDelta16 && delta <= kMaxIndexDelta16;
    };
    std::vector<uint32_t> out;
    for (size_t t = 0; t + 2 < indices.size(); t += 3)
        if (!fits(indices[t], indices[t + 1]) || !fits(indices[t], indices[t + 2])) out.push_back(uint32_t(t / 3));
    return out;
}

uint64_t DecodedChunk::residentBytes() const {
    return positions.size() * 12 + indices.size() * 4 + primitiveIds.size() * 4 + materialIds.size() * 4 +
           normals.size() * 4 + colors.size() * 4 + uvs.size() * 8 + bvh.nodes.size() * sizeof(Bvh4Node);
}

Result<DecodedChunk> decodeChunkBlob(const std::vector<uint8_t>& blob, const ChunkInfo& info,
                                     const QuantizationGrid& grid, uint32_t materialCount,
                                     uint64_t importedTriangles) {
    ByteReader in(blob.data(), blob.size());
    auto header = readBlobHeader(in);
    if (!header) return header.status();
    const ChunkBlobHeader& h = *header;
    if (h.triangleCount != info.triangleCount || h.vertexCount != info.vertexCount ||
        h.bvhNodeCount != info.bvhNodeCount)
        return Status::error("chunk header disagrees with the directory");
    const bool hasMaterials = (h.flags & format::kChunkHasMaterialIds) != 0;
    const uint64_t expected = uint64_t(format::kChunkHeaderBytes) + h.geometryBytes +
                              uint64_t(h.triangleCount) * (hasMaterials ? 12 : 8) +
                              uint64_t(h.bvhNodeCount) * sizeof(Bvh4Node);
    if (expected != blob.size()) return Status::error("chunk size disagrees with its counts");

    const GeometryCodec codec =
        (h.flags & format::kChunkMeshoptGeometry) ? GeometryCodec::Meshopt : GeometryCodec::Draco;
    const GeometryAttributes attributes{(h.flags & format::kChunkHasNormals) != 0, (h.flags & format::kChunkHasColors) != 0,
                                        (h.flags & format::kChunkHasUvs) != 0};
    auto geometry = decodeChunkGeometry(in.current(), h.geometryBytes, grid.bits == 0, codec, attributes);
    if (!geometry) return geometry.status();
    in.skip(h.geometryBytes);
    if (geometry->indices.size() != size_t(h.triangleCount) * 3 || geometry->vertexWords.size() != size_t(h.vertexCount) * 3 ||
        (attributes.normals && geometry->normals.size() != h.vertexCount) ||
        (attributes.colors && geometry->colors.size() != h.vertexCount) ||
        (attributes.uvs && geometry->uvs.size() != h.vertexCount))
        return Status::error(std::string(geometryCodecName(codec)) + " stream disagrees with the chunk's counts");

    DecodedChunk chunk;
    chunk.id = info.id;
    chunk.indices = std::move(geometry->indices);
    chunk.normals = std::move(geometry->normals);
    chunk.colors = std::move(geometry->colors);
    chunk.uvs = std::move(geometry->uvs);
    for (size_t v = 0; v < chunk.uvs.size(); ++v)
        if (!(std::fabs(chunk.uvs[v][0]) <= kMaxAbsUv && std::fabs(chunk.uvs[v][1]) <= kMaxAbsUv)) {  // NaN fails too
            char text[64];
            std::snprintf(text, sizeof text, "(%.9g, %.9g)", chunk.uvs[v][0], chunk.uvs[v][1]);
            return Status::error("vertex " + std::to_string(v) + " texture coordinate " + text +
                                 " is not finite or beyond +-1e6");
        }
    for (uint32_t index : chunk.indices)
        if (index >= h.vertexCount) return Status::error("vertex index out of range");
    chunk.positions.resize(h.vertexCount);
    // Grid coordinates beyond the grid (a forged stream) would dequantize off it, where the
    // device's packed positions (QuantizationGrid::packsPositions) could not follow them.
    const int64_t gridTop = grid.bits == 0 ? 0 : (int64_t(1) << grid.bits) - 1;
    for (size_t v = 0; v < h.vertexCount; ++v) {
        if (grid.bits != 0)
            for (int axis = 0; axis < 3; ++axis)
                if (const int32_t q = geometry->vertexWords[3 * v + axis]; q < 0 || q > gridTop)
                    return Status::error("vertex " + std::to_string(v) + " grid coordinate " + std::to_string(q) +
                                         " is outside the " + std::to_string(grid.bits) + "-bit grid [0, " +
                                         std::to_string(gridTop) + "]");
        chunk.positions[v] = grid.position(&geometry->vertexWords[3 * v]);
        // Lossless chunks carry raw float bits: a resealed blob could hold NaN or Inf.
        if (!isFinite(chunk.positions[v])) return Status::error("vertex " + std::to_string(v) + " is not finite");
    }
    in.getArray(chunk.primitiveIds, h.triangleCount);
    if (hasMaterials) in.getArray(chunk.materialIds, h.triangleCount);
    in.getArray(chunk.bvh.nodes, h.bvhNodeCount);
    std::vector<uint32_t> order;
    in.getArray(order, h.triangleCount);
    chunk.bvh.bounds = h.bvhBounds;
    chunk.bvh.maxDepth = h.bvhMaxDepth;
    VASTRAY_TRY(applyLeafOrder(order, chunk.indices));
    chunk.indexDeltas16 = (info.flags & kChunkIndexDeltas16) != 0;
    if (chunk.indexDeltas16) {
        chunk.longTriangles = longTriangles(chunk.indices);
        if (chunk.longTriangles.size() != info.longTriangles)
            return Status::error(std::to_string(chunk.longTriangles.size()) +
                                 " triangles have vertex indices beyond 16-bit offsets, its directory entry says " +
                                 std::to_string(info.longTriangles));
    }
    for (uint32_t id : chunk.primitiveIds)
        if (id >= importedTriangles) return Status::error("primitive id " + std::to_string(id) + " out of range");
    for (uint32_t m : chunk.materialIds)
        if (m >= materialCount) return Status::error("material id " + std::to_string(m) + " out of range");
    if (const std::string bad = validateBvh4Nodes(chunk.bvh.nodes, h.triangleCount); !bad.empty())
        return Status::error(bad);
    chunk.validated = true;
    return chunk;
}

}  // namespace vastray
