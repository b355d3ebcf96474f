#include "ChunkUploader.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <utility>

#include "VkCheck.h"
#include "shared/StreamTypes.h"

namespace vastray::gpu {
namespace {

// Command buffers in the ring: a batch of copies each, so as many batches may be in flight.
constexpr uint32_t kCommandBuffers = 32;

// A lost device takes no more work (VulkanDevice::fail), whichever call found it.
void failIfLost(VulkanDevice& device, VkResult r) {
    if (r == VK_ERROR_DEVICE_LOST) device.fail(device.info().name + ": the device was lost (VK_ERROR_DEVICE_LOST)");
}

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Words [from, end) of a chunk's indices as kSlotIndexDeltas16 lays them out: two a triangle,
// then three for each long one. `from` is even (pieces start at multiples of 256 KiB).
void packIndexWords(const SlotCopy& c, uint64_t from, uint64_t end, uint32_t* out) {
    const auto* indices = static_cast<const uint32_t*>(c.data);
    const std::vector<uint32_t>& longs = *c.longTriangles;
    const uint64_t pairWords = (c.size - 12 * longs.size()) / 4;
    uint64_t w = from;
    if (w < pairWords) {
        uint64_t t = w / 2;
        auto next = std::lower_bound(longs.begin(), longs.end(), uint32_t(t));
        for (; w < std::min(end, pairWords); w += 2, ++t) {
            if (next != longs.end() && *next == t) {
                out[w - from] = uint32_t(pairWords + 3 * uint64_t(next - longs.begin()));
                out[w + 1 - from] = kSlotLongTriangle;
                ++next;
                continue;
            }
            const uint32_t first = indices[3 * t];
            out[w - from] = first;
            out[w + 1 - from] = ((indices[3 * t + 1] - first) & 0xFFFFu) | (indices[3 * t + 2] - first) << 16;
        }
    }
    for (; w < end; ++w) {
        const uint64_t o = w - pairWords;
        out[w - from] = indices[3 * uint64_t(longs[o / 3]) + o % 3];
    }
}

}  // namespace

// One core writing through a write-combined mapping manages a few GB/s, well below what PCIe
// takes (most arrays of a 4 MiB chunk are under 1 MiB, so larger pieces left them to one core),
// and a loop per array paid its start and join for each (PERF_NOTES 40): one loop over the
// pieces of all arrays.
Status copyPieces(GpuBuffer& to, uint64_t base, std::span<const SlotCopy> copies, bool parallel) {
    constexpr uint64_t kPiece = 256 << 10;
    struct Piece {
        const SlotCopy* copy;
        uint64_t at, size;
    };
    std::vector<Piece> pieces;
    for (const SlotCopy& c : copies)
        for (uint64_t at = 0; at < c.size; at += kPiece) pieces.push_back({&c, at, std::min(kPiece, c.size - at)});
    auto run = [&](const Piece& p) {
        if (p.copy->size == 0) return true;
        if (p.copy->grid) {  // 8 bytes a vertex; pieces start at multiples of 256 KiB
            const auto* positions = static_cast<const Vec3f*>(p.copy->data) + p.at / 8;
            std::vector<uint64_t> packed(p.size / 8);
            p.copy->grid->packPositions(positions, packed.size(), packed.data());
            return to.upload(packed.data(), p.size, base + p.copy->offset + p.at).isOk();
        }
        if (!p.copy->longTriangles) {
            const auto* from = static_cast<const uint8_t*>(p.copy->data) + p.at;
            return to.upload(from, p.size, base + p.copy->offset + p.at).isOk();
        }
        std::vector<uint32_t> packed(p.size / 4);
        packIndexWords(*p.copy, p.at / 4, (p.at + p.size) / 4, packed.data());
        return to.upload(packed.data(), p.size, base + p.copy->offset + p.at).isOk();
    };
    std::atomic<bool> failed{false};
    if (!parallel || pieces.size() == 1) {
        for (const Piece& p : pieces)
            if (!run(p)) failed = true;
    } else if (pieces.size() > 1)
        tbb::parallel_for(size_t(0), pieces.size(), [&](size_t i) {
            if (!run(pieces[i])) failed = true;
        });
    return failed ? Status::error("copy to the device failed") : Status::ok();
}

Result<std::unique_ptr<ChunkUploader>> ChunkUploader::create(VulkanDevice& device, uint64_t stagingBytes,
                                                             uint64_t largestUpload, uint32_t chunks,
                                                             uint64_t submitBytes, bool seenLate) {
    std::unique_ptr<ChunkUploader> u(new ChunkUploader(device));
    u->submitBytes_ = submitBytes;
    u->seenLate_ = seenLate;
    u->blockBytes_ = (std::max<uint64_t>(largestUpload, 1) + 255) / 256 * 256;
    const uint64_t blocks = std::clamp<uint64_t>(stagingBytes / u->blockBytes_, 2, std::max<uint32_t>(chunks, 2));
    u->blocks_.resize(blocks);
    u->chunkBlock_.assign(chunks, kNoChunk);
    VASTRAY_TRY(u->init(blocks * u->blockBytes_).withContext("chunk uploads: "));
    return u;
}

Status ChunkUploader::init(uint64_t stagingBytes) {
    auto staging = device_.createBuffer(stagingBytes, VulkanDevice::MemoryUse::Staging);
    if (!staging) return staging.status();
    staging_ = std::move(staging).value();
    figures_.stagingBytes = staging_.size();
    const VkDevice d = device_.handle();
    auto type = vkStruct<VkSemaphoreTypeCreateInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_TYPE_CREATE_INFO);
    type.semaphoreType = VK_SEMAPHORE_TYPE_TIMELINE;
    auto semaphore = vkStruct<VkSemaphoreCreateInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO);
    semaphore.pNext = &type;
    VASTRAY_VK_TRY(vkCreateSemaphore(d, &semaphore, nullptr, &timeline_));
    auto poolInfo = vkStruct<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
    poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    poolInfo.queueFamilyIndex = device_.transferFamily();
    VASTRAY_VK_TRY(vkCreateCommandPool(d, &poolInfo, nullptr, &pool_));
    commands_.resize(kCommandBuffers);
    commandValue_.assign(kCommandBuffers, 0);
    timed_.assign(kCommandBuffers, false);
    auto alloc = vkStruct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
    alloc.commandPool = pool_;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = kCommandBuffers;
    VASTRAY_VK_TRY(vkAllocateCommandBuffers(d, &alloc, commands_.data()));
    // Timestamps around each copy, reset from the host (a transfer queue cannot reset queries).
    if (device_.transferTimestampValidBits() > 0 && device_.hostQueryReset()) {
        auto info = vkStruct<VkQueryPoolCreateInfo>(VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO);
        info.queryType = VK_QUERY_TYPE_TIMESTAMP;
        info.queryCount = 2 * kCommandBuffers;
        if (vkCreateQueryPool(d, &info, nullptr, &queries_) != VK_SUCCESS) queries_ = VK_NULL_HANDLE;
    }
    figures_.dmaTimed = queries_ != VK_NULL_HANDLE;
    return Status::ok();
}

