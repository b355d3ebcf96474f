// Fuzzes the chunk decoder (Draco or meshopt geometry, ids, BVH) behind its checksum: the
// directory entry is taken from the blob's own counts so that inputs get past the count check,
// as a package whose checksums were recomputed would.
#include <cstring>

#include "vastray/streamer/ScenePackage.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 25) return 0;
    vastray::ChunkInfo info;
    // The chunk header (ChunkBlob.cpp): magic, version, triangles, vertices, BVH nodes, ...
    std::memcpy(&info.triangleCount, data + 8, 4);
    std::memcpy(&info.vertexCount, data + 12, 4);
    std::memcpy(&info.bvhNodeCount, data + 16, 4);
    // The last byte: lossless or quantized positions (bit 0), and 8-byte indices (bit 1) with
    // its upper bits as the directory's long-triangle count (checked against the indices).
    const uint8_t last = data[size - 1];
    if (last & 2) info.flags = vastray::kChunkIndexDeltas16, info.longTriangles = last >> 2;
    vastray::QuantizationGrid grid;
    grid.bits = last % 2 ? 0 : 20;
    const std::vector<uint8_t> blob(data, data + size - 1);
    (void)vastray::decodeChunkBlob(blob, info, grid, 4, 1u << 20);
    return 0;
}
