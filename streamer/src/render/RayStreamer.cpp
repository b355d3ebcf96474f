#include "render/RayStreamer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>
#include <numeric>

#include "render/DemandPager.h"
#include "vastray/core/KdTree.h"

namespace vastray {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// The one order hits are compared in, whatever order cells are traced in: nearer first; at the
// same t a front face before a back face (docs/GEOMETRY.md); then the earlier cell of the ray.
// Within a cell the backend has already applied its own rule (front face, lower triangle).
bool replaces(const StreamHit& h, uint32_t cell, const StreamResult& best) {
    if (!(h.flags & kStreamHitFound)) return false;
    if (!(best.hit.flags & kStreamHitFound) || h.t < best.hit.t) return true;
    if (h.t != best.hit.t) return false;
    const bool front = h.flags & kStreamHitFrontFacing, bestFront = best.hit.flags & kStreamHitFrontFacing;
    if (front != bestFront) return front;
    return cell < best.cell;
}

}  // namespace

RayStreamer::RayStreamer(const PackageInfo& package, const ChunkAttributes& attributes, ChunkBackend& backend,
                         ChunkCache& cache, StreamingStats& stats)
    : package_(package), attributes_(attributes), backend_(backend), cache_(cache), stats_(stats) {
    slotChunk_.assign(backend.slotCount(), kEmptyCell);
    slotLastUse_.assign(backend.slotCount(), 0);
    const size_t chunks = package.chunks.size();
    chunkSlot_.assign(chunks, kEmptyCell);
    touched_.assign(chunks, 0);
    waiting_.resize(chunks);
    demand_.assign(chunks, 0);
    ready_.assign(chunks, 0);
    usedThisStream_.assign(chunks, 0);
    seenThisStream_.assign(chunks, 0);
    inOrder_ = backend.slotCount() >= chunks;
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
                states_[i].begin = states_[i].cursor = uint32_t(arena.size());
                for (const KdLeafVisit& leaf : leaves) {
                    const uint32_t chunk = package_.topTree[leaf.node].firstRef();
                    if (chunk != kEmptyCell && chunk < waiting_.size()) arena.push_back({chunk, leaf.t0, leaf.t1, 0});
                }
                states_[i].end = uint32_t(arena.size());
            }
        }
    });
}

bool RayStreamer::prunable(const CellVisit& cell, uint32_t ray, const std::vector<StreamResult>& results) const {
    // Done, or the cell lies wholly beyond the hit.
    const StreamResult& best = results[ray];
    return (best.hit.flags & kStreamHitFound) && (isAnyHit(ray) || best.hit.t < cell.t0);
}

void RayStreamer::finishCell(uint32_t ray, uint32_t index) {
    CellVisit& cell = cellAt(ray, index);
    if (cell.done) return;
    cell.done = 1;
    --demand_[cell.chunk];
}

// Moves the ray's cursor past finished (and now prunable) cells, keeps ready_ in step and, in
// order, queues the ray at its next cell. A ray whose cells are all done is finished.
void RayStreamer::moveCursor(uint32_t ray, const std::vector<StreamResult>& results) {
    RayState& s = states_[ray];
    if (s.readyChunk != kEmptyCell) --ready_[s.readyChunk], s.readyChunk = kEmptyCell;
    for (; s.cursor < s.end; ++s.cursor) {
        CellVisit& cell = cellAt(ray, s.cursor);
        if (!cell.done && prunable(cell, ray, results)) finishCell(ray, s.cursor);
        if (!cell.done) break;
    }
    if (s.cursor == s.end) return;
    const uint32_t chunk = cellAt(ray, s.cursor).chunk;
    s.readyChunk = chunk, ++ready_[chunk];
    if (inOrder_) waiting_[chunk].push_back({ray, s.cursor}), ++waitingTotal_;
}

// Which chunk to load first: the one for which the largest share of its outstanding cells are
// rays' next cells (so loading it now resolves rays front to back, and in order few rays still
// upstream can arrive later and force a reload), then the one with most cells queued, then the
// lower id.
void RayStreamer::sortByUrgency(std::vector<uint32_t>& chunks) const {
    std::sort(chunks.begin(), chunks.end(), [&](uint32_t a, uint32_t b) {
        const double ra = double(ready_[a]) / double(std::max<uint64_t>(demand_[a], 1));
        const double rb = double(ready_[b]) / double(std::max<uint64_t>(demand_[b], 1));
        if (ra != rb) return ra > rb;
        return waiting_[a].size() != waiting_[b].size() ? waiting_[a].size() > waiting_[b].size() : a < b;
    });
}