ChunkUploader::~ChunkUploader() {
    (void)finish();
    const VkDevice d = device_.handle();
    // After a failed wait the copies may still run: the device's destructor waits for idle
    // first, so leaking nothing here would free memory a copy reads. Wait for idle instead.
    if (completed_ < submitted_) vkDeviceWaitIdle(d);
    if (queries_) vkDestroyQueryPool(d, queries_, nullptr);
    if (pool_) vkDestroyCommandPool(d, pool_, nullptr);  // frees the command buffers
    if (timeline_) vkDestroySemaphore(d, timeline_, nullptr);
}

Status ChunkUploader::waitFor(uint64_t value) {
    if (value <= completed_) return Status::ok();
    auto info = vkStruct<VkSemaphoreWaitInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_WAIT_INFO);
    info.semaphoreCount = 1;
    info.pSemaphores = &timeline_;
    info.pValues = &value;
    const double limit = std::clamp(device_.submitTimeoutSeconds(), 0.0, 1e9);
    const VkResult r = vkWaitSemaphores(device_.handle(), &info, uint64_t(limit * 1e9));
    if (r == VK_TIMEOUT) {
        char seconds[32];
        std::snprintf(seconds, sizeof seconds, "%g", limit);
        const std::string message = device_.info().name + ": a chunk copy did not finish within " + seconds +
                                    " s (hung device?); it takes no more work";
        device_.fail(message);
        return Status::error(message);
    }
    failIfLost(device_, r);
    VASTRAY_VK_TRY(r);
    completed_ = value;
    return Status::ok();
}

