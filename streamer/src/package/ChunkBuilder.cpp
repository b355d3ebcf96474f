#include "package/ChunkBuilder.h"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cstring>
#include <string>

#include "package/ChunkBlob.h"
#include "package/ChunkCodec.h"
#include "vastray/core/Checksum.h"

namespace vastray {
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A triangle identified by its corner words, rotated so the smallest corner comes first:
// invariant under edgebreaker's corner rotation, and it keeps the winding.
using TriangleWords = std::array<int32_t, 9>;

TriangleWords triangleWords(const int32_t* vertexWords, const uint32_t* corners) {
    std::array<std::array<int32_t, 3>, 3> c;
    for (int k = 0; k < 3; ++k) std::memcpy(c[k].data(), &vertexWords[3 * size_t(corners[k])], 12);
    int first = 0;
    for (int k = 1; k < 3; ++k)
        if (c[k] < c[first]) first = k;
    TriangleWords words;
    for (int k = 0; k < 3; ++k) std::memcpy(&words[3 * k], c[(first + k) % 3].data(), 12);
    return words;
}

// Triangles in a canonical order: by a 64-bit hash of their words (small elements to sort),
// equal hashes by the words, equal words by position. Two sides holding the same triangles
// come out in corresponding order.
std::vector<uint32_t> canonicalOrder(const std::vector<TriangleWords>& words) {
    struct Entry {
        uint64_t hash;
        uint32_t index;
    };
    std::vector<Entry> entries(words.size());
    for (size_t t = 0; t < words.size(); ++t) entries[t] = {checksum64(words[t].data(), sizeof(TriangleWords)), uint32_t(t)};
    std::sort(entries.begin(), entries.end(), [&](const Entry& a, const Entry& b) {
        if (a.hash != b.hash) return a.hash < b.hash;
        return words[a.index] != words[b.index] ? words[a.index] < words[b.index] : a.index < b.index;
    });
    std::vector<uint32_t> order(entries.size());
    for (size_t k = 0; k < entries.size(); ++k) order[k] = entries[k].index;
    return order;
}

// Local vertex table of a cell, in first-use order, through an open-addressing map from
// global to local vertex id (no sort: this runs for every reference of the scene).
ChunkGeometry gatherGeometry(const ChunkSource& source, const std::vector<TriangleRef>& refs) {
    const size_t corners = refs.size() * 3;
    size_t capacity = 16;
    while (capacity < corners * 2) capacity *= 2;
    constexpr uint32_t kFree = 0xFFFFFFFFu;
    std::vector<std::pair<uint32_t, uint32_t>> table(capacity, {kFree, 0});
    ChunkGeometry geometry;
    geometry.indices.resize(corners);
    geometry.vertexWords.reserve(corners);
    uint32_t localCount = 0;
    for (size_t c = 0; c < corners; ++c) {
        const uint32_t global = source.indices[3 * size_t(refs[c / 3].triangle) + c % 3];
        size_t slot = (global * 0x9E3779B1u) & (capacity - 1);
        while (table[slot].first != kFree && table[slot].first != global) slot = (slot + 1) & (capacity - 1);
        if (table[slot].first == kFree) {
            table[slot] = {global, localCount++};
            geometry.vertexWords.insert(geometry.vertexWords.end(), &source.vertexWords[3 * size_t(global)],
                                        &source.vertexWords[3 * size_t(global)] + 3);
        }
        geometry.indices[c] = table[slot].second;
    }
    return geometry;
}

// For every decoded face, the original triangle id: both sides put in canonical order and zipped.
Result<std::vector<uint32_t>> recoverPrimitiveIds(const ChunkGeometry& input, const std::vector<TriangleRef>& refs,
                                                  const ChunkGeometry& decoded) {
    const size_t n = refs.size();
    if (decoded.indices.size() != n * 3)
        return Status::error("the codec returned " + std::to_string(decoded.indices.size() / 3) + " faces for " +
                             std::to_string(n) + " triangles");
    std::vector<TriangleWords> before(n), after(n);
    for (size_t t = 0; t < n; ++t) {
        before[t] = triangleWords(input.vertexWords.data(), &input.indices[3 * t]);
        after[t] = triangleWords(decoded.vertexWords.data(), &decoded.indices[3 * t]);
    }
    const std::vector<uint32_t> beforeOrder = canonicalOrder(before), afterOrder = canonicalOrder(after);
    std::vector<uint32_t> ids(n);
    for (size_t k = 0; k < n; ++k) {
        if (before[beforeOrder[k]] != after[afterOrder[k]])
            return Status::error("decoded face " + std::to_string(afterOrder[k]) + " matches no input triangle");
        ids[afterOrder[k]] = refs[beforeOrder[k]].triangle;
    }
    return ids;
}

std::vector<Vec3f> wordsToPositions(const std::vector<int32_t>& words, const QuantizationGrid& grid) {
    std::vector<Vec3f> positions(words.size() / 3);
    for (size_t v = 0; v < positions.size(); ++v) positions[v] = grid.position(&words[3 * v]);
    return positions;
}

}  // namespace

