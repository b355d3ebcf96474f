#pragma once
// The pager of the device wavefront: turns per-chunk demand counters (rays waiting per chunk,
// read from the device after a walk pass) into loads and evictions of the backend's slots,
// with chunks decoded by the host cache's workers. Residency persists from render to render.
#include <cstdint>
#include <span>
#include <vector>

#include "render/ChunkCache.h"
#include "vastray/streamer/StreamingRenderer.h"

namespace vastray {

// One byte per triangle of the chunk (nonzero: its material is single-sided), as
// ChunkBackend::load takes them; empty when the render reads no sidedness.
std::vector<uint8_t> singleSidedFlags(const PackageInfo& package, const ChunkAttributes& attributes,
                                      const DecodedChunk& chunk);

class DemandPager final : public ChunkPager {
public:
    DemandPager(const PackageInfo& package, const ChunkAttributes& attributes, ChunkBackend& backend,
                ChunkCache& cache, StreamingStats& stats);

    void beginRender();  // chunksTouchedThisRender counts from zero again
    uint64_t chunksTouchedThisRender() const { return touchedThisRender_; }

    void beginStream() override;
    std::vector<uint32_t> planLoads(std::span<const uint32_t> demand, std::span<const uint32_t> ahead = {}) override;
    Result<std::vector<uint32_t>> loadPlanned() override;
    void markUsed(std::span<const uint32_t> touched) override;
    void streamTouched(std::span<const uint32_t> touched) override;
    std::span<const uint32_t> chunkSlots() const override { return chunkSlot_; }
    bool allResident() const override;

private:
    const PackageInfo& package_;
    ChunkAttributes attributes_;
    ChunkBackend& backend_;
    ChunkCache& cache_;
    StreamingStats& stats_;
    std::vector<uint32_t> slotChunk_, chunkSlot_;  // kEmptyCell: none
    std::vector<uint64_t> slotLastUse_;
    std::vector<std::pair<uint32_t, uint32_t>> planned_;  // (chunk, slot) that loadPlanned loads
    std::vector<uint8_t> touched_;          // traced in this render
    std::vector<uint8_t> seenThisStream_;   // loaded or resident during this stream
    uint64_t touchedThisRender_ = 0;
    uint64_t tick_ = 0;
};

}  // namespace vastray