// An empty block, else the least recently used, reserved for the caller's write; a copy still
// reading it is waited for. Blocks that stage() is writing are not taken (when every block is,
// this waits for one).
Result<uint32_t> ChunkUploader::victim() {
    uint32_t best = kNoChunk;
    uint64_t value = 0;
    {
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
            for (uint32_t b = 0; b < blocks_.size(); ++b) {
                if (blocks_[b].reserved) continue;
                if (blocks_[b].chunk == kNoChunk) {
                    best = b;
                    break;
                }
                if (best == kNoChunk || blocks_[b].lastUse < blocks_[best].lastUse) best = b;
            }
            if (best != kNoChunk) break;
            released_.wait(lock);
        }
        Block& block = blocks_[best];
        block.reserved = true;
        if (block.chunk != kNoChunk && chunkBlock_[block.chunk] == best) chunkBlock_[block.chunk] = kNoChunk;
        block.chunk = kNoChunk;
        value = block.value;
    }
    if (value > completed_) {
        const auto start = std::chrono::steady_clock::now();
        Status s = value > submitted_ ? close() : Status::ok();  // read by the batch still open
        if (s.isOk()) s = waitFor(value);
        figures_.stagingWaitSeconds += secondsSince(start);
        if (!s.isOk()) {
            std::lock_guard<std::mutex> lock(mutex_);
            blocks_[best].reserved = false;
            return s;
        }
    }
    return best;
}

Status ChunkUploader::stage(uint32_t chunk, std::span<const SlotCopy> copies, uint64_t span) {
    if (chunk >= chunkBlock_.size() || span > blockBytes_)
        return Status::error("chunk " + std::to_string(chunk) + " of " + std::to_string(span) +
                             " bytes does not fit the staging blocks");
    uint32_t b = kNoChunk;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (chunkBlock_[chunk] != kNoChunk) return Status::ok();
        // A block no copy has read (value 0): nothing to wait for, and nobody's chunk is lost.
        for (uint32_t i = 0; i < blocks_.size() && b == kNoChunk; ++i)
            if (blocks_[i].chunk == kNoChunk && !blocks_[i].reserved && blocks_[i].value == 0) b = i;
        if (b == kNoChunk) return Status::ok();
        blocks_[b].reserved = true;
    }
    const auto start = std::chrono::steady_clock::now();
    const Status s = copyPieces(staging_, b * blockBytes_, copies, false);
    {
        std::lock_guard<std::mutex> lock(mutex_);
        Block& block = blocks_[b];
        block.reserved = false;
        if (s.isOk() && chunkBlock_[chunk] == kNoChunk) {  // else the render thread staged it meanwhile
            block.chunk = chunk, block.span = span, block.lastUse = ++tick_;
            chunkBlock_[chunk] = b;
            ++figures_.stagedOnDecode;
            figures_.stageSeconds += secondsSince(start);
        }
    }
    released_.notify_all();
    return s;
}

void ChunkUploader::collectTimes(uint32_t index) {
    if (!timed_[index] || commandValue_[index] > completed_) return;
    timed_[index] = false;
    uint64_t ticks[2] = {};
    const VkResult r =
        vkGetQueryPoolResults(device_.handle(), queries_, 2 * index, 2, sizeof ticks, ticks, 8, VK_QUERY_RESULT_64_BIT);
    if (r != VK_SUCCESS) return;
    const uint32_t bits = device_.transferTimestampValidBits();
    const uint64_t mask = bits >= 64 ? ~0ull : (1ull << bits) - 1;
    figures_.dmaSeconds += double((ticks[1] - ticks[0]) & mask) * device_.timestampPeriodNs() * 1e-9;
}

Status ChunkUploader::upload(uint32_t chunk, const GpuBuffer& slot, std::span<const SlotCopy> copies, uint64_t span) {
    if (chunk >= chunkBlock_.size() || span > blockBytes_)
        return Status::error("chunk " + std::to_string(chunk) + " of " + std::to_string(span) +
                             " bytes does not fit the staging blocks");
    uint32_t b = kNoChunk;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        const uint32_t held = chunkBlock_[chunk];
        if (held != kNoChunk && blocks_[held].span == span) {
            b = held;
            ++figures_.stagingHits;  // staged before (or as it was decoded) and kept: the device copies it
        }
    }
    if (b == kNoChunk) {
        auto free = victim();
        if (!free) return free.status();
        b = *free;
        const auto start = std::chrono::steady_clock::now();
        const Status copied = copyPieces(staging_, b * blockBytes_, copies);
        figures_.hostCopySeconds += secondsSince(start);
        {
            std::lock_guard<std::mutex> lock(mutex_);
            blocks_[b].reserved = false;
            if (copied.isOk()) {
                const uint32_t old = chunkBlock_[chunk];  // a block of other arrays of the chunk: now free
                if (old != kNoChunk && old != b) blocks_[old].chunk = kNoChunk;
                blocks_[b].chunk = chunk, blocks_[b].span = span, chunkBlock_[chunk] = b;
            }
        }
        VASTRAY_TRY(copied);
    }
    {
        std::lock_guard<std::mutex> lock(mutex_);
        Block& block = blocks_[b];
        block.lastUse = ++tick_;
        block.value = submitted_ + 1;
    }
    const uint64_t at = b * blockBytes_;
    if (open_ < 0) VASTRAY_TRY(open());
    std::vector<VkBufferCopy> regions;
    uint64_t bytes = 0;
    for (const SlotCopy& c : copies)
        if (c.size > 0) regions.push_back({at + c.offset, c.offset, c.size}), bytes += c.size;
    const VkCommandBuffer cmd = commands_[uint32_t(open_)];
    // Copies into one slot follow each other in queue order: a chunk loaded and evicted before
    // any kernel waited for its copy must not land after the copy that replaces it.
    auto order = vkStruct<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
    order.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    order.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &order, 0, nullptr,
                         0, nullptr);
    if (!regions.empty())
        vkCmdCopyBuffer(cmd, staging_.handle(), slot.handle(), uint32_t(regions.size()), regions.data());
    figures_.dmaBytes += bytes;
    ++figures_.dmaCopies;
    openBytes_ += bytes;
    return openBytes_ >= submitBytes_ ? close() : Status::ok();
}

