#pragma once
// Chunk geometry compression; the only file that includes Draco's encoder or meshoptimizer.
//
// Positions travel as exact 32-bit words per axis: grid coordinates when quantized (our own
// scene-wide grid, so the decoder returns the integers we gave it and a triangle shared by
// several chunks decodes identically in each), raw float bits when lossless.
#include <array>
#include <cstdint>
#include <vector>

#include "vastray/core/Result.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {

struct ChunkGeometry {
    std::vector<int32_t> vertexWords;  // 3 per vertex
    std::vector<uint32_t> indices;     // 3 per triangle
    // Per vertex, or empty (core/VertexAttributes.h codes); both codecs return them exactly.
    std::vector<uint32_t> normals;
    std::vector<uint32_t> colors;
    std::vector<std::array<float, 2>> uvs;  // per vertex, or empty: f32 bit patterns, kept exactly
};

// Which optional per-vertex attributes a geometry stream carries (the chunk header's flags).
struct GeometryAttributes {
    bool normals = false;
    bool colors = false;
    bool uvs = false;
};

// `lossless` stores float bit patterns, otherwise grid integers; both codecs return exactly
// the words they were given. Draco: edgebreaker, dracoSpeed 0 (smallest) … 10 (fastest).
// Meshopt: vertex-cache and vertex-fetch optimisation, then meshoptimizer's index codec and
// its vertex codec on chunk-relative words (16 bits per axis when they fit, else 32).
Result<std::vector<uint8_t>> encodeChunkGeometry(const ChunkGeometry& geometry, bool lossless, GeometryCodec codec,
                                                 int dracoSpeed);

// Faces come back in the codec's order (not the encoder's input order), possibly with rotated
// corners (and split vertices with Draco); the cyclic order (winding) of every face is kept.
// `attributes` says which attributes the stream carries; a stream lacking one is an error.
Result<ChunkGeometry> decodeChunkGeometry(const uint8_t* data, size_t size, bool lossless, GeometryCodec codec,
                                          GeometryAttributes attributes = {});

}  // namespace vastray
