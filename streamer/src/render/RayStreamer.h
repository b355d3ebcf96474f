#pragma once
// Traces one stream of rays (a bounce's closest-hit rays, or its shadow rays) through the
// package: walks each ray's cells in the top-level tree, queues rays per chunk, traces the
// queues of resident chunks, merges hits across cells, and pages chunks in and out of the
// backend's slots. Residency persists from one stream to the next.
#include <cstdint>
#include <span>
#include <vector>

#include "render/ChunkCache.h"
#include "vastray/streamer/StreamingRenderer.h"

namespace vastray {

class RayStreamer {
public:
    RayStreamer(const PackageInfo& package, const ChunkAttributes& attributes, ChunkBackend& backend,
                ChunkCache& cache, StreamingStats& stats);

    // Starts a render: chunksTouchedThisRender counts from zero again.
    void beginRender();
    uint64_t chunksTouchedThisRender() const { return touchedThisRender_; }

    // Every ray's [tMin, tMax] is its whole range; results[i] belongs to rays[i]. anyHit: one
    // flag per ray (nonzero: a shadow ray, any hit ends it), or empty for all closest-hit.
    Status trace(std::span<const StreamRay> rays, std::span<const uint8_t> anyHit, std::vector<StreamResult>& results);

private:
    struct CellVisit {
        uint32_t chunk;
        float t0, t1;
        uint32_t done;  // traced, or pruned by a nearer hit
    };
    struct RayState {
        uint32_t begin = 0, end = 0;  // cells of this ray in its block's arena
        uint32_t cursor = 0;          // first cell not done
        uint32_t readyChunk = kEmptyCell;  // the chunk counted in ready_ for this ray
    };
    struct Pending {
        uint32_t ray;
        uint32_t cell;  // index into the ray's block arena
    };

    Status traceQueued(std::span<const StreamRay> rays, std::span<const uint8_t> anyHit,
                       std::vector<StreamResult>& results);
    void walkCells(std::span<const StreamRay> rays);
    CellVisit& cellAt(uint32_t ray, uint32_t index) { return arenas_[ray / kBlockRays][index]; }
    bool prunable(const CellVisit& cell, uint32_t ray, const std::vector<StreamResult>& results) const;
    void finishCell(uint32_t ray, uint32_t cell);
    void moveCursor(uint32_t ray, const std::vector<StreamResult>& results);
    Status loadChunks();
    void sortByUrgency(std::vector<uint32_t>& chunks) const;
    void prefetchAhead(const std::vector<uint32_t>& chunks);
    Status traceResident(std::span<const StreamRay> rays, std::vector<StreamResult>& results);

    static constexpr uint32_t kBlockRays = 4096;

    const PackageInfo& package_;
    ChunkAttributes attributes_;
    ChunkBackend& backend_;
    ChunkCache& cache_;
    StreamingStats& stats_;
    // In order (the scene fits: every chunk has a slot): a ray waits only at its next cell, so
    // a nearer hit prunes the cells behind it. Out of order (it does not fit): every cell of
    // every ray is queued at once, so each chunk is paged in at most once per stream, at the
    // price of tracing some cells a front-to-back order would have pruned. Both give the same
    // hits: the closest under one total order (t, front before back, earlier cell).
    bool inOrder_ = true;

    // Residency (kEmptyCell: none).
    std::vector<uint32_t> slotChunk_, chunkSlot_;
    std::vector<uint64_t> slotLastUse_;
    std::vector<uint8_t> touched_;  // traced in this render
    uint64_t touchedThisRender_ = 0;
    uint64_t tick_ = 0;

    // Per stream.
    std::vector<std::vector<CellVisit>> arenas_;  // one per block of kBlockRays rays
    std::vector<RayState> states_;
    std::vector<std::vector<Pending>> waiting_;  // per chunk: cells queued for it
    uint64_t waitingTotal_ = 0;
    std::vector<uint64_t> demand_;  // per chunk: cells not done yet
    std::vector<uint64_t> ready_;   // per chunk: rays whose first cell not done is in it
    std::vector<uint8_t> usedThisStream_;  // traced in this stream
    std::vector<uint8_t> seenThisStream_;  // resident at some point of this stream
    std::vector<StreamRay> batchRays_;
    std::vector<StreamHit> batchHits_;
    std::vector<Pending> batchOwners_;
    std::vector<Pending> taken_;
    std::span<const uint8_t> anyHit_;  // of the stream being traced
    std::vector<StreamResult>* results_ = nullptr;  // of the stream being traced
    bool isAnyHit(uint32_t ray) const { return !anyHit_.empty() && anyHit_[ray] != 0; }
};

}  // namespace vastray