// Begins the next command buffer of the ring (its last batch done) for a batch of copies.
Status ChunkUploader::open() {
    const uint32_t index = nextCommand_;
    nextCommand_ = (nextCommand_ + 1) % kCommandBuffers;
    VASTRAY_TRY(waitFor(commandValue_[index]));
    collectTimes(index);
    const VkCommandBuffer cmd = commands_[index];
    VASTRAY_VK_TRY(vkResetCommandBuffer(cmd, 0));
    auto begin = vkStruct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VASTRAY_VK_TRY(vkBeginCommandBuffer(cmd, &begin));
    if (queries_) {
        vkResetQueryPool(device_.handle(), queries_, 2 * index, 2);
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, 2 * index);
    }
    open_ = int(index), openBytes_ = 0;
    return Status::ok();
}

// Ends the open batch and submits it, signalling the next timeline value when its copies are done.
Status ChunkUploader::close() {
    if (open_ < 0) return Status::ok();
    const uint32_t index = uint32_t(open_);
    open_ = -1;
    const VkCommandBuffer cmd = commands_[index];
    if (queries_) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, 2 * index + 1);
    VASTRAY_VK_TRY(vkEndCommandBuffer(cmd));
    const uint64_t value = submitted_ + 1;
    auto timeline = vkStruct<VkTimelineSemaphoreSubmitInfo>(VK_STRUCTURE_TYPE_TIMELINE_SEMAPHORE_SUBMIT_INFO);
    timeline.signalSemaphoreValueCount = 1;
    timeline.pSignalSemaphoreValues = &value;
    auto submit = vkStruct<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
    submit.pNext = &timeline;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    submit.signalSemaphoreCount = 1;
    submit.pSignalSemaphores = &timeline_;
    const VkResult r = vkQueueSubmit(device_.transferQueue(), 1, &submit, VK_NULL_HANDLE);
    failIfLost(device_, r);
    VASTRAY_VK_TRY(r);
    submitted_ = value;
    commandValue_[index] = value;
    timed_[index] = queries_ != VK_NULL_HANDLE;
    ++figures_.dmaSubmits;
    return Status::ok();
}

Result<SubmitWait> ChunkUploader::pending(uint64_t upTo) {
    VASTRAY_TRY(close());
    SubmitWait wait;
    const uint64_t value = std::min(upTo, submitted_);
    if (value <= waitedFor_) return wait;
    waitedFor_ = value;
    wait.semaphore = timeline_;
    wait.value = value;
    // Only the kernels read the slots (fills and copies of the compute queue never do).
    wait.stages = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    return wait;
}

Result<uint64_t> ChunkUploader::completed() {
    uint64_t value = 0;
    const VkResult r = vkGetSemaphoreCounterValue(device_.handle(), timeline_, &value);
    failIfLost(device_, r);
    VASTRAY_VK_TRY(r);
    completed_ = std::max(completed_, value);
    if (!seenLate_) return completed_;
    return std::exchange(lastSeen_, completed_);
}

uint64_t ChunkUploader::copyValue(uint32_t chunk) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const uint32_t b = chunk < chunkBlock_.size() ? chunkBlock_[chunk] : kNoChunk;
    return b == kNoChunk ? 0 : blocks_[b].value;
}

Status ChunkUploader::finish() {
    Status s = close();
    if (s.isOk()) s = waitFor(submitted_);
    for (uint32_t i = 0; i < kCommandBuffers; ++i) collectTimes(i);
    return s;
}

}  // namespace vastray::gpu
