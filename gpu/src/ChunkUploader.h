#pragma once
// How a decoded chunk's arrays reach its slot. Mapped: the host writes them through the slot's
// mapping (resizable BAR on a discrete GPU) on all cores. DMA (ChunkUploader): the host writes
// them into a block of pinned staging memory (system memory on a discrete GPU) and the transfer
// queue copies them into a slot the host cannot map, while the compute queue walks; the next
// compute submission waits for the copies on a timeline semaphore (PERF_NOTES 44). A block
// keeps its chunk until it is needed for another (least recently used first): a chunk paged in
// again while its block holds it is only copied by the device, the host writes nothing.
// Both run on the render thread, which also submits the compute work; with DMA a decoding
// thread may stage a chunk it has just decoded into a block no chunk has used yet (stage), so
// that the render thread's load of it only records the device's copy (PERF_NOTES 105).
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <vector>

#include "vastray/core/Result.h"
#include "vastray/gpu/VulkanChunkBackend.h"
#include "vastray/gpu/VulkanDevice.h"

namespace vastray::gpu {

// One array of a chunk: `size` bytes at `data` go to `offset` in the slot. With longTriangles set,
// `data` holds three uint32 vertex indices a triangle and the slot gets them as
// kSlotIndexDeltas16 lays them out (shared/StreamTypes.h): `size` = 8 x triangles + 12 x the
// long triangles (*longTriangles, ascending). With grid set, `data` holds Vec3f positions and the
// slot gets each as grid->packedPosition's 8 bytes: `size` = 8 x vertices.
struct SlotCopy {
    uint64_t offset;
    const void* data;
    uint64_t size;
    const std::vector<uint32_t>* longTriangles = nullptr;
    const QuantizationGrid* grid = nullptr;
};

// Writes the arrays into the mapped buffer `to` at base + offset, in 256 KiB pieces on all cores
// (parallel), or on the calling thread alone.
Status copyPieces(GpuBuffer& to, uint64_t base, std::span<const SlotCopy> copies, bool parallel = true);

class ChunkUploader {
public:
    // stagingBytes: the staging area's size, cut into blocks of the largest upload
    // (`largestUpload`), at least two and at most `chunks`; copies are submitted in batches of
    // at least submitBytes (0: a submission per chunk), and before every compute submission
    // (pending). seenLate: completed() answers what the timeline said at the call before
    // (ChunkUploadOptions::copiesSeenLate, for tests).
    static Result<std::unique_ptr<ChunkUploader>> create(VulkanDevice& device, uint64_t stagingBytes,
                                                         uint64_t largestUpload, uint32_t chunks, uint64_t submitBytes,
                                                         bool seenLate = false);
    ~ChunkUploader();  // waits for the copies still running
    ChunkUploader(const ChunkUploader&) = delete;
    ChunkUploader& operator=(const ChunkUploader&) = delete;

    // Stages chunk `chunk`'s arrays (their offsets within `span` bytes) unless a block still
    // holds them, and copies them into `slot` on the transfer queue. A chunk id names the same
    // arrays for the uploader's life (the package's chunk; `span` is checked too). No
    // submission running or waiting for pending() may read what the copy writes (the pager
    // evicts a slot before it is loaded again).
    Status upload(uint32_t chunk, const GpuBuffer& slot, std::span<const SlotCopy> copies, uint64_t span);
    // Any thread, beside the render thread's calls: writes chunk `chunk`'s arrays into a staging
    // block no chunk has used yet, on the calling thread, so that a later upload() of the same
    // arrays (`span` bytes) only copies them on the device. Does nothing when a block holds the
    // chunk already or no unused block is left (it never evicts: the render thread's chunks stay).
    Status stage(uint32_t chunk, std::span<const SlotCopy> copies, uint64_t span);
    // Submits the open batch; what the next compute submission must wait for: every copy so far,
    // or with upTo the copies up to that timeline value (no semaphore when there is none since
    // the last call). A submission that waits for less must not read the slots of later copies.
    Result<SubmitWait> pending(uint64_t upTo = ~0ull);
    // The timeline value of the copies the device has finished (asked now, no wait), and the
    // value of chunk `chunk`'s last copy (0: none the uploader still tracks, so it is done):
    // chunk c's arrays are in its slot once copyValue(c) <= completed().
    Result<uint64_t> completed();
    uint64_t copyValue(uint32_t chunk) const;
    // Waits for every copy and adds the last copies' device times to the figures.
    Status finish();

    const ChunkUploadFigures& figures() const { return figures_; }
    uint64_t stagingBytes() const { return staging_.size(); }
    uint64_t stagingAllocatedBytes() const { return staging_.allocatedBytes(); }

private:
    explicit ChunkUploader(VulkanDevice& device) : device_(device) {}
    Status init(uint64_t stagingBytes);
    Status waitFor(uint64_t value);                 // host wait on the timeline
    Result<uint32_t> victim();                       // a block reserved to stage into, its copies done
    Status open();   // a batch in the ring's next command buffer
    Status close();  // submits the open batch (nothing when none is open)
    void collectTimes(uint32_t index);              // the copy's timestamps, once it is done

    static constexpr uint32_t kNoChunk = ~0u;
    struct Block {
        uint32_t chunk = kNoChunk;
        uint64_t span = 0;       // the chunk's bytes
        uint64_t value = 0;      // timeline value of the last copy reading the block
        uint64_t lastUse = 0;
        bool reserved = false;   // being written (stage, or upload's copy): no other writer takes it
    };
    VulkanDevice& device_;
    GpuBuffer staging_;
    VkSemaphore timeline_ = VK_NULL_HANDLE;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    VkQueryPool queries_ = VK_NULL_HANDLE;  // two per command buffer; none without timestamps
    std::vector<VkCommandBuffer> commands_;
    std::vector<uint64_t> commandValue_;  // the value the command buffer's last copy signals (0: none)
    std::vector<bool> timed_;             // its timestamps are written and not yet collected
    uint32_t nextCommand_ = 0;
    int open_ = -1;  // the command buffer recording a batch, or -1
    uint64_t openBytes_ = 0, submitBytes_ = 0;
    uint64_t blockBytes_ = 0;
    // blocks_, chunkBlock_, tick_ and the figures stage() adds to are shared with the decoding
    // threads: mutex_ guards them; released_ wakes the render thread's victim() waiting for a block
    // that stage() reserved (only stage() releases blocks another thread may wait for).
    mutable std::mutex mutex_;
    std::condition_variable released_;
    std::vector<Block> blocks_;
    std::vector<uint32_t> chunkBlock_;  // per chunk: its block or kNoChunk
    uint64_t tick_ = 0;
    uint64_t submitted_ = 0, completed_ = 0, waitedFor_ = 0;  // timeline values
    bool seenLate_ = false;
    uint64_t lastSeen_ = 0;  // seenLate_: what completed() found at its last call
    ChunkUploadFigures figures_;
};

}  // namespace vastray::gpu
