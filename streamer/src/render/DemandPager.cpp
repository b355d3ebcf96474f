#include "render/DemandPager.h"

#include <algorithm>
#include <chrono>
#include <numeric>

namespace vastray {

DemandPager::DemandPager(const PackageInfo& package, const ChunkAttributes& attributes, ChunkBackend& backend,
                         ChunkCache& cache, StreamingStats& stats)
    : package_(package), attributes_(attributes), backend_(backend), cache_(cache), stats_(stats),
      slotChunk_(backend.slotCount(), kEmptyCell), chunkSlot_(package.chunks.size(), kEmptyCell),
      slotLastUse_(backend.slotCount(), 0), touched_(package.chunks.size(), 0),
      seenThisStream_(package.chunks.size(), 0) {}

void DemandPager::beginRender() {
    std::fill(touched_.begin(), touched_.end(), 0);
    touchedThisRender_ = 0;
}

void DemandPager::beginStream() {
    for (uint32_t c = 0; c < chunkSlot_.size(); ++c) seenThisStream_[c] = chunkSlot_[c] != kEmptyCell;
}

bool DemandPager::allResident() const {
    return std::none_of(chunkSlot_.begin(), chunkSlot_.end(), [](uint32_t slot) { return slot == kEmptyCell; });
}

void DemandPager::streamTouched(std::span<const uint32_t> touched) {
    for (size_t c = 0; c < touched.size() && c < touched_.size(); ++c) {
        if (!touched[c]) continue;
        ++stats_.streamChunksTouched;
        if (!touched_[c]) touched_[c] = 1, ++touchedThisRender_;
        if (chunkSlot_[c] != kEmptyCell) slotLastUse_[chunkSlot_[c]] = ++tick_;
    }
}

std::vector<uint8_t> singleSidedFlags(const PackageInfo& package, const ChunkAttributes& attributes,
                                      const DecodedChunk& chunk) {
    if (!attributes.singleSided) return {};
    const size_t triangles = chunk.indices.size() / 3;
    std::vector<uint8_t> out(triangles, 0);
    for (size_t t = 0; t < triangles; ++t) {
        const uint32_t m = chunk.materialIds.empty() ? 0u : chunk.materialIds[t];
        out[t] = m < package.materials.size() && !package.materials[m].doubleSided;
    }
    return out;
}

Result<std::vector<uint32_t>> DemandPager::page(std::span<const uint32_t> demand) {
    std::vector<uint32_t> wanted;
    for (uint32_t c = 0; c < chunkSlot_.size() && c < demand.size(); ++c)
        if (demand[c] > 0 && chunkSlot_[c] == kEmptyCell) wanted.push_back(c);
    // Most waiting rays first; the chunk id breaks ties, so the schedule is deterministic.
    std::stable_sort(wanted.begin(), wanted.end(), [&](uint32_t a, uint32_t b) { return demand[a] > demand[b]; });
    for (uint32_t c : wanted) cache_.prefetch(c);  // decode them on the workers, in parallel
    if (wanted.size() > slotChunk_.size()) wanted.resize(slotChunk_.size());
    // Victims: empty slots, then slots whose chunk nobody waits for, least recently used first.
    std::vector<uint32_t> slots(slotChunk_.size());
    std::iota(slots.begin(), slots.end(), 0u);
    auto waitedFor = [&](uint32_t slot) {
        const uint32_t c = slotChunk_[slot];
        return c != kEmptyCell && c < demand.size() && demand[c] > 0;
    };
    std::stable_sort(slots.begin(), slots.end(), [&](uint32_t a, uint32_t b) {
        if ((slotChunk_[a] == kEmptyCell) != (slotChunk_[b] == kEmptyCell)) return slotChunk_[a] == kEmptyCell;
        if (waitedFor(a) != waitedFor(b)) return !waitedFor(a);
        return slotLastUse_[a] < slotLastUse_[b];
    });
    std::vector<uint32_t> loaded;
    for (size_t i = 0; i < wanted.size(); ++i) {
        const uint32_t chunk = wanted[i], slot = slots[i];
        if (waitedFor(slot)) break;  // never evict a chunk rays still wait for
        auto decoded = cache_.get(chunk);
        if (!decoded) return decoded.status();
        if (slotChunk_[slot] != kEmptyCell) chunkSlot_[slotChunk_[slot]] = kEmptyCell;
        slotChunk_[slot] = kEmptyCell;
        VASTRAY_TRY(backend_.load(slot, **decoded, singleSidedFlags(package_, attributes_, **decoded)));
        slotChunk_[slot] = chunk, chunkSlot_[chunk] = slot;
        slotLastUse_[slot] = ++tick_;
        ++stats_.chunkLoads;
        if (seenThisStream_[chunk]) ++stats_.streamReloads;
        seenThisStream_[chunk] = 1;
        loaded.push_back(chunk);
    }
    return loaded;
}

}  // namespace vastray
