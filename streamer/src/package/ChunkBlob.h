#pragma once
// Chunk blob layout (all little-endian):
//   header (kChunkHeaderBytes): magic "VCHK", version, triangleCount, vertexCount,
//     kdNodeCount, kdRefCount, geometryBytes, flags, kd bounds (6 floats), kd max depth, zero pad
//   geometry stream (geometryBytes): Draco, or meshopt with kChunkMeshoptGeometry
//   primitive ids  u32 × triangleCount   (decoded face order)
//   material ids   u32 × triangleCount   (only with kChunkHasMaterialIds)
//   KD nodes       8 B × kdNodeCount
//   KD refs        u32 × kdRefCount
#include <cstdint>
#include <vector>

#include "vastray/core/KdTree.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {

std::vector<uint8_t> serializeChunkBlob(const std::vector<uint8_t>& geometry, GeometryCodec codec, uint32_t vertexCount,
                                        const std::vector<uint32_t>& primitiveIds,
                                        const std::vector<uint32_t>& materialIds, const KdTree& kdTree);

}  // namespace vastray
