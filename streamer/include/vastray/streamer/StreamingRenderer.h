#pragma once
// The streaming renderer: a wavefront path tracer over a scene package whose chunks are paged
// through a fixed number of device slots. The backend (the Vulkan one, gpu/) runs the whole
// wavefront on its device; this module keeps what the host does: the host chunk cache and its
// decode workers, and the pager that turns the device's per-chunk demand counters into loads
// and evictions (ChunkPager). docs/RENDERING.md describes the algorithm.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "vastray/core/Camera.h"
#include "vastray/core/Mesh.h"
#include "vastray/core/RenderImage.h"
#include "vastray/core/RenderOptions.h"
#include "vastray/core/RenderStats.h"
#include "vastray/core/Result.h"
#include "vastray/core/Vec3.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {

// Which per-triangle attributes a render reads; the others are never uploaded.
struct ChunkAttributes {
    bool primitiveIds = false;  // the primid AOV
    bool materialIds = false;   // the scene has more than one material
    bool singleSided = false;   // some material is single-sided
    bool normals = false;       // the package has per-vertex shading normals
    bool colors = false;        // the package has per-vertex colours
    bool uvs = false;           // the package has texture coordinates and the render reads them (maps, uv AOV)
    bool tangents = false;      // with uvs: some material has a normal map (hits keep their UV derivatives)
    // Not an attribute but how positions lie: 8 bytes a vertex, the package grid's coordinates
    // (QuantizationGrid::packedPosition), where its grid allows it (packsPositions); else 3 floats.
    bool packedPositions = false;
};

// Where each array of a chunk lies in a device slot: byte offsets of 16-byte aligned sections
// (an absent attribute has size 0). Slots are sized from the directory before any chunk is read.
struct ChunkLayout {
    uint64_t nodes = 0, positions = 0, indices = 0;
    uint64_t singleSided = 0;   // one byte per triangle, four to a word
    uint64_t primitiveIds = 0;  // uint32 per triangle
    uint64_t materialIds = 0;   // uint32 per triangle
    uint64_t normals = 0;       // uint32 per vertex (octahedral)
    uint64_t colors = 0;        // uint32 per vertex (sRGB8)
    uint64_t uvs = 0;           // 2 x f32 per vertex
    uint64_t totalBytes = 0;
};
// indexDeltas16: the indices as kChunkIndexDeltas16 says, 8 bytes a triangle and 12 more for each
// of its longTriangles (else 12 a triangle).
ChunkLayout chunkLayout(uint64_t bvhNodes, uint64_t vertices, uint64_t triangles, bool indexDeltas16,
                        uint64_t longTriangles, const ChunkAttributes& attributes);
inline ChunkLayout chunkLayout(const ChunkInfo& c, const ChunkAttributes& attributes) {
    return chunkLayout(c.bvhNodeCount, c.vertexCount, c.triangleCount, (c.flags & kChunkIndexDeltas16) != 0,
                       c.longTriangles, attributes);
}

struct StreamingStats;

// Residency of chunks in a backend's slots, driven by demand (the pager). A device wavefront
// asks it, between paging steps, to page in the chunks its parked rays wait for; it decides
// what to load and evict, and loads through ChunkBackend::load. Backends never decide what to load.
class ChunkPager {
public:
    virtual ~ChunkPager() = default;
    // A new ray stream (a wave's rays, all bounces) starts: a chunk loaded again before the next
    // beginStream counts as a reload.
    virtual void beginStream() = 0;
    // demand[c] rays wait for chunk c (chunks that are resident have none); ahead[c] (empty, or
    // one entry per chunk) of them reach chunk c later on. Loads the most wanted chunks (as many
    // as there are slots), evicting chunks nobody waits for, those no ray reaches later and the
    // least recently used first; fills slots still empty with the chunks most rays reach later.
    // Returns the chunks it loaded.
    Result<std::vector<uint32_t>> page(std::span<const uint32_t> demand, std::span<const uint32_t> ahead = {}) {
        planLoads(demand, ahead);
        return loadPlanned();
    }
    // page in two halves, for a caller that loads while the device works: planLoads picks the
    // chunks and their slots and evicts what those slots held (chunkSlots() shows them empty
    // from then on, so a submission made now does not read them); loadPlanned loads them and
    // makes them resident (call it while no running submission reads those slots; chunkSlots()
    // shows them afterwards). Returns the chunks planned, then the chunks loaded.
    virtual std::vector<uint32_t> planLoads(std::span<const uint32_t> demand,
                                            std::span<const uint32_t> ahead = {}) = 0;
    virtual Result<std::vector<uint32_t>> loadPlanned() = 0;
    // Per chunk, set by the device: nonzero when a ray traced one of its cells in the last
    // paging step (recency for eviction).
    virtual void markUsed(std::span<const uint32_t> touched) = 0;
    // The same for the whole stream: recency, and the stream's chunks-touched figure.
    virtual void streamTouched(std::span<const uint32_t> touched) = 0;
    virtual std::span<const uint32_t> chunkSlots() const = 0;  // per chunk: its slot or kEmptyCell
    virtual bool allResident() const = 0;                      // every chunk has a slot
};

