#include "package/ChunkBuilder.h"

#include <algorithm>
#include <array>
#include <bit>
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

// A triangle as three vertex ids, rotated to its lexicographically smallest rotation: the
// same under edgebreaker's corner rotation, and it keeps the winding.
using Triple = std::array<uint32_t, 3>;

Triple smallestRotation(uint32_t a, uint32_t b, uint32_t c) {
    return std::min({Triple{a, b, c}, Triple{b, c, a}, Triple{c, a, b}});
}

// Local vertex table of a cell, in first-use order, through an open-addressing map from
// global to local vertex id (no sort: this runs for every reference of the scene). Eight
// consecutive global ids share a cache line of the table (meshes number their vertices
// roughly in surface order); the table starts small and doubles at half load.
ChunkGeometry gatherGeometry(const ChunkSource& source, const std::vector<TriangleRef>& refs) {
    const size_t corners = refs.size() * 3;
    constexpr uint32_t kFree = 0xFFFFFFFFu;
    using Entry = std::pair<uint32_t, uint32_t>;  // global id, local id
    size_t capacity = 64;
    while (capacity < corners / 2) capacity *= 2;
    std::vector<Entry> table(capacity, {kFree, 0});
    auto slotOf = [&](uint32_t global) {
        size_t slot = ((size_t((global >> 3) * 0x9E3779B1u) << 3) | (global & 7)) & (capacity - 1);
        while (table[slot].first != kFree && table[slot].first != global) slot = (slot + 1) & (capacity - 1);
        return slot;
    };
    ChunkGeometry geometry;
    geometry.indices.resize(corners);
    geometry.vertexWords.reserve(corners);
    uint32_t localCount = 0;
    for (size_t c = 0; c < corners; ++c) {
        const uint32_t global = source.indices[3 * size_t(refs[c / 3].triangle) + c % 3];
        size_t slot = slotOf(global);
        if (table[slot].first == kFree) {
            if (2 * (size_t(localCount) + 1) > capacity) {
                std::vector<Entry> old(capacity * 2, {kFree, 0});
                old.swap(table);
                capacity *= 2;
                for (const Entry& e : old)
                    if (e.first != kFree) table[slotOf(e.first)] = e;
                slot = slotOf(global);
            }
            table[slot] = {global, localCount++};
            geometry.vertexWords.insert(geometry.vertexWords.end(), &source.vertexWords[3 * size_t(global)],
                                        &source.vertexWords[3 * size_t(global)] + 3);
            if (source.normals) geometry.normals.push_back(source.normals[global]);
            if (source.colors) geometry.colors.push_back(source.colors[global]);
            if (source.uvs) geometry.uvs.push_back(source.uvs[global]);
        }
        geometry.indices[c] = table[slot].second;
    }
    return geometry;
}

