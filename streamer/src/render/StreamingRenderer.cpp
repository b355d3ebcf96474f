// A package opened for rendering on a backend that runs the whole path tracer on its device
// (ChunkBackend::renderOnDevice): this file opens the backend, the host chunk cache and the
// pager, hands renders to the device, and reports each render's figures.

#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <thread>

#include "render/ChunkCache.h"
#include "render/DemandPager.h"
#include "render/PrefetchOrder.h"
#include "vastray/core/Camera.h"
#include "vastray/core/PathShading.h"
#include "vastray/core/RenderMemory.h"
#include "vastray/core/Volume.h"
#include "vastray/streamer/StreamingRenderer.h"

namespace vastray {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// Out of core, queues the chunks for decoding in the background, as many as the host cache
// holds (with what it holds already), in the order the streamed tiles first see them
// (prefetchOrder: the rows of the image, top first): the first waves' rays wait for the chunks
// the top of the image shows, and each later load then finds its chunk decoded (PERF_NOTES 43, 104).
// Chunks queued as the scene opened (decodeOnOpen, in id order) and not yet decoded take this order.
void prefetchForRender(const PackageInfo& info, ChunkCache& cache, const Camera& camera, const PixelBounds& bounds,
                       uint32_t frameWidth, uint32_t frameHeight) {
    std::vector<uint32_t> order = prefetchOrder(info, camera, bounds, frameWidth, frameHeight);
    uint64_t bytes = 0;
    size_t fits = 0;
    while (fits < order.size() && (bytes += info.chunks[order[fits]].residentBytes) <= cache.capacity()) ++fits;
    order.resize(fits);
    cache.prefetchBackground(order);
}

}  // namespace

struct StreamingScene::State {
    const PackageReader& reader;
    ChunkAttributes attributes;
    StreamingOptions options;
    std::unique_ptr<ChunkBackend> backend;
    std::unique_ptr<ChunkCache> cache;
    std::unique_ptr<DemandPager> pager;
    StreamingStats totals;  // what the pager and the backend count into; each render reports its difference
    bool rendered = false;  // a render has reported its statistics
    explicit State(const PackageReader& r) : reader(r) {}
};

ChunkAttributes requiredAttributes(const PackageInfo& info, const RenderOptions& options) {
    ChunkAttributes a;
    a.primitiveIds = (options.aovs & kAovPrimId) != 0;
    a.materialIds = info.materials.size() > 1;
    for (const Material& m : info.materials) a.singleSided |= !m.doubleSided;
    a.normals = info.hasNormals;
    a.colors = info.hasColors;
    // Read by the materials' maps (a package with UVs has textures: import keeps UVs only for
    // maps) and the uv AOV.
    a.uvs = info.hasUvs && (!info.textures.empty() || (options.aovs & kAovUv) != 0);
    // A blend's coins are keyed by the primitive id (core/PathShading.h alphaCoin).
    for (const Material& m : info.materials) a.primitiveIds |= isBlended(m, a.uvs ? info.textures.size() : 0);
    for (const Material& m : info.materials)
        a.tangents |= a.uvs && m.textures.slots[uint32_t(TextureSlot::Normal)].texture < info.textures.size();
    a.packedPositions = info.grid.packsPositions();
    return a;
}

StreamingScene::StreamingScene() = default;
StreamingScene::~StreamingScene() = default;

Result<std::unique_ptr<StreamingScene>> StreamingScene::open(const PackageReader& reader,
                                                             const ChunkAttributes& attributes,
                                                             const StreamingOptions& options,
                                                             const ChunkBackendFactory& factory) {
    if (options.maxPathsPerWave == 0) return Status::error("maxPathsPerWave must be at least 1");
    std::unique_ptr<StreamingScene> scene(new StreamingScene());
    scene->state_ = std::make_unique<State>(reader);
    State& s = *scene->state_;
    s.attributes = attributes;
    s.options = options;
    // One worker per core but one (the render thread's), except on two cores, where a cold
    // render mostly waits for decoding: two workers there (1M-4M city on the 2-core machine).
    const uint32_t cores = std::max(1u, std::thread::hardware_concurrency());
    const uint32_t workers = options.decodeThreads > 0 ? options.decodeThreads : cores <= 2 ? cores : cores - 1;
    uint64_t hostCache = options.hostCacheBytes;
    if (hostCache == StreamingOptions::kHostCacheAuto) {
        const uint64_t decoded = reader.info().decodedBytes();
        const uint64_t machine = physicalHostBytes();
        hostCache = std::min<uint64_t>(decoded, (machine > 0 ? machine : 4ull << 30) / 4);
    }
    s.cache = std::make_unique<ChunkCache>(reader, hostCache, workers);
    if (options.decodeOnOpen && reader.info().decodedBytes() <= s.cache->capacity())
        for (const ChunkInfo& c : reader.info().chunks) s.cache->prefetchBackground(c.id);
    auto backend = factory(reader.info(), attributes);
    if (!backend) return backend.status();
    s.backend = std::move(backend).value();
    s.pager = std::make_unique<DemandPager>(reader.info(), attributes, *s.backend, *s.cache, s.totals);
    // Chunks go into the backend's staging memory as they are decoded (and those decoded while
    // the backend was made), off the render thread (PERF_NOTES 105). The cache's workers stop
    // before the backend goes (State's members are destroyed in reverse order).
    if (s.backend->stagesChunks()) {
        ChunkBackend* backend = s.backend.get();
        const PackageInfo& info = reader.info();
        s.cache->setDecodedHook([backend, &info, attributes](const DecodedChunk& chunk) {
            // An error here is the load's to report (it prepares the same arrays): nothing is lost.
            (void)backend->stage(chunk, singleSidedFlags(info, attributes, chunk));
        });
    }
    return scene;
}

