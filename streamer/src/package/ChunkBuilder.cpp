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

// A cheap 64-bit mix of a triangle's words; equal hashes are confirmed by comparing the words.
uint64_t hashWords(const TriangleWords& words) {
    uint64_t h = 0x9E3779B97F4A7C15ull;
    for (int32_t w : words) h = std::rotl((h ^ uint32_t(w)) * 0xFF51AFD7ED558CCDull, 29);
    return h ^ (h >> 32);
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
        }
        geometry.indices[c] = table[slot].second;
    }
    return geometry;
}

// For every decoded face, the original triangle id. The input triangles go into a hash table
// keyed by their words; identical triangles share one slot and queue in input order, so the
// k-th identical decoded face (in decoded order) takes the k-th identical input triangle.
Result<std::vector<uint32_t>> recoverPrimitiveIds(const ChunkGeometry& input, const std::vector<TriangleRef>& refs,
                                                  const ChunkGeometry& decoded) {
    const size_t n = refs.size();
    if (decoded.indices.size() != n * 3)
        return Status::error("the codec returned " + std::to_string(decoded.indices.size() / 3) + " faces for " +
                             std::to_string(n) + " triangles");
    struct Slot {
        uint64_t hash;
        uint32_t head, tail;  // queue of identical input triangles through `next`; head kNone once taken
    };
    constexpr uint32_t kNone = 0xFFFFFFFFu;
    size_t capacity = 16;
    while (capacity < n * 2) capacity *= 2;
    std::vector<Slot> table(capacity, Slot{0, kNone, kNone});
    std::vector<uint32_t> next(n, kNone);
    auto inputWords = [&](uint32_t t) { return triangleWords(input.vertexWords.data(), &input.indices[3 * size_t(t)]); };
    // The slot of the triangles equal to `words` (compared with the slot's last one), or the
    // free slot where they go; a slot whose queue was emptied stays occupied.
    auto find = [&](const TriangleWords& words, uint64_t hash) -> Slot& {
        size_t i = hash & (capacity - 1);
        while (table[i].tail != kNone && (table[i].hash != hash || inputWords(table[i].tail) != words))
            i = (i + 1) & (capacity - 1);
        return table[i];
    };
    for (uint32_t t = 0; t < n; ++t) {
        const TriangleWords words = inputWords(t);
        const uint64_t hash = hashWords(words);
        Slot& slot = find(words, hash);
        if (slot.tail == kNone) slot = Slot{hash, t, t};
        else slot.tail = next[slot.tail] = t;
    }
    std::vector<uint32_t> ids(n);
    for (uint32_t f = 0; f < n; ++f) {
        const TriangleWords words = triangleWords(decoded.vertexWords.data(), &decoded.indices[3 * size_t(f)]);
        Slot& slot = find(words, hashWords(words));
        if (slot.tail == kNone || slot.head == kNone)
            return Status::error("decoded face " + std::to_string(f) + " matches no input triangle");
        ids[f] = refs[slot.head].triangle;
        slot.head = slot.head == slot.tail ? kNone : next[slot.head];
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
