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

struct StreamResult {
    StreamHit hit;                  // closest (or, for shadow rays, any) hit; flags 0 on a miss
    uint32_t chunk = kMissPrimId;   // chunk whose cell produced the hit
    uint32_t cellsTraced = 0;       // chunk traces this ray took
    uint32_t trianglesTested = 0;
};

class RayStreamer {
public:
    RayStreamer(const PackageInfo& package, const ChunkAttributes& attributes, ChunkBackend& backend,
                ChunkCache& cache, StreamingStats& stats);

    // Every ray's [tMin, tMax] is its whole range; results[i] belongs to rays[i].
    Status trace(std::span<const StreamRay> rays, bool anyHit, std::vector<StreamResult>& results);

private:
    struct CellVisit {
        uint32_t chunk;
        float t0, t1;
    };
    struct RayState {
        uint32_t begin = 0, end = 0;  // cells of this ray in its block's arena
        uint32_t cursor = 0;          // next cell to trace
    };

    void walkCells(std::span<const StreamRay> rays);
    void advance(uint32_t ray, bool anyHit, const std::vector<StreamResult>& results);
    const CellVisit& cellOf(uint32_t ray, uint32_t index) const;
    Status loadChunks();
    Status traceResident(std::span<const StreamRay> rays, bool anyHit, std::vector<StreamResult>& results);
    std::vector<uint8_t> singleSidedOf(const DecodedChunk& chunk) const;

    const PackageInfo& package_;
    ChunkAttributes attributes_;
    ChunkBackend& backend_;
    ChunkCache& cache_;
    StreamingStats& stats_;

    // Residency (kEmptyCell: none).
    std::vector<uint32_t> slotChunk_, chunkSlot_;
    std::vector<uint64_t> slotLastUse_;
    std::vector<uint8_t> touched_;
    uint64_t tick_ = 0;

    // Per stream.
    std::vector<std::vector<CellVisit>> arenas_;  // one per block of kBlockRays rays
    std::vector<RayState> states_;
    std::vector<std::vector<uint32_t>> waiting_;  // per chunk: rays whose next cell it is
    uint64_t waitingTotal_ = 0;
    std::vector<StreamRay> batchRays_;
    std::vector<StreamHit> batchHits_;
    std::vector<uint32_t> batchOwners_;
};

}  // namespace vastray