const ChunkAttributes& StreamingScene::attributes() const { return state_->attributes; }
ChunkBackend& StreamingScene::backend() { return *state_->backend; }
uint64_t StreamingScene::raysWalked() const { return state_->totals.walkedRays; }

Result<RenderImage> StreamingScene::render(const RenderOptions& options, RenderStats* stats,
                                           StreamingStats* streamingStats, const StreamingProgress& progress,
                                           const std::atomic<bool>* cancel) {
    VASTRAY_TRY(validateRenderOptions(options));
    State& st = *state_;
    const PackageInfo& info = st.reader.info();
    const ChunkAttributes needed = requiredAttributes(info, options);
    if ((needed.primitiveIds && !st.attributes.primitiveIds) || (needed.materialIds && !st.attributes.materialIds) ||
        (needed.singleSided && !st.attributes.singleSided) || (needed.normals && !st.attributes.normals) ||
        (needed.colors && !st.attributes.colors) || (needed.uvs && !st.attributes.uvs) ||
        (needed.tangents && !st.attributes.tangents))
        return Status::error("this render needs chunk attributes the scene was not opened with (primid or uv AOV?)");
    std::optional<tbb::global_control> threadLimit;
    if (options.threads > 0) threadLimit.emplace(tbb::global_control::max_allowed_parallelism, options.threads);

    // Automatic framing frames the mesh and its volumes.
    const Aabb framed = boundsWithVolumes(info.bounds, options.volumes.get());
    const Camera camera = options.frameScene ? frameBounds(framed, options.camera.fovYDegrees,
                                                           float(options.width) / float(options.height), options.camera.up)
                                             : options.camera;
    VASTRAY_TRY(validateCamera(camera).withContext("camera: "));

    // The streamer counts into st.totals across renders; this render reports the difference.
    // Until a render has reported, the cache's counters start at zero: the first report counts
    // the decoding done since the scene opened (decodeOnOpen), and that of a render that failed.
    StreamingStats before = st.totals;
    if (st.rendered) {
        before.bytesRead = st.cache->bytesRead(), before.decodes = st.cache->decodes();
        before.decodeSeconds = st.cache->decodeSeconds(), before.decodeWaitSeconds = st.cache->waitSeconds();
    }
    before.uploadSeconds = st.backend->uploadSeconds();
    before.deviceSeconds = st.backend->deviceSeconds(), before.bytesUploaded = st.backend->bytesUploaded();
    const PixelBounds bounds = renderBounds(options);
    RenderImage image;
    image.allocate(bounds.width(), bounds.height(), options.aovs);
    image.placeInFrame(bounds.x0, bounds.y0, options.width, options.height);
    recordCamera(image, camera, options.width, options.height);
    const Clock::time_point start = Clock::now();
    st.pager->beginRender();
    if (st.options.prefetchScene && st.backend->slotCount() < info.chunks.size())
        prefetchForRender(info, *st.cache, camera, bounds, options.width, options.height);
    DeviceRenderJob job;
    job.options = &options;
    job.camera = camera;
    job.materials = info.materials;
    job.textures = info.textures;
    const PackageReader& reader = st.reader;
    job.readTexturePage = [&reader](uint32_t texture, uint32_t page, uint8_t* out) {
        return reader.readTexturePage(texture, page, out);
    };
    const Material fallback{"default"};
    if (job.materials.empty()) job.materials = std::span<const Material>(&fallback, 1);
    job.maxPathsPerWave = st.options.maxPathsPerWave;
    job.overlapLoads = st.options.overlapLoads;
    job.partialResidency = st.options.partialResidency;
    job.streamWaves = st.options.streamWaves;
    job.windowTiles = st.options.windowTiles;
    job.restartInShade = st.options.restartInShade;
    job.progress = progress;
    job.cancel = cancel;
    VASTRAY_TRY(st.backend->renderOnDevice(job, *st.pager, image, st.totals));
    const uint64_t rays = st.totals.walkedRays - before.walkedRays;
    reportStats(st, before, stats, streamingStats, start, rays);
    st.rendered = true;
    return image;
}