// Starts decoding these chunks (most urgent first) on the workers, as far as the host cache
// holds them and at least the next slots' worth.
void RayStreamer::prefetchAhead(const std::vector<uint32_t>& chunks) {
    uint64_t bytes = 0;
    for (size_t i = 0; i < chunks.size(); ++i) {
        bytes += package_.chunks[chunks[i]].residentBytes;
        if (i >= slotChunk_.size() && bytes > cache_.capacity()) break;
        cache_.prefetch(chunks[i]);
    }
}

// Nothing resident has cells queued: load the most urgent chunks into free slots, then into the
// slots whose chunks have the fewest outstanding cells (least recently used among ties).
Status RayStreamer::loadChunks() {
    std::vector<uint32_t> candidates, wanted;
    for (uint32_t c = 0; c < waiting_.size(); ++c)
        if (!waiting_[c].empty() && chunkSlot_[c] == kEmptyCell) candidates.push_back(c);
    sortByUrgency(candidates);
    // A chunk whose queued cells have all been pruned since (nearer hits found elsewhere) is
    // not worth a load: drop those cells first.
    for (uint32_t c : candidates) {
        if (wanted.size() == slotChunk_.size()) break;
        std::vector<Pending>& queue = waiting_[c];
        const size_t before = queue.size();
        std::erase_if(queue, [&](const Pending& p) {
            CellVisit& cell = cellAt(p.ray, p.cell);
            if (cell.done) return true;
            if (!prunable(cell, p.ray, *results_)) return false;
            finishCell(p.ray, p.cell);
            if (p.cell == states_[p.ray].cursor) moveCursor(p.ray, *results_);
            return true;
        });
        waitingTotal_ -= before - queue.size();
        if (!queue.empty()) wanted.push_back(c);
    }
    if (wanted.empty()) return Status::ok();
    for (uint32_t c : wanted) cache_.prefetch(c);  // decode them in parallel
    prefetchAhead(candidates);                     // and what comes after, as far as the cache holds

    std::vector<uint32_t> slots(slotChunk_.size());
    std::iota(slots.begin(), slots.end(), 0u);
    std::stable_sort(slots.begin(), slots.end(), [&](uint32_t a, uint32_t b) {
        const uint32_t ca = slotChunk_[a], cb = slotChunk_[b];
        if ((ca == kEmptyCell) != (cb == kEmptyCell)) return ca == kEmptyCell;
        if (ca != kEmptyCell && demand_[ca] != demand_[cb]) return demand_[ca] < demand_[cb];
        return slotLastUse_[a] < slotLastUse_[b];
    });
    for (size_t i = 0; i < wanted.size(); ++i) {
        const uint32_t chunk = wanted[i], slot = slots[i];
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
    }
    return Status::ok();
}

// One backend call over the queues of resident chunks (up to maxBatchRays cells), then every
// traced cell merges its hit into its ray's result and the ray moves on.
Status RayStreamer::traceResident(std::span<const StreamRay> rays, std::vector<StreamResult>& results) {
    const uint32_t capacity = backend_.maxBatchRays();
    batchRays_.resize(capacity), batchHits_.resize(capacity), batchOwners_.resize(capacity);
    std::vector<ChunkBackend::Batch> batches;
    std::vector<uint32_t> batchChunks;
    uint32_t used = 0;
    for (uint32_t slot = 0; slot < slotChunk_.size() && used < capacity; ++slot) {
        const uint32_t chunk = slotChunk_[slot];
        if (chunk == kEmptyCell || waiting_[chunk].empty()) continue;
        std::vector<Pending>& queue = waiting_[chunk];
        taken_.clear();
        while (!queue.empty() && used + taken_.size() < capacity) {
            const Pending p = queue.back();
            queue.pop_back();
            --waitingTotal_;
            CellVisit& cell = cellAt(p.ray, p.cell);
            if (cell.done) continue;
            if (prunable(cell, p.ray, results)) {
                finishCell(p.ray, p.cell);
                if (p.cell == states_[p.ray].cursor) moveCursor(p.ray, results);
                continue;
            }
            taken_.push_back(p);
        }
        slotLastUse_[slot] = ++tick_;
        if (taken_.empty()) continue;
        if (!usedThisStream_[chunk]) usedThisStream_[chunk] = 1, ++stats_.streamChunksTouched;
        if (!touched_[chunk]) touched_[chunk] = 1, ++touchedThisRender_;
        // One batch of closest-hit rays and one of shadow rays per chunk.
        for (const bool anyHit : {false, true}) {
            const uint32_t first = used;
            for (const Pending& p : taken_) {
                if (isAnyHit(p.ray) != anyHit) continue;
                const CellVisit& cell = cellAt(p.ray, p.cell);
                const StreamRay& r = rays[p.ray];
                const StreamResult& best = results[p.ray];
                StreamRay clipped = r;
                clipped.tMin = std::max(r.tMin, cell.t0);
                clipped.tMax = std::min((best.hit.flags & kStreamHitFound) ? best.hit.t : r.tMax, cell.t1);
                batchRays_[used] = clipped;
                batchOwners_[used] = p;
                ++used;
            }
            if (used == first) continue;
            batches.push_back({slot, std::span<const StreamRay>(batchRays_.data() + first, used - first),
                               std::span<StreamHit>(batchHits_.data() + first, used - first), anyHit});
            batchChunks.push_back(chunk);
        }
    }
    if (batches.empty()) return Status::ok();

    // While the device traces, decode what the next loads will want.
    std::vector<uint32_t> next;
    for (uint32_t c = 0; c < waiting_.size(); ++c)
        if (!waiting_[c].empty() && chunkSlot_[c] == kEmptyCell) next.push_back(c);
    sortByUrgency(next);
    prefetchAhead(next);

    const Clock::time_point start = Clock::now();
    VASTRAY_TRY(backend_.trace(batches));
    stats_.traceSeconds += secondsSince(start);
    stats_.chunkTraces += used;

    const Clock::time_point merge = Clock::now();
    uint32_t at = 0;
    for (size_t b = 0; b < batches.size(); ++b) {
        for (size_t k = 0; k < batches[b].rays.size(); ++k, ++at) {
            const Pending p = batchOwners_[at];
            const StreamHit& h = batchHits_[at];
            StreamResult& best = results[p.ray];
            ++best.cellsTraced;
            best.trianglesTested += h.trianglesTested;
            if (batches[b].anyHit ? (h.flags & kStreamHitFound) && !(best.hit.flags & kStreamHitFound)
                                  : replaces(h, p.cell, best)) {
                best.hit = h;
                best.chunk = batchChunks[b];
                best.cell = p.cell;
            }
            finishCell(p.ray, p.cell);
            if (p.cell == states_[p.ray].cursor) moveCursor(p.ray, results);
        }
    }
    stats_.walkSeconds += secondsSince(merge);
    return Status::ok();
}

