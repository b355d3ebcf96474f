#pragma once
// Chunk geometry compression; the only file that includes Draco.
//
// Positions travel as exact 32-bit words per axis: grid coordinates when quantized (our own
// scene-wide grid, so the decoder returns the integers we gave it and a triangle shared by
// several chunks decodes identically in each), raw float bits when lossless.
#include <cstdint>
#include <vector>

#include "vastray/core/Result.h"

namespace vastray {

struct ChunkGeometry {
    std::vector<int32_t> vertexWords;  // 3 per vertex
    std::vector<uint32_t> indices;     // 3 per triangle
};

// Draco edgebreaker. `lossless` stores float bit patterns, otherwise grid integers.
// speed: Draco's 0 (smallest) … 10 (fastest).
Result<std::vector<uint8_t>> encodeChunkGeometry(const ChunkGeometry& geometry, bool lossless, int speed);

// Faces come back in edgebreaker order (not the encoder's), possibly with rotated corners
// and split vertices; the cyclic order (winding) of every face is kept.
Result<ChunkGeometry> decodeChunkGeometry(const uint8_t* data, size_t size, bool lossless);

}  // namespace vastray