void StreamingScene::reportStats(State& st, const StreamingStats& before, RenderStats* stats,
                                 StreamingStats* streamingStats, std::chrono::steady_clock::time_point start,
                                 uint64_t rays) {
    const PackageInfo& info = st.reader.info();
    if (streamingStats) {
        StreamingStats& s = *streamingStats;
        const StreamingStats& t = st.totals;
        const uint64_t budget = s.memoryBudgetBytes;
        s = StreamingStats{};
        s.memoryBudgetBytes = budget;
        s.chunksTotal = info.chunks.size();
        s.slots = st.backend->slotCount();
        s.wavePaths = t.wavePaths, s.pathStateHostBytes = t.pathStateHostBytes;
        s.chunksTouched = st.pager->chunksTouchedThisRender();
        s.chunkLoads = t.chunkLoads - before.chunkLoads;
        s.streamChunksTouched = t.streamChunksTouched - before.streamChunksTouched;
        s.streamReloads = t.streamReloads - before.streamReloads;
        s.walkedRays = t.walkedRays - before.walkedRays;
        s.submits = t.submits - before.submits;
        s.idleLoadSteps = t.idleLoadSteps - before.idleLoadSteps;
        s.lateChunks = t.lateChunks - before.lateChunks;
        s.hostGapSeconds = t.hostGapSeconds - before.hostGapSeconds;
        s.deviceIdleSeconds = t.deviceIdleSeconds - before.deviceIdleSeconds;
        s.walkPasses = t.walkPasses - before.walkPasses;
        s.pipelineSeconds = t.pipelineSeconds - before.pipelineSeconds;
        s.streamedTiles = t.streamedTiles - before.streamedTiles;
        s.streamWindowTiles = t.streamWindowTiles;
        s.volumeBrickSlots = t.volumeBrickSlots;
        s.volumeBrickLoads = t.volumeBrickLoads - before.volumeBrickLoads;
        s.volumeBricksRead = t.volumeBricksRead - before.volumeBricksRead;
        s.texturePageSlots = t.texturePageSlots;
        s.texturePageLoads = t.texturePageLoads - before.texturePageLoads;
        s.texturePagesRead = t.texturePagesRead - before.texturePagesRead;
        s.hostToDeviceBytes = t.hostToDeviceBytes - before.hostToDeviceBytes;
        s.deviceToHostBytes = t.deviceToHostBytes - before.deviceToHostBytes;
        for (int k = 0; k < StreamingStats::kKernels; ++k) s.kernelSeconds[k] = t.kernelSeconds[k] - before.kernelSeconds[k];
        s.bytesRead = st.cache->bytesRead() - before.bytesRead;
        s.decodes = st.cache->decodes() - before.decodes;
        s.decodeSeconds = st.cache->decodeSeconds() - before.decodeSeconds;
        s.decodeWaitSeconds = st.cache->waitSeconds() - before.decodeWaitSeconds;
        s.bytesUploaded = st.backend->bytesUploaded() - before.bytesUploaded;
        s.uploadSeconds = st.backend->uploadSeconds() - before.uploadSeconds;
        s.deviceSeconds = st.backend->deviceSeconds() - before.deviceSeconds;
        s.peakDeviceBytes = st.backend->peakDeviceBytes();
    }
    if (stats) {
        stats->backend = st.backend->name();
        stats->renderSeconds = secondsSince(start);
        stats->buildSeconds = 0;
        stats->rays = rays;
        stats->triangles = info.triangleCount;
        stats->peakHostBytes = peakHostBytes();
    }
}

Result<RenderImage> renderStreaming(const PackageReader& reader, const RenderOptions& options,
                                    const StreamingOptions& streaming, const ChunkBackendFactory& factory,
                                    RenderStats* stats, StreamingStats* streamingStats,
                                    const StreamingProgress& progress) {
    VASTRAY_TRY(validateRenderOptions(options));
    auto scene = StreamingScene::open(reader, requiredAttributes(reader.info(), options), streaming, factory);
    if (!scene) return scene.status();
    return (*scene)->render(options, stats, streamingStats, progress);
}

}  // namespace vastray