// What a device-side render needs besides the package: the options, the camera it resolved
// (framing applied), the materials, and the caller's progress and cancel hooks.
struct DeviceRenderJob {
    const RenderOptions* options = nullptr;
    Camera camera;
    std::span<const Material> materials;  // at least one
    // The package's textures (the materials' maps name them) and how a page of one is read
    // (PackageReader::readTexturePage; called from worker threads).
    std::span<const PackageTexture> textures;
    std::function<Status(uint32_t texture, uint32_t page, uint8_t* out)> readTexturePage;
    uint32_t maxPathsPerWave = 0;         // StreamingOptions::maxPathsPerWave (the budget may allow fewer)
    bool overlapLoads = true;             // StreamingOptions::overlapLoads
    bool partialResidency = true;         // StreamingOptions::partialResidency
    bool streamWaves = true;              // StreamingOptions::streamWaves
    uint32_t windowTiles = 0;             // StreamingOptions::windowTiles
    bool restartInShade = true;           // StreamingOptions::restartInShade
    std::function<void(uint64_t done, uint64_t total)> progress;  // optional
    const std::atomic<bool>* cancel = nullptr;                   // optional: set stops the render
};

// The narrow interface of a streaming backend: a fixed number of slots, each holding one chunk.
class ChunkBackend {
public:
    virtual ~ChunkBackend() = default;
    virtual std::string name() const = 0;
    virtual uint32_t slotCount() const = 0;
    // Makes `chunk` resident in `slot`, replacing what was there. singleSided: one byte per
    // triangle (nonzero: invisible from behind) when attributes.singleSided, else empty.
    virtual Status load(uint32_t slot, const DecodedChunk& chunk, std::span<const uint8_t> singleSided) = 0;
    // Called by the threads that decode chunks, as each chunk is decoded, any number at once and
    // beside the render thread's calls: may prepare a later load() of the chunk (the Vulkan
    // backend with DMA writes it into staging memory; PERF_NOTES 105). Doing nothing is correct.
    virtual Status stage(const DecodedChunk& /*chunk*/, std::span<const uint8_t> /*singleSided*/) {
        return Status::ok();
    }
    virtual bool stagesChunks() const { return false; }  // stage() does something: worth calling

    // The whole render on the device (camera rays, the walk, traversal, shading, accumulation):
    // fills image (allocated by the caller) and the device figures of stats (submits, bytes each
    // way, walk passes, kernel times). Chunks come in through pager only.
    virtual Status renderOnDevice(const DeviceRenderJob& job, ChunkPager& pager, RenderImage& image,
                                  StreamingStats& stats) = 0;

    virtual uint64_t bytesUploaded() const = 0;
    virtual uint64_t peakDeviceBytes() const = 0;
    virtual double uploadSeconds() const = 0;
    // Time spent waiting for the device's submissions.
    virtual double deviceSeconds() const = 0;
};

// Creates the backend once the renderer knows what it needs: the package and the attributes.
using ChunkBackendFactory =
    std::function<Result<std::unique_ptr<ChunkBackend>>(const PackageInfo& package, const ChunkAttributes& attributes)>;