// For every decoded face, the original triangle id, without a table keyed by triangles
// (random probes into it cost as much as Draco's decoder). Every vertex, input or decoded,
// is named by the first input vertex with the same words; a triangle is then the smallest
// rotation of its three names. Input triangles are listed by their first name, each list
// sorted by the other two names and the input order, so a decoded face is found by a binary
// search in one short list; the k-th identical decoded face (in decoded order) takes the k-th
// identical input triangle.
Result<std::vector<uint32_t>> recoverPrimitiveIds(const ChunkGeometry& input, const std::vector<TriangleRef>& refs,
                                                  const ChunkGeometry& decoded) {
    const size_t n = refs.size();
    if (decoded.indices.size() != n * 3)
        return Status::error("the codec returned " + std::to_string(decoded.indices.size() / 3) + " faces for " +
                             std::to_string(n) + " triangles");
    constexpr uint32_t kNone = 0xFFFFFFFFu;
    const uint32_t inputVertices = uint32_t(input.vertexWords.size() / 3);
    size_t capacity = 16;
    while (capacity < size_t(inputVertices) * 2) capacity *= 2;
    std::vector<uint32_t> table(capacity, kNone);  // input vertex per distinct words
    // The input vertex with the words at `words`, or kNone; `insert` adds `v` when there is none.
    auto name = [&](const int32_t* words, uint32_t insert) {
        uint64_t h = 0x9E3779B97F4A7C15ull;
        for (int k = 0; k < 3; ++k) h = std::rotl((h ^ uint32_t(words[k])) * 0xFF51AFD7ED558CCDull, 29);
        for (size_t i = (h ^ (h >> 32)) & (capacity - 1);; i = (i + 1) & (capacity - 1)) {
            if (table[i] == kNone) return insert == kNone ? kNone : (table[i] = insert);
            if (std::memcmp(&input.vertexWords[3 * size_t(table[i])], words, 12) == 0) return table[i];
        }
    };
    std::vector<uint32_t> inputName(inputVertices);
    for (uint32_t v = 0; v < inputVertices; ++v) inputName[v] = name(&input.vertexWords[3 * size_t(v)], v);
    const size_t decodedVertices = decoded.vertexWords.size() / 3;
    std::vector<uint32_t> decodedName(decodedVertices);
    for (size_t v = 0; v < decodedVertices; ++v)
        if ((decodedName[v] = name(&decoded.vertexWords[3 * v], kNone)) == kNone)
            return Status::error("decoded vertex " + std::to_string(v) + " matches no input vertex");
    auto triple = [](const std::vector<uint32_t>& names, const uint32_t* corners) {
        return smallestRotation(names[corners[0]], names[corners[1]], names[corners[2]]);
    };

    std::vector<Triple> inputTriples(n);
    std::vector<uint32_t> listStart(size_t(inputVertices) + 1, 0), list(n);
    for (size_t t = 0; t < n; ++t) {
        inputTriples[t] = triple(inputName, &input.indices[3 * t]);
        ++listStart[inputTriples[t][0] + 1];
    }
    for (uint32_t v = 0; v < inputVertices; ++v) listStart[v + 1] += listStart[v];
    {
        std::vector<uint32_t> fill(listStart.begin(), listStart.end() - 1);
        for (uint32_t t = 0; t < n; ++t) list[fill[inputTriples[t][0]]++] = t;
    }
    auto byNames = [&](uint32_t a, uint32_t b) {
        return std::tie(inputTriples[a][1], inputTriples[a][2], a) < std::tie(inputTriples[b][1], inputTriples[b][2], b);
    };
    for (uint32_t v = 0; v < inputVertices; ++v)
        if (listStart[v + 1] - listStart[v] > 1) std::sort(&list[listStart[v]], &list[listStart[v + 1]], byNames);

    std::vector<uint32_t> taken(n, 0);  // at a group's first list position: how many of the group are taken
    std::vector<uint32_t> ids(n);
    for (size_t f = 0; f < n; ++f) {
        const Triple key = triple(decodedName, &decoded.indices[3 * f]);
        const uint32_t* first = &list[listStart[key[0]]];
        const uint32_t* last = &list[listStart[key[0] + 1]];
        const uint32_t* group = std::lower_bound(first, last, key, [&](uint32_t t, const Triple& k) {
            return std::tie(inputTriples[t][1], inputTriples[t][2]) < std::tie(k[1], k[2]);
        });
        const size_t at = size_t(group - list.data()) + taken[group - list.data()]++;
        if (at >= size_t(last - list.data()) || inputTriples[list[at]] != key)
            return Status::error("decoded face " + std::to_string(f) + " matches no input triangle");
        ids[f] = refs[list[at]].triangle;
    }
    return ids;
}

std::vector<Vec3f> wordsToPositions(const std::vector<int32_t>& words, const QuantizationGrid& grid) {
    std::vector<Vec3f> positions(words.size() / 3);
    for (size_t v = 0; v < positions.size(); ++v) positions[v] = grid.position(&words[3 * v]);
    return positions;
}

// What every render uploads of a chunk: BVH nodes, positions, indices (the cap of
// --resident-bytes-per-triangle counts these; indices take 8 bytes a triangle on the device and
// 12 more for each long triangle, kChunkIndexDeltas16; positions 8 bytes a vertex where the grid
// packs them).
uint64_t chunkGeometryBytes(uint64_t vertices, uint64_t triangles, uint64_t bvhNodes, uint64_t longTriangles,
                            bool packedPositions) {
    return devicePositionBytes(vertices, packedPositions) + deviceIndexBytes(triangles, true, longTriangles) +
           bvhNodes * sizeof(Bvh4Node);
}

