#pragma once
// Chunk blob layout (all little-endian):
//   header (kChunkHeaderBytes): magic "VCHK", version, triangleCount, vertexCount,
//     bvhNodeCount, reserved (0), geometryBytes, flags, BVH bounds (6 floats), BVH max depth, zero pad
//   geometry stream (geometryBytes): Draco, or meshopt with kChunkMeshoptGeometry; positions, and
//     per-vertex normals (kChunkHasNormals), colours (kChunkHasColors) and texture coordinates
//     (kChunkHasUvs, two f32 each)
//   primitive ids  u32 × triangleCount   (leaf order)
//   material ids   u32 × triangleCount   (leaf order; only with kChunkHasMaterialIds)
//   BVH nodes      56 B × bvhNodeCount   (Bvh4Node)
//   leaf order     u32 × triangleCount   (entry i: the decoded face stored at position i)
// Codecs keep their own face order, so the leaf order is applied after decoding.
#include <cstdint>
#include <vector>

#include "package/ChunkCodec.h"
#include "vastray/core/Bvh4.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {

std::vector<uint8_t> serializeChunkBlob(const std::vector<uint8_t>& geometry, GeometryCodec codec, uint32_t vertexCount,
                                        const std::vector<uint32_t>& primitiveIds,
                                        const std::vector<uint32_t>& materialIds, const Bvh4& bvh,
                                        GeometryAttributes attributes = {});

}  // namespace vastray
