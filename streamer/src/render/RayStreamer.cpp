#include "render/RayStreamer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <numeric>

#include "vastray/core/KdTree.h"

namespace vastray {
namespace {

constexpr uint32_t kBlockRays = 4096;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// Closest-hit merge across cells: nearer wins; at the same t a front face beats a back face
// (docs/GEOMETRY.md); otherwise the hit found first (the earlier cell) stays, so the result
// depends only on the ray's own cell order, never on scheduling or budget.
bool replaces(const StreamHit& h, const StreamResult& best) {
    if (!(h.flags & kStreamHitFound)) return false;
    if (!(best.hit.flags & kStreamHitFound) || h.t < best.hit.t) return true;
    return h.t == best.hit.t && (h.flags & kStreamHitFrontFacing) && !(best.hit.flags & kStreamHitFrontFacing);
}

}  // namespace

RayStreamer::RayStreamer(const PackageInfo& package, const ChunkAttributes& attributes, ChunkBackend& backend,
                         ChunkCache& cache, StreamingStats& stats)
    : package_(package), attributes_(attributes), backend_(backend), cache_(cache), stats_(stats) {
    slotChunk_.assign(backend.slotCount(), kEmptyCell);
    slotLastUse_.assign(backend.slotCount(), 0);
    chunkSlot_.assign(package.chunks.size(), kEmptyCell);
    touched_.assign(package.chunks.size(), 0);
    waiting_.resize(package.chunks.size());
}

const RayStreamer::CellVisit& RayStreamer::cellOf(uint32_t ray, uint32_t index) const {
    return arenas_[ray / kBlockRays][index];
}

// Each ray's non-empty cells, front to back, with intervals widened by the traversal margin.
void RayStreamer::walkCells(std::span<const StreamRay> rays) {
    const size_t blocks = (rays.size() + kBlockRays - 1) / kBlockRays;
    arenas_.resize(blocks);
    states_.assign(rays.size(), RayState{});
    tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks, 1), [&](const tbb::blocked_range<size_t>& range) {
        std::vector<KdLeafVisit> leaves;
        for (size_t b = range.begin(); b != range.end(); ++b) {
            std::vector<CellVisit>& arena = arenas_[b];
            arena.clear();
            const size_t end = std::min(rays.size(), (b + 1) * kBlockRays);
            for (size_t i = b * kBlockRays; i < end; ++i) {
                const StreamRay& r = rays[i];
                kdLeavesAlongRay(package_.topTree, package_.bounds, Ray{r.origin, r.direction}, r.tMin, r.tMax,
                                 &leaves);
                states_[i].begin = uint32_t(arena.size());
                for (const KdLeafVisit& leaf : leaves) {
                    const uint32_t chunk = package_.topTree[leaf.node].firstRef();
                    if (chunk != kEmptyCell) arena.push_back({chunk, leaf.t0, leaf.t1});
                }
                states_[i].end = uint32_t(arena.size());
                states_[i].cursor = states_[i].begin;
            }
        }
    });
}

// Queues the ray at its next cell that could still hold a better hit; a ray with none left is done.
void RayStreamer::advance(uint32_t ray, bool anyHit, const std::vector<StreamResult>& results) {
    RayState& s = states_[ray];
    const StreamResult& best = results[ray];
    const bool found = best.hit.flags & kStreamHitFound;
    if (found && anyHit) return;
    for (; s.cursor < s.end; ++s.cursor) {
        const CellVisit& cell = cellOf(ray, s.cursor);
        if (found && best.hit.t < cell.t0) continue;  // the cell lies wholly beyond the hit
        waiting_[cell.chunk].push_back(ray);
        ++waitingTotal_;
        return;
    }
}

std::vector<uint8_t> RayStreamer::singleSidedOf(const DecodedChunk& chunk) const {
    if (!attributes_.singleSided) return {};
    const size_t triangles = chunk.indices.size() / 3;
    std::vector<uint8_t> out(triangles, 0);
    for (size_t t = 0; t < triangles; ++t) {
        const uint32_t m = chunk.materialIds.empty() ? 0u : chunk.materialIds[t];
        out[t] = m < package_.materials.size() && !package_.materials[m].doubleSided;
    }
    return out;
}

// Nothing resident has waiting rays: load the chunks with the most rays waiting (ties: lower
// id) into free slots, then into the least recently used ones (nobody waits for any of them).
Status RayStreamer::loadChunks() {
    std::vector<uint32_t> wanted;
    for (uint32_t c = 0; c < waiting_.size(); ++c)
        if (!waiting_[c].empty() && chunkSlot_[c] == kEmptyCell) wanted.push_back(c);
    std::sort(wanted.begin(), wanted.end(), [&](uint32_t a, uint32_t b) {
        return waiting_[a].size() != waiting_[b].size() ? waiting_[a].size() > waiting_[b].size() : a < b;
    });
    if (wanted.size() > slotChunk_.size()) wanted.resize(slotChunk_.size());
    for (uint32_t c : wanted) cache_.prefetch(c);  // decode them in parallel

    std::vector<uint32_t> slots(slotChunk_.size());
    std::iota(slots.begin(), slots.end(), 0u);
    std::stable_sort(slots.begin(), slots.end(), [&](uint32_t a, uint32_t b) {
        const bool freeA = slotChunk_[a] == kEmptyCell, freeB = slotChunk_[b] == kEmptyCell;
        if (freeA != freeB) return freeA;
        return slotLastUse_[a] < slotLastUse_[b];
    });
    for (size_t i = 0; i < wanted.size(); ++i) {
        const uint32_t chunk = wanted[i], slot = slots[i];
        auto decoded = cache_.get(chunk);
        if (!decoded) return decoded.status();
        if (slotChunk_[slot] != kEmptyCell) chunkSlot_[slotChunk_[slot]] = kEmptyCell;
        slotChunk_[slot] = kEmptyCell;
        VASTRAY_TRY(backend_.load(slot, **decoded, singleSidedOf(**decoded)));
        slotChunk_[slot] = chunk, chunkSlot_[chunk] = slot;
        slotLastUse_[slot] = ++tick_;
        ++stats_.chunkLoads;
        if (!touched_[chunk]) touched_[chunk] = 1, ++stats_.chunksTouched;
    }
    return Status::ok();
}