struct StreamingOptions {
    // Decoded chunks kept on the host; 0: none kept; kHostCacheAuto: the whole decoded scene,
    // up to a quarter of the machine's memory (a chunk paged out and in again then decodes once).
    static constexpr uint64_t kHostCacheAuto = ~0ull;
    uint64_t hostCacheBytes = kHostCacheAuto;
    uint32_t maxPathsPerWave = 1u << 21;   // (pixel, sample) paths traced together per wave
    // Out of core, chunks are loaded while the device walks the next paging step (they serve the
    // step after it); false: between steps, the device idle meanwhile (for comparisons).
    bool overlapLoads = true;
    // Out of core with chunks copied by the transfer queue (gpu::ChunkUploadMode::Dma), a paging
    // step does not wait for copies still running when it is submitted: their chunks count as
    // absent for that step (the rays waiting for them wait one step more) while the kernels walk
    // what has arrived, unless nothing else has work; false: every step waits for every copy
    // made before it (for comparisons). Images are the same either way.
    bool partialResidency = true;
    // Out of core, waves are streamed: a group of a pixel's samples that is done starts the next
    // pixel at once, so the wave stays full while a tile's last paths wait for chunks (false: a
    // tile's wave at a time, for comparisons; docs/RENDERING.md, "Streamed waves").
    bool streamWaves = true;
    // Streamed waves: the most tiles open at once (0: as many as the output buffer holds, at
    // most 32: gpu::PoolPlan::outputPixels); for comparisons.
    uint32_t windowTiles = 0;
    // Streamed waves: the shading kernel that ends a group's block adds it to its pixel and starts
    // the group's next block in the same dispatch (false: a generate kernel after each shading
    // does, as before; for comparisons). Images are the same either way.
    bool restartInShade = true;
    // Out of core, every chunk the host cache can hold is queued for decoding when a render
    // starts, in the order the image's rows (top first) first show them (render/PrefetchOrder.h),
    // behind the chunks rays wait for: a later load then finds its chunk decoded instead of
    // waiting for it (false: decode on demand only).
    bool prefetchScene = true;
    // When the host cache holds the whole decoded scene, every chunk is queued for decoding as
    // the scene opens, before the backend factory runs: a factory that waits for a device being
    // created meanwhile (the CLI's) overlaps its start-up with decoding. The first render's
    // statistics count these decodes. False (the default): decoding starts with a render.
    bool decodeOnOpen = false;
    uint32_t decodeThreads = 0;            // chunk decode workers; 0: one per core but one (two on two cores)
};

// The streaming figures of one render (--stats-json names in comments).
struct StreamingStats {
    uint64_t chunksTotal = 0;       // chunks_total
    uint64_t chunksTouched = 0;     // chunks_touched: distinct chunks this render traced rays against
    uint64_t chunkLoads = 0;        // chunk_loads: uploads into a slot
    // Per ray stream (a tile's wave, all bounces; for streamed waves, the paging steps between
    // two closed tiles), summed over streams: distinct chunks the stream traced
    // (stream_chunks_touched), and loads of a chunk the same stream had already had resident
    // (stream_reloads). (touched + reloads) / touched is the loads per chunk a stream touches:
    // 1.0 when no chunk is paged in twice within a stream.
    uint64_t streamChunksTouched = 0;
    uint64_t streamReloads = 0;
    uint64_t bytesRead = 0;         // bytes_read: chunk blobs read from the package
    uint64_t bytesUploaded = 0;     // bytes_uploaded
    uint64_t decodes = 0;           // chunks decoded (a host-cache hit decodes nothing)
    double decodeSeconds = 0;       // decode_seconds: read + decode time summed over workers
    double decodeWaitSeconds = 0;   // decode_wait_seconds: the render thread waiting for decodes to load
    double uploadSeconds = 0;       // upload_seconds
    double deviceSeconds = 0;       // device_seconds: waiting for the device's submissions
    uint64_t peakDeviceBytes = 0;   // peak_device_bytes
    uint64_t memoryBudgetBytes = 0; // memory_budget_bytes (set by the caller that knows it)
    uint32_t slots = 0;             // chunk slots the budget holds
    // The device wavefront's wave: its paths (wave_paths), and the bytes of their state when it
    // lies in host memory (path_state_host_bytes; 0: in device memory, gpu::PathStateMemory).
    uint32_t wavePaths = 0;
    uint64_t pathStateHostBytes = 0;
    uint64_t walkedRays = 0;        // walked_rays: rays walked on the device (camera, AOV, bounce and shadow)
    // The device wavefront's (ChunkBackend::renderOnDevice): command-buffer submissions, walk
    // passes (one per scattering event in core; three per paging step out of core), and the
    // bytes that crossed the bus besides chunk data (bytes_uploaded): parameters and chunk
    // tables up; demand and look-ahead counters, queue sizes, touched flags and the image with
    // its AOVs down.
    uint64_t submits = 0;           // submits
    // idle_load_steps: paging steps (out of core) whose planned chunks were loaded before the
    // step ran, the device idle: no waiting ray could go on without them (or overlapLoads off);
    // the other steps load while the device walks.
    uint64_t idleLoadSteps = 0;
    // late_chunks: out of core with partial residency (StreamingOptions::partialResidency),
    // chunks a paging step saw absent because their copies still ran when it was submitted,
    // summed over steps (a chunk late for two steps counts twice).
    uint64_t lateChunks = 0;
    // host_gap_seconds: out of core, the time from a paging step's end (its wait returned) to the
    // next submission: the host reading counters, closing tiles, planning and recording, the
    // compute queue idle meanwhile (the transfer queue may still copy).
    double hostGapSeconds = 0;
    // device_idle_seconds: between two submissions of the render, the device's time from the one's
    // last command to the next one's first, read from their timestamps: the host gap, the
    // latencies of waking the host and of starting a submission, and a submission's wait for chunk
    // copies (0 without timestamp queries).
    double deviceIdleSeconds = 0;
    uint64_t walkPasses = 0;        // walk_passes
    // pipeline_seconds: creating the compute pipelines this render needs that the scene had not
    // created before (its shade and walk variants; a driver compilation, which the driver's own
    // disk cache makes cheaper in later processes)
    double pipelineSeconds = 0;
    uint64_t streamedTiles = 0;     // streamed_tiles: tiles rendered by streamed waves (out of core)
    uint64_t streamWindowTiles = 0; // stream_window_tiles: the most tiles streamed waves held open at once (0: not streamed)
    uint64_t volumeBrickSlots = 0;  // volume_brick_slots: the pool's brick slots (0: volumes in core or none)
    uint64_t volumeBrickLoads = 0;  // volume_brick_loads: bricks loaded into those slots
    // volume_bricks_read: bricks read from the package and checked (2 KiB each, 4 KiB with an
    // emission grid; version 6 packages, in core or paged; a paged brick the host cache lost is
    // read again). Older packages read their volumes whole when they open: 0.
    uint64_t volumeBricksRead = 0;
    uint64_t texturePageSlots = 0;  // texture_page_slots: the pool's page slots (0: textures in core or none)
    uint64_t texturePageLoads = 0;  // texture_page_loads: pages loaded into those slots
    // texture_pages_read: pages read from the package and inflated (in core every page once;
    // paged, those the host cache of inflated pages did not hold)
    uint64_t texturePagesRead = 0;
    uint64_t hostToDeviceBytes = 0; // host_to_device_bytes
    uint64_t deviceToHostBytes = 0; // device_to_host_bytes
    // Device time per kernel of the device wavefront, from timestamp queries (kernel_seconds,
    // named by kKernelNames); zero where the device has no timestamps.
    static constexpr int kKernels = 5;
    static constexpr int kKernelGenerate = 0, kKernelWalk = 1, kKernelShade = 2, kKernelAccumulate = 3, kKernelAov = 4;
    static constexpr const char* kKernelNames[kKernels] = {"generate", "walk", "shade", "accumulate", "aov"};
    double kernelSeconds[kKernels] = {};
};