uint64_t chunkResidentBytes(uint64_t vertices, uint64_t triangles, bool materialIds, uint64_t kdNodes,
                            uint64_t kdRefs) {
    return vertices * 12 + triangles * (12 + 4 + (materialIds ? 4 : 0)) + kdNodes * 8 + kdRefs * 4;
}

Result<BuiltChunk> buildChunk(const ChunkSource& source, const std::vector<TriangleRef>& refs, const Aabb& cell) {
    BuiltChunk chunk;
    const bool lossless = source.grid->bits == 0;
    const ChunkGeometry input = gatherGeometry(source, refs);

    auto start = std::chrono::steady_clock::now();
    auto encoded = encodeChunkGeometry(input, lossless, source.codec, source.dracoSpeed);
    if (!encoded) return encoded.status();
    chunk.encodeSeconds = secondsSince(start);

    start = std::chrono::steady_clock::now();
    auto decoded = decodeChunkGeometry(encoded->data(), encoded->size(), lossless, source.codec);
    if (!decoded) return decoded.status();
    auto primitiveIds = recoverPrimitiveIds(input, refs, *decoded);
    if (!primitiveIds) return primitiveIds.status();
    const std::vector<Vec3f> positions = wordsToPositions(decoded->vertexWords, *source.grid);
    chunk.decodeSeconds = secondsSince(start);

    std::vector<uint32_t> materialIds;
    if (source.materialIds) {
        materialIds.resize(primitiveIds->size());
        for (size_t t = 0; t < materialIds.size(); ++t) materialIds[t] = source.materialIds[(*primitiveIds)[t]];
    }

    start = std::chrono::steady_clock::now();
    const uint32_t triangles = uint32_t(refs.size());
    const KdTree kdTree = buildKdTree(positions.data(), decoded->indices.data(), triangles, compactKdBuildOptions(triangles));
    chunk.kdBuildSeconds = secondsSince(start);

    chunk.info.cell = cell;
    chunk.info.triangleCount = triangles;
    chunk.info.vertexCount = uint32_t(positions.size());
    chunk.info.kdNodeCount = uint32_t(kdTree.nodes.size());
    chunk.info.kdRefCount = uint32_t(kdTree.leafRefs.size());
    chunk.info.residentBytes = chunkResidentBytes(positions.size(), triangles, !materialIds.empty(),
                                                  kdTree.nodes.size(), kdTree.leafRefs.size());
    chunk.blob = serializeChunkBlob(*encoded, source.codec, chunk.info.vertexCount, *primitiveIds, materialIds, kdTree);
    chunk.info.size = chunk.blob.size();
    return chunk;
}

}  // namespace vastray