// One backend call over the queues of resident chunks (up to maxBatchRays rays), then every
// traced ray merges its hit and moves on to its next cell.
Status RayStreamer::traceResident(std::span<const StreamRay> rays, bool anyHit, std::vector<StreamResult>& results) {
    const uint32_t capacity = backend_.maxBatchRays();
    batchRays_.resize(capacity), batchHits_.resize(capacity), batchOwners_.resize(capacity);
    std::vector<ChunkBackend::Batch> batches;
    std::vector<uint32_t> batchChunks;
    uint32_t used = 0;
    for (uint32_t slot = 0; slot < slotChunk_.size() && used < capacity; ++slot) {
        const uint32_t chunk = slotChunk_[slot];
        if (chunk == kEmptyCell || waiting_[chunk].empty()) continue;
        std::vector<uint32_t>& queue = waiting_[chunk];
        const uint32_t take = uint32_t(std::min<size_t>(queue.size(), capacity - used));
        const uint32_t first = used;
        for (uint32_t k = 0; k < take; ++k) {
            const uint32_t ray = queue[queue.size() - take + k];
            const CellVisit& cell = cellOf(ray, states_[ray].cursor);
            const StreamRay& r = rays[ray];
            const StreamResult& best = results[ray];
            StreamRay clipped = r;
            clipped.tMin = std::max(r.tMin, cell.t0);
            clipped.tMax = std::min((best.hit.flags & kStreamHitFound) ? best.hit.t : r.tMax, cell.t1);
            batchRays_[used] = clipped;
            batchOwners_[used] = ray;
            ++used;
        }
        queue.resize(queue.size() - take);
        waitingTotal_ -= take;
        slotLastUse_[slot] = ++tick_;
        batches.push_back({slot, std::span<const StreamRay>(batchRays_.data() + first, take),
                           std::span<StreamHit>(batchHits_.data() + first, take)});
        batchChunks.push_back(chunk);
    }
    if (batches.empty()) return Status::ok();

    // While the device traces, decode what the next loads will want.
    std::vector<uint32_t> next;
    for (uint32_t c = 0; c < waiting_.size(); ++c)
        if (!waiting_[c].empty() && chunkSlot_[c] == kEmptyCell) next.push_back(c);
    std::sort(next.begin(), next.end(), [&](uint32_t a, uint32_t b) {
        return waiting_[a].size() != waiting_[b].size() ? waiting_[a].size() > waiting_[b].size() : a < b;
    });
    for (size_t i = 0; i < next.size() && i < slotChunk_.size(); ++i) cache_.prefetch(next[i]);

    const Clock::time_point start = Clock::now();
    VASTRAY_TRY(backend_.trace(batches, anyHit));
    stats_.traceSeconds += secondsSince(start);
    stats_.chunkTraces += used;

    const Clock::time_point merge = Clock::now();
    uint32_t at = 0;
    for (size_t b = 0; b < batches.size(); ++b) {
        for (size_t k = 0; k < batches[b].rays.size(); ++k, ++at) {
            const uint32_t ray = batchOwners_[at];
            const StreamHit& h = batchHits_[at];
            StreamResult& best = results[ray];
            ++best.cellsTraced;
            best.trianglesTested += h.trianglesTested;
            if (anyHit ? (h.flags & kStreamHitFound) != 0 : replaces(h, best)) {
                const uint32_t cells = best.cellsTraced, triangles = best.trianglesTested;
                best.hit = h;
                best.chunk = batchChunks[b];
                best.cellsTraced = cells, best.trianglesTested = triangles;
            }
            ++states_[ray].cursor;
            advance(ray, anyHit, results);
        }
    }
    stats_.walkSeconds += secondsSince(merge);
    return Status::ok();
}

Status RayStreamer::trace(std::span<const StreamRay> rays, bool anyHit, std::vector<StreamResult>& results) {
    ++stats_.streams;
    results.assign(rays.size(), StreamResult{});
    const Clock::time_point start = Clock::now();
    walkCells(rays);
    waitingTotal_ = 0;
    for (auto& q : waiting_) q.clear();
    for (uint32_t i = 0; i < rays.size(); ++i) advance(i, anyHit, results);
    stats_.walkSeconds += secondsSince(start);

    while (waitingTotal_ > 0) {
        bool residentWaiting = false;
        for (uint32_t chunk : slotChunk_)
            if (chunk != kEmptyCell && !waiting_[chunk].empty()) residentWaiting = true;
        if (!residentWaiting) VASTRAY_TRY(loadChunks());
        VASTRAY_TRY(traceResident(rays, anyHit, results));
    }
    return Status::ok();
}

}  // namespace vastray