// Called from the render thread with (units done, units total).
using StreamingProgress = std::function<void(uint64_t done, uint64_t total)>;

// The attributes a render with these options reads.
ChunkAttributes requiredAttributes(const PackageInfo& package, const RenderOptions& options);

// A package opened for rendering: its backend (device slots), host chunk cache, decode workers
// and residency live as long as this object, so that renders after the first reuse the chunks
// already resident or decoded (a second render of a scene that fits loads nothing).
// reader must outlive it; renders run one at a time.
class StreamingScene {
public:
    static Result<std::unique_ptr<StreamingScene>> open(const PackageReader& reader, const ChunkAttributes& attributes,
                                                        const StreamingOptions& options,
                                                        const ChunkBackendFactory& backend);
    ~StreamingScene();
    StreamingScene(const StreamingScene&) = delete;
    StreamingScene& operator=(const StreamingScene&) = delete;

    // An error when the options need attributes the scene was not opened with. The streaming
    // figures are this render's alone (loads, bytes, seconds); memoryBudgetBytes is kept.
    // cancel, when given and set, stops the render between ray streams with an error
    // "render cancelled" (the scene stays usable).
    Result<RenderImage> render(const RenderOptions& options, RenderStats* stats = nullptr,
                               StreamingStats* streamingStats = nullptr, const StreamingProgress& progress = {},
                               const std::atomic<bool>* cancel = nullptr);

    const ChunkAttributes& attributes() const;
    ChunkBackend& backend();
    // Rays walked on the device by this scene's renders so far, the running one included up to
    // its last finished tile (for progress reports: read it from the progress callback).
    uint64_t raysWalked() const;

private:
    StreamingScene();
    struct State;
    static void reportStats(State& st, const StreamingStats& before, RenderStats* stats,
                            StreamingStats* streamingStats, std::chrono::steady_clock::time_point start,
                            uint64_t rays);
    std::unique_ptr<State> state_;
};

// Opens the package and renders once; the image equals, bit for bit, the one any other
// backend or budget gives for the same hits. RenderImage gets the chunkid and cost AOVs when
// options.aovs asks for them.
Result<RenderImage> renderStreaming(const PackageReader& package, const RenderOptions& options,
                                    const StreamingOptions& streaming, const ChunkBackendFactory& backend,
                                    RenderStats* stats = nullptr, StreamingStats* streamingStats = nullptr,
                                    const StreamingProgress& progress = {});

}  // namespace vastray