// The BVH of the first of these cost settings whose chunk fits the cap: leaves of about 2, 3, 5
// and 8 triangles (docs/PERF_NOTES.md); the last is kept whatever it costs.
constexpr std::array<Bvh4BuildOptions, 4> kBvhLadder{{{1.0f, 1.0f, 4, 16}, {1.0f, 0.5f, 4, 16},
                                                       {1.0f, 0.3f, 8, 16}, {1.0f, 0.15f, 16, 16}}};

Bvh4 buildChunkBvh(const std::vector<Vec3f>& positions, const std::vector<uint32_t>& indices, double bytesPerTriangle,
                   uint64_t longTriangles, bool packedPositions) {
    const uint32_t triangles = uint32_t(indices.size() / 3);
    const double limit = bytesPerTriangle * triangles;
    Bvh4 bvh;
    for (const Bvh4BuildOptions& options : kBvhLadder) {
        bvh = buildBvh4(positions.data(), indices.data(), triangles, options);
        if (bytesPerTriangle <= 0 ||
            double(chunkGeometryBytes(positions.size(), triangles, bvh.nodes.size(), longTriangles,
                                      packedPositions)) <= limit)
            break;
    }
    return bvh;
}

}  // namespace

uint64_t chunkResidentBytes(uint64_t vertices, uint64_t triangles, bool materialIds, uint64_t bvhNodes,
                            uint32_t attributeWords) {
    return vertices * 12 + triangles * 12 + bvhNodes * sizeof(Bvh4Node) + triangles * (4 + (materialIds ? 4 : 0)) +
           vertices * 4 * attributeWords;
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
    const GeometryAttributes attributes{source.normals != nullptr, source.colors != nullptr, source.uvs != nullptr};
    auto decoded = decodeChunkGeometry(encoded->data(), encoded->size(), lossless, source.codec, attributes);
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
    if (triangles > kBvh4MaxTriangles)
        return Status::error("a chunk of " + std::to_string(triangles) + " triangles exceeds the limit of " +
                             std::to_string(kBvh4MaxTriangles) + ": use a smaller --chunk-size");
    // The leaf order moves triangles, not their corners: the count holds for the stored order too.
    const uint64_t longCount = longTriangles(decoded->indices).size();
    Bvh4 bvh = buildChunkBvh(positions, decoded->indices, source.residentBytesPerTriangle, longCount,
                             source.grid->packsPositions());
    // Ids travel in leaf order; the blob keeps the order so that the reader can sort the
    // decoded faces the same way.
    auto inLeafOrder = [&](std::vector<uint32_t>& ids) {
        if (ids.empty()) return;
        std::vector<uint32_t> sorted(ids.size());
        for (size_t i = 0; i < sorted.size(); ++i) sorted[i] = ids[bvh.order[i]];
        ids = std::move(sorted);
    };
    inLeafOrder(*primitiveIds);
    inLeafOrder(materialIds);
    chunk.bvhBuildSeconds = secondsSince(start);

    chunk.info.cell = cell;
    chunk.info.triangleCount = triangles;
    chunk.info.vertexCount = uint32_t(positions.size());
    chunk.info.bvhNodeCount = uint32_t(bvh.nodes.size());
    chunk.info.flags = kChunkIndexDeltas16;
    chunk.info.longTriangles = uint32_t(longCount);
    chunk.info.residentBytes = chunkResidentBytes(positions.size(), triangles, !materialIds.empty(), bvh.nodes.size(),
                                                  uint32_t(attributes.normals) + uint32_t(attributes.colors) +
                                                      2 * uint32_t(attributes.uvs));
    chunk.blob =
        serializeChunkBlob(*encoded, source.codec, chunk.info.vertexCount, *primitiveIds, materialIds, bvh, attributes);
    chunk.info.size = chunk.blob.size();
    return chunk;
}

}  // namespace vastray
