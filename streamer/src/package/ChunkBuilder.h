#pragma once
// Builds one chunk from the triangles of one cell: codec round trip, original-id recovery,
// 4-wide BVH on the decoder's output, serialized blob.
#include <array>
#include <cstdint>
#include <vector>

#include "package/Partitioner.h"
#include "vastray/core/Result.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {

// Scene-wide inputs every chunk reads (shared, read-only, by all worker threads).
struct ChunkSource {
    const Vec3f* positions;          // dequantized (what the renderer sees)
    const int32_t* vertexWords;      // 3 per vertex: grid coordinates, or float bits if lossless
    const uint32_t* indices;
    const uint32_t* materialIds;     // nullptr when the scene has one material
    const QuantizationGrid* grid;
    int dracoSpeed = 7;
    GeometryCodec codec = GeometryCodec::Draco;
    double residentBytesPerTriangle = 0;  // PackageBuildOptions::residentBytesPerTriangle
    const uint32_t* normals = nullptr;    // per vertex, or nullptr (TriangleMesh::normals)
    const uint32_t* colors = nullptr;     // per vertex, or nullptr (TriangleMesh::colors)
    const std::array<float, 2>* uvs = nullptr;  // per vertex, or nullptr (TriangleMesh::uvs)
};

struct BuiltChunk {
    std::vector<uint8_t> blob;
    ChunkInfo info;                  // id and offset are assigned when the package is written
    double encodeSeconds = 0, decodeSeconds = 0, bvhBuildSeconds = 0;
};

Result<BuiltChunk> buildChunk(const ChunkSource& source, const std::vector<TriangleRef>& refs, const Aabb& cell);

// Decoded resident footprint of a chunk with these counts, indices at 12 bytes a triangle (the
// host's decoded chunk; its device slot, vastray::chunkLayout, is no larger).
// attributeWords: per-vertex attribute words (one each for normals and colours, two for UVs).
uint64_t chunkResidentBytes(uint64_t vertices, uint64_t triangles, bool materialIds, uint64_t bvhNodes,
                            uint32_t attributeWords = 0);

}  // namespace vastray
