#include "package/ChunkBuilder.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstring>
#include <string>

#include "package/ChunkBlob.h"
#include "package/ChunkCodec.h"

namespace vastray {
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A triangle identified by its corner words, rotated so the smallest corner comes first:
// invariant under edgebreaker's corner rotation, and it keeps the winding.
struct TriangleKey {
    std::array<int32_t, 9> words;
    uint32_t id;  // original triangle id (input side) or decoded face index (output side)

    bool operator<(const TriangleKey& other) const {
        return words != other.words ? words < other.words : id < other.id;
    }
};

TriangleKey makeKey(const int32_t* vertexWords, const uint32_t* corners, uint32_t id) {
    std::array<std::array<int32_t, 3>, 3> c;
    for (int k = 0; k < 3; ++k) std::memcpy(c[k].data(), &vertexWords[3 * size_t(corners[k])], 12);
    int first = 0;
    for (int k = 1; k < 3; ++k)
        if (c[k] < c[first]) first = k;
    TriangleKey key;
    for (int k = 0; k < 3; ++k) std::memcpy(&key.words[3 * k], c[(first + k) % 3].data(), 12);
    key.id = id;
    return key;
}

// Local vertex table of a cell: sorted unique global vertex ids.
ChunkGeometry gatherGeometry(const ChunkSource& source, const std::vector<TriangleRef>& refs) {
    std::vector<uint32_t> globalIds;
    globalIds.reserve(refs.size() * 3);
    for (const TriangleRef& ref : refs)
        for (int k = 0; k < 3; ++k) globalIds.push_back(source.indices[3 * size_t(ref.triangle) + k]);
    std::vector<uint32_t> unique = globalIds;
    std::sort(unique.begin(), unique.end());
    unique.erase(std::unique(unique.begin(), unique.end()), unique.end());
    ChunkGeometry geometry;
    geometry.vertexWords.resize(unique.size() * 3);
    for (size_t v = 0; v < unique.size(); ++v)
        std::memcpy(&geometry.vertexWords[3 * v], &source.vertexWords[3 * size_t(unique[v])], 12);
    geometry.indices.resize(globalIds.size());
    for (size_t c = 0; c < globalIds.size(); ++c)
        geometry.indices[c] =
            uint32_t(std::lower_bound(unique.begin(), unique.end(), globalIds[c]) - unique.begin());
    return geometry;
}

// For every decoded face, the original triangle id: both sides sorted by key and zipped.
Result<std::vector<uint32_t>> recoverPrimitiveIds(const ChunkGeometry& input, const std::vector<TriangleRef>& refs,
                                                  const ChunkGeometry& decoded) {
    const size_t n = refs.size();
    if (decoded.indices.size() != n * 3)
        return Status::error("Draco returned " + std::to_string(decoded.indices.size() / 3) + " faces for " +
                             std::to_string(n) + " triangles");
    std::vector<TriangleKey> before(n), after(n);
    for (size_t t = 0; t < n; ++t) {
        before[t] = makeKey(input.vertexWords.data(), &input.indices[3 * t], refs[t].triangle);
        after[t] = makeKey(decoded.vertexWords.data(), &decoded.indices[3 * t], uint32_t(t));
    }
    std::sort(before.begin(), before.end());
    std::sort(after.begin(), after.end());
    std::vector<uint32_t> ids(n);
    for (size_t k = 0; k < n; ++k) {
        if (before[k].words != after[k].words)
            return Status::error("decoded face " + std::to_string(after[k].id) + " matches no input triangle");
        ids[after[k].id] = before[k].id;
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
    auto draco = encodeChunkGeometry(input, lossless, source.dracoSpeed);
    if (!draco) return draco.status();
    chunk.encodeSeconds = secondsSince(start);

    start = std::chrono::steady_clock::now();
    auto decoded = decodeChunkGeometry(draco->data(), draco->size(), lossless);
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
    const KdTree kdTree = buildKdTree(positions.data(), decoded->indices.data(), triangles);
    chunk.kdBuildSeconds = secondsSince(start);

    chunk.info.cell = cell;
    chunk.info.triangleCount = triangles;
    chunk.info.vertexCount = uint32_t(positions.size());
    chunk.info.kdNodeCount = uint32_t(kdTree.nodes.size());
    chunk.info.kdRefCount = uint32_t(kdTree.leafRefs.size());
    chunk.info.residentBytes = chunkResidentBytes(positions.size(), triangles, !materialIds.empty(),
                                                  kdTree.nodes.size(), kdTree.leafRefs.size());
    chunk.blob = serializeChunkBlob(*draco, chunk.info.vertexCount, *primitiveIds, materialIds, kdTree);
    chunk.info.size = chunk.blob.size();
    return chunk;
}

}  // namespace vastray
