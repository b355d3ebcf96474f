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

void DemandPager::markUsed(std::span<const uint32_t> touched) {
    const uint64_t now = ++tick_;
    for (size_t c = 0; c < touched.size() && c < chunkSlot_.size(); ++c)
        if (touched[c] && chunkSlot_[c] != kEmptyCell) slotLastUse_[chunkSlot_[c]] = now;
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

std::vector<uint32_t> DemandPager::planLoads(std::span<const uint32_t> demand, std::span<const uint32_t> ahead) {
    const uint32_t chunks = uint32_t(chunkSlot_.size());
    auto count = [](std::span<const uint32_t> counts, uint32_t c) { return c < counts.size() ? counts[c] : 0u; };
    auto isPlanned = [&](uint32_t chunk) {
        return std::any_of(planned_.begin(), planned_.end(), [&](const auto& p) { return p.first == chunk; });
    };
    // Most waiting rays first, then most rays reaching the chunk later; the chunk id breaks
    // ties, so the schedule is deterministic.
    std::vector<uint32_t> wanted, later;
    for (uint32_t c = 0; c < chunks; ++c) {
        if (chunkSlot_[c] != kEmptyCell || isPlanned(c)) continue;
        if (count(demand, c) > 0) wanted.push_back(c);
        else if (count(ahead, c) > 0) later.push_back(c);
    }
    std::stable_sort(wanted.begin(), wanted.end(), [&](uint32_t a, uint32_t b) { return demand[a] > demand[b]; });
    std::stable_sort(later.begin(), later.end(), [&](uint32_t a, uint32_t b) { return ahead[a] > ahead[b]; });
    const size_t slotCount = slotChunk_.size();
    // Decode on the workers, in parallel: what is loaded now, and the chunks rays reach later,
    // as many as there are slots or as half the host cache holds, whichever is more (a
    // prefetched chunk stays in the host cache until used).
    for (uint32_t c : wanted) cache_.prefetch(c);
    uint64_t prefetchBytes = 0;
    for (size_t i = 0; i < later.size(); ++i) {
        prefetchBytes += package_.chunks[later[i]].residentBytes;
        if (i >= slotCount && prefetchBytes > cache_.capacity() / 2) break;
        cache_.prefetch(later[i]);
    }
    // Victims: empty slots, then slots whose chunk nobody waits for, those no ray reaches
    // later, least recently used first. Slots already planned are not candidates.
    std::vector<uint32_t> slots;
    for (uint32_t s = 0; s < slotCount; ++s)
        if (std::none_of(planned_.begin(), planned_.end(), [&](const auto& p) { return p.second == s; }))
            slots.push_back(s);
    if (wanted.size() > slots.size()) wanted.resize(slots.size());
    auto waitedFor = [&](uint32_t slot) {
        const uint32_t c = slotChunk_[slot];
        return c != kEmptyCell && count(demand, c) > 0;
    };
    auto reachedLater = [&](uint32_t slot) {
        const uint32_t c = slotChunk_[slot];
        return c != kEmptyCell && count(ahead, c) > 0;
    };
    std::stable_sort(slots.begin(), slots.end(), [&](uint32_t a, uint32_t b) {
        if ((slotChunk_[a] == kEmptyCell) != (slotChunk_[b] == kEmptyCell)) return slotChunk_[a] == kEmptyCell;
        if (waitedFor(a) != waitedFor(b)) return !waitedFor(a);
        if (reachedLater(a) != reachedLater(b)) return !reachedLater(a);
        return slotLastUse_[a] < slotLastUse_[b];
    });
    std::vector<uint32_t> planned;
    auto plan = [&](uint32_t chunk, uint32_t slot) {
        if (slotChunk_[slot] != kEmptyCell) chunkSlot_[slotChunk_[slot]] = kEmptyCell;  // evicted now
        slotChunk_[slot] = kEmptyCell;
        planned_.push_back({chunk, slot});
        planned.push_back(chunk);
    };
    size_t next = 0;
    for (; next < wanted.size(); ++next) {
        if (waitedFor(slots[next])) break;  // never evict a chunk rays still wait for
        plan(wanted[next], slots[next]);
    }
    // Slots still empty take the chunks most rays reach later (nothing is evicted for them).
    for (size_t i = 0; i < later.size() && next < slots.size() && slotChunk_[slots[next]] == kEmptyCell; ++i, ++next)
        plan(later[i], slots[next]);
    return planned;
}

Result<std::vector<uint32_t>> DemandPager::loadPlanned() {
    std::vector<uint32_t> loaded;
    std::vector<std::pair<uint32_t, uint32_t>> planned;
    planned.swap(planned_);
    for (const auto& [chunk, slot] : planned) {
        auto decoded = cache_.get(chunk);
        if (!decoded) return decoded.status();
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
