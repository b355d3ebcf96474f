#pragma once
// The Vulkan backend of the streaming renderer: a pool of chunk slots and the device
// wavefront's path state, all allocated once from the memory budget. Whole renders run on the
// device (gpu/src/Wavefront.h); the host only pages chunks in between walk passes.
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "vastray/core/Result.h"
#include "vastray/gpu/VulkanDevice.h"
#include "vastray/streamer/StreamingRenderer.h"

namespace vastray::gpu {

// How a budget is split: every figure is what the device is asked to allocate.
struct PoolPlan {
    uint64_t slotBytes = 0;      // one chunk slot: the largest chunk's upload (ChunkLayout)
    uint32_t slots = 0;          // chunk slots (never more than the package's chunks)
    uint32_t batchRays = 0;      // paths per wave of the device wavefront
    // Pixels of the output buffer (the tiles' colours and AOVs, read back by the host): a wave's,
    // and out of core with the outputs off the budget (outputInDeviceMemory false)
    // kOutOfCoreOutputScale times that, so that the streamed waves' window holds more tiles
    // (up to kMaxWindowTiles) than the wave has groups for (docs/RENDERING.md, "Streamed waves").
    uint64_t outputPixels = 0;
    uint64_t rayBytes = 0;       // their state (rays, walk records, path vectors), and the tile
                                 // outputs when those are in device memory (outputInDeviceMemory)
    uint64_t tableBytes = 0;     // slot table, top-level tree, per-chunk tables, parameters, materials
    uint64_t totalBytes = 0;     // all of the above, <= the budget
    uint64_t minimumBytes = 0;   // one slot + the minimal batch + the tables (+ the staging area
                                 // when it is in device memory)
    bool outputInDeviceMemory = true;  // the tile outputs count against the budget
    // DMA uploads with the staging area in device memory (lavapipe): the staging taken from the
    // budget (counted in totalBytes; two slots at least, a slot per chunk at most); 0 otherwise.
    uint64_t stagingBytes = 0;
    // Device bytes kept from the budget for the render's environment map, the scene's volumes and
    // its textures (counted in totalBytes and minimumBytes, allocated by the render that uses
    // them); 0: none.
    uint64_t reservedBytes = 0;
    // Of reservedBytes, the textures' (textureReserveBytes); the rest is the map's and volumes'.
    uint64_t textureBytes = 0;
    // What the plan leaves of the budget (budget - totalBytes: the wave grows by doubling, and
    // slots beyond the chunk count are not made): paged volumes take it for brick slots besides
    // their reserve (docs/RENDERING.md, "Volumes out of core").
    uint64_t spareBytes = 0;
    // The wave's path state (StateLayout) lies in host memory, read and written by the kernels
    // across the bus (PathStateMemory): out of core only. Where host memory is outside the
    // device's heaps (outputInDeviceMemory false) it is not counted against the budget and the
    // slots take all of it; else it is counted as in device memory.
    bool stateInHostMemory = false;
};

// How chunk data reaches the slots (gpu/src/ChunkUploader.h). Mapped: the host writes each chunk
// through the slot's mapping (resizable BAR on a discrete GPU) on all cores. Dma: the host
// writes it into a block of pinned staging memory and the transfer queue (a DMA engine where
// the device has one) copies it into slots in device memory the host cannot map, overlapping
// the walk; a block keeps its chunk, so a chunk paged in again while its block holds it costs
// the host nothing. Auto: Dma on a discrete GPU (device-only memory and system memory the device
// can read: VulkanDevice::hasSeparateMemory), Mapped elsewhere (PERF_NOTES 44 measured both on
// an H200: Dma 13 % faster at 4x over budget).
enum class ChunkUploadMode { Auto, Mapped, Dma };

// Upload figures of a backend's life, for benchmarks (bytes_uploaded and upload_seconds in
// StreamingStats stay the totals: upload_seconds is the host's time in ChunkBackend::load).
struct ChunkUploadFigures {
    double hostCopySeconds = 0;  // writing chunk arrays into slots (Mapped) or staging (Dma)
    double dmaSeconds = 0;       // the transfer queue's copies, from timestamps (Dma; 0 untimed)
    double stagingWaitSeconds = 0;  // waiting for staging memory still being copied (Dma)
    uint64_t dmaBytes = 0, dmaCopies = 0, dmaSubmits = 0;
    uint64_t stagingHits = 0;    // DMA copies of a chunk the staging area still held (no host copy)
    uint64_t stagedOnDecode = 0;  // chunks the decoding threads wrote into staging (stageOnDecode)
    double stageSeconds = 0;      // their time doing it (summed over the threads, off the render thread)
    bool dmaTimed = false;       // the transfer queue has timestamps
    uint64_t stagingBytes = 0;   // the staging ring (host memory on a discrete GPU)
};

// The staging area's size when ChunkUploadOptions asks for none in particular: a sixteenth of the
// machine's memory, within [1 GiB, 16 GiB] (out of core a chunk still staged is copied by the DMA
// engine alone: on the H200 a 1 GiB area, half of city 64M's chunks, left 0.48 s of host copies
// where 4 GiB left 0.29 s; PERF_NOTES 56).
uint64_t defaultStagingBytes();

struct ChunkUploadOptions {
    ChunkUploadMode mode = ChunkUploadMode::Auto;
    // Dma: the staging area's size when it lies in host memory (pinned system memory: not
    // counted against the device budget; it is host memory besides the host chunk cache), cut
    // into blocks of one slot: at least two, at most one per chunk of the package. Where the
    // staging memory is device memory (lavapipe) it is taken from the budget (PoolPlan::stagingBytes).
    // kStagingAuto (the default): defaultStagingBytes().
    static constexpr uint64_t kStagingAuto = 0;
    uint64_t stagingBytes = kStagingAuto;
    // Dma: chunk copies are submitted to the transfer queue in batches of at least this many
    // bytes (0: one submission per chunk), and whatever is staged before each compute submission.
    uint64_t submitBytes = 0;
    // Dma, for tests: the uploader sees a copy done one query later than the timeline says (a
    // render with partial residency then finds every copy it made during a step still running
    // after it, as a fast device does when the bus is the bottleneck; lavapipe's copies are done
    // long before its kernels). Later than true is always safe: the step waits for less and
    // reads less.
    bool copiesSeenLate = false;
    // Dma: a chunk is written into a staging block as soon as it is decoded, by the thread that
    // decoded it (ChunkBackend::stage), while a block no chunk has used is left; its load then only
    // records the device's copy. Off: the render thread writes each chunk at its first load (for
    // comparisons; PERF_NOTES 105).
    bool stageOnDecode = true;
    // When set, the backend adds its figures here when it is destroyed.
    ChunkUploadFigures* figures = nullptr;
};

// The smallest wave a budget must hold besides one chunk slot (~300 KiB of path state).
constexpr uint32_t kMinBatchRays = 1024;
// The largest wave: its walk dispatches two rays per path in workgroups of 64, and 65535
// workgroups along x is what every device supports.
constexpr uint32_t kMaxBatchRays = 65535u * 32u;
// A quarter of the budget goes to the wave (at most kMaxBatchRays paths); beyond that the wave
// grows into what the slots leave only up to this many paths (~77 MiB), so that scenes sharing
// a service's pool do not each take all of it.
constexpr uint32_t kGrowBatchRays = 1u << 18;
// Out of core the wave takes waveShareOutOfCore of the budget up to this many paths (~188 MiB of
// path state); what a larger wave would take goes to chunk slots. Beyond it the walk gains little
// while fewer slots mean more reloads, and too few slots leave no room to upload beside the walk
// (PERF_NOTES 95: city 64M, 16 MiB chunks, at 4x over a 475 MiB budget, scene kept open, H100:
// 655 k paths 0.475 s, 786 k 0.464-0.471 s, 852 k 0.460-0.465 s, 983 k 0.411-0.417 s, 1.11 M
// 0.585-0.605 s, 1.24 M 0.583-0.585 s; with 4 MiB chunks PERF_NOTES 63 had put it at 655 k). A
// budget below ~400 MiB never reaches it. Measured again with 8-byte positions (PERF_NOTES 99: at
// 512 MiB, 49 slots, 0.367 s kept open; 1.11-1.38 M paths 0.49-0.50 s): the cliff follows the wave.
constexpr uint32_t kMaxOutOfCoreBatchRays = 960u * 1024u;

// Out of core with the tile outputs in host memory (off the budget), the output buffer holds this
// many waves' pixels: a streamed window of up to 32 tiles instead of 16 (PERF_NOTES 91: city 10M
// at 4x over budget on an H100, 3,288 -> 2,872 loads and 0.58-0.62 -> 0.53 s kept open; 64 tiles no
// better; 16x and city 64M unchanged). Host memory only: ~68 bytes a pixel.
constexpr uint32_t kOutOfCoreOutputScale = 2;

// Where a wave's path state lives out of core (docs/RENDERING.md, "Path state in host memory").
// Device: in the budget, beside the slots (a wave of waveShareOutOfCore of it, at most
// kMaxOutOfCoreBatchRays paths). Host: in pinned host memory off the budget, a wave of
// kHostStatePaths paths, the slots taking the whole budget; every kernel then reads and writes
// the state across the bus (~200 bytes a path a bounce, each way), which costs more than a small
// wave saves at 4x over budget and far less at 16x (PERF_NOTES 77, city 10M on an H100: 4x 0.85
// s in device memory against 1.61 s in host memory, 8x 1.72 against 1.72 s, 16x 4.40 against
// 1.93 s). Auto: Host where that pays, resolvePathStateMemory.
enum class PathStateMemory { Auto, Device, Host };
Result<PathStateMemory> parsePathStateMemory(std::string_view name);  // auto, device or host
// A wave in host memory: 2^19 paths (~180 MiB of host memory with its tile outputs). Of 256 k,
// 512 k and 1 M paths 512 k was fastest at 8x and 16x and within 3 % at 4x (PERF_NOTES 77).
constexpr uint32_t kHostStatePaths = 1u << 19;
// Auto puts the state in host memory where the package's resident chunks exceed this many
// budgets: the measured crossing of the two modes (PERF_NOTES 93, city 10M 16 spp depth 5 on an
// H100 with a window of 32 tiles: 6x 1.21 s in the budget against 1.24 s in host memory, 8x 1.89
// against 1.30-1.38 s; 8 before the walk bits moved and the window widened, PERF_NOTES 77; the
// ratio is the scene's, so the rule holds for other frames only as far as their paths cost the
// same per bounce).
constexpr double kHostStateOversubscription = 6.0;
// Auto's answer: Host on a device whose memory is apart from the host's (separateMemory:
// VulkanDevice::hasSeparateMemory, a discrete GPU; elsewhere host memory is the device's and
// moving the state there only takes it from the slots), for a package without volumes (their
// paged tracking keeps per-path records in device memory) whose chunks' resident bytes exceed
// kHostStateOversubscription budgets; else Device. Device and Host are kept as asked, but Host for
// a package with volumes is an error.
Result<PathStateMemory> resolvePathStateMemory(PathStateMemory asked, bool separateMemory, const PackageInfo& package,
                                               const ChunkAttributes& attributes, uint64_t budget);
// The bytes of the package's chunks as slots hold them (ChunkLayout), all of them.
uint64_t residentChunkBytes(const PackageInfo& package, const ChunkAttributes& attributes);

// Splits `budget` between slots and the ray batch; an error (naming the minimum) when the
// budget cannot hold one slot plus a minimal batch. The tile outputs the host reads back live
// in host-cached memory: in system memory on a discrete GPU, where they do not count against
// the device budget (outputInDeviceMemory false), in the one memory of lavapipe or an
// integrated GPU, where they do (true; also the conservative answer when the device is unknown).
// When the slots cannot hold every chunk, the wave gets waveShareOutOfCore of the budget (in
// (0, 1); the default, half, is PERF_NOTES 25's measured choice).
// reservedBytes: the environment map's and the volumes' (environmentBytes, volumeReserveBytes);
// the package's textures' (textureReserveBytes) are added to it here.
// stagingInDeviceMemory: for DMA uploads whose staging area is device memory, the staging bytes
// asked for (ChunkUploadOptions::stagingBytes), kept from the budget as whole slots, two at least
// and one per chunk at most (PoolPlan::stagingBytes); 0: none.
// hostStatePaths > 0: out of core the wave's state lies in host memory (PoolPlan::stateInHostMemory),
// a wave of that many paths (fewer where the state counts and the budget cannot hold them).
// maxOutOfCorePaths: out of core with the state in the budget, the wave's cap (kMaxOutOfCoreBatchRays
// by default; at least kMinBatchRays, at most kMaxBatchRays).
constexpr double kWaveShareOutOfCore = 0.5;
Result<PoolPlan> planPool(const PackageInfo& package, const ChunkAttributes& attributes, uint64_t budget,
                          bool outputInDeviceMemory = true, double waveShareOutOfCore = kWaveShareOutOfCore,
                          uint64_t stagingInDeviceMemory = 0, uint64_t reservedBytes = 0,
                          uint32_t hostStatePaths = 0, uint32_t maxOutOfCorePaths = kMaxOutOfCoreBatchRays);

// The upload mode Auto resolves to on this device.
ChunkUploadMode resolveUploadMode(const VulkanDevice& device, ChunkUploadMode mode);

// The device bytes an environment map takes (environmentBytes(options.environment) is what a
// render with those options needs kept: reservedBytes below); 0 without a map.
uint64_t environmentBytes(const Environment& environment);
// The device bytes the package's volumes take in core; 0 without volumes.
uint64_t volumeBytes(const PackageInfo& package);
// What a render of the package at this budget keeps for its volumes (reservedBytes below,
// besides the map's): all of volumeBytes when that is at most kVolumeShareOutOfCore of the
// budget; else that share (at least the tables and the fewest brick slots), through which the
// bricks are paged, and the backend adds what the wave and the chunk slots leave
// (PoolPlan::spareBytes; docs/RENDERING.md, "Volumes out of core"). Paged, the share also sets
// the wave (what it leaves); 0.4 (a fifth more paths, a tenth fewer slots) took 8 % fewer loads
// and 2 % more paging steps over nine lavapipe cloud renders, more steps where half the bricks
// were resident (61 -> 80, 190 -> 225): not kept.
constexpr double kVolumeShareOutOfCore = 0.5;
uint64_t volumeReserveBytes(const PackageInfo& package, uint64_t budget);
// What a render of the package at this budget keeps for its textures (planPool adds it to the
// reserve itself): every page when that is at most kTextureShareOutOfCore of the budget; else
// that share (at least the tables, the fewest page slots and the cut-outs' level-0 pages, which
// stay resident), through which the pages are paged (docs/RENDERING.md, "Textures out of core").
// 0 without textures.
constexpr double kTextureShareOutOfCore = 0.25;
uint64_t textureReserveBytes(const PackageInfo& package, uint64_t budget);
// The device bytes the package's textures take in core (every page); 0 without textures.
uint64_t textureBytes(const PackageInfo& package);
// A texture pool holds at least this many pages (besides the cut-outs' pinned ones): a shading
// reads two levels' pages of each of its maps (eight at most), and waiting paths keep the pages
// they read while they wait.
constexpr uint64_t kMinTexturePageSlots = 16;

// Where the path state lives (resolvePathStateMemory decides Auto), a Host wave's paths, and
// the cap of a Device wave out of core (planPool's maxOutOfCorePaths; for comparisons).
struct PathStateOptions {
    PathStateMemory memory = PathStateMemory::Auto;
    uint32_t hostPaths = kHostStatePaths;
    uint32_t deviceWaveCap = kMaxOutOfCoreBatchRays;
};

// device must outlive the backend. Every buffer is allocated here, once, but the environment
// map's and the volumes': reservedBytes of the budget are kept for them (environmentBytes plus
// volumeReserveBytes); the volumes are paged when they do not fit what the map leaves, and a
// render whose map and minimal volume pool need more is refused.
Result<std::unique_ptr<ChunkBackend>> createVulkanChunkBackend(VulkanDevice& device, const PackageInfo& package,
                                                               const ChunkAttributes& attributes, uint64_t budget,
                                                               double waveShareOutOfCore = kWaveShareOutOfCore,
                                                               const ChunkUploadOptions& upload = {},
                                                               uint64_t reservedBytes = 0,
                                                               const PathStateOptions& pathState = {});

}  // namespace vastray::gpu