void RayStreamer::beginRender() {
    std::fill(touched_.begin(), touched_.end(), 0);
    touchedThisRender_ = 0;
}

// A scene whose chunks all have slots, on a backend that walks whole rays: one backend call per
// batch instead of a host round trip per cell. Once some chunk is resident, every ray goes to
// the walk first; those that reach a chunk without a slot (cold renders) take the queued path.
// Every ray's cells are walked on the host and queued per chunk (ChunkBackend::trace).
Status RayStreamer::trace(std::span<const StreamRay> rays, std::span<const uint8_t> anyHit,
                          std::vector<StreamResult>& results) {
    if (!anyHit.empty() && anyHit.size() != rays.size()) return Status::error("trace: one any-hit flag per ray");
    ++stats_.streams;
    std::fill(usedThisStream_.begin(), usedThisStream_.end(), 0);
    std::fill(seenThisStream_.begin(), seenThisStream_.end(), 0);
    for (uint32_t chunk : slotChunk_)
        if (chunk != kEmptyCell) seenThisStream_[chunk] = 1;
    return traceQueued(rays, anyHit, results);
}

// Each ray waits at its cells in the chunks' queues; chunks are paged in by demand.
Status RayStreamer::traceQueued(std::span<const StreamRay> rays, std::span<const uint8_t> anyHit,
                                std::vector<StreamResult>& results) {
    anyHit_ = anyHit;
    results_ = &results;
    results.assign(rays.size(), StreamResult{});
    const Clock::time_point start = Clock::now();
    walkCells(rays);
    waitingTotal_ = 0;
    for (auto& q : waiting_) q.clear();
    std::fill(demand_.begin(), demand_.end(), 0);
    std::fill(ready_.begin(), ready_.end(), 0);
    for (const auto& arena : arenas_)
        for (const CellVisit& cell : arena) ++demand_[cell.chunk];
    for (uint32_t i = 0; i < rays.size(); ++i) {
        if (!inOrder_)
            for (uint32_t c = states_[i].begin; c < states_[i].end; ++c)
                waiting_[cellAt(i, c).chunk].push_back({i, c}), ++waitingTotal_;
        moveCursor(i, results);
    }
    stats_.walkSeconds += secondsSince(start);

    while (waitingTotal_ > 0) {
        bool residentWaiting = false;
        for (uint32_t chunk : slotChunk_)
            if (chunk != kEmptyCell && !waiting_[chunk].empty()) residentWaiting = true;
        if (!residentWaiting) VASTRAY_TRY(loadChunks());
        VASTRAY_TRY(traceResident(rays, results));
    }
    return Status::ok();
}

}  // namespace vastray
