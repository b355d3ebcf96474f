// The wavefront integrator of the streaming renderer. Per wave of (pixel, sample) paths and
// per bounce: one closest-hit stream, host shading, one shadow stream. The shading steps are
// core/PathShading.h's, in the order cpu/src/Integrators.cpp applies them, so a path's floats
// equal the reference's whenever the hits agree.
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <optional>
#include <thread>

#include "render/ChunkCache.h"
#include "render/DemandPager.h"
#include "render/RayStreamer.h"
#include "vastray/core/Camera.h"
#include "vastray/core/PathShading.h"
#include "vastray/core/RayOffset.h"
#include "vastray/core/VecMath.h"
#include "vastray/streamer/StreamingRenderer.h"

namespace vastray {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

template <typename F>
void parallelFor(size_t n, F&& f) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t i = r.begin(); i != r.end(); ++i) f(i);
    });
}

struct PathState {
    Vec3f throughput{1, 1, 1};
    Vec3f radiance;
    Vec3f pendingSun;  // the sun's contribution, added if the shadow ray reaches the sun
    Ray ray;     // the ray to trace at the next bounce
    Ray shadow;  // towards the sun (path) or the sampled direction (ao), when shadowPending
    float shadowRange = 0;
    uint32_t pixel = 0, sample = 0;
    bool alive = true;
    bool cameraRayHit = false;
    bool shadowPending = false;
};

// The integrator's per-path and per-ray arrays (hundreds of MB at 2 M paths). They live as long
// as the StreamingScene, so a render after the first reuses memory the process has already
// touched instead of faulting in fresh pages.
struct IntegratorBuffers {
    std::vector<PathState> paths;
    std::vector<uint32_t> active, shadowOwners;
    std::vector<StreamRay> rays;
    std::vector<uint8_t> anyHit;
    std::vector<StreamResult> results;
    std::vector<double> sum;
    std::vector<uint32_t> hits;
};

class Integrator {
public:
    Integrator(const PackageInfo& info, const RenderOptions& options, const CameraRays& camera, RayStreamer& streamer,
               StreamingStats& stats, RenderImage& image, const std::atomic<bool>* cancel, IntegratorBuffers& buffers)
        : options_(options), camera_(camera), streamer_(streamer), stats_(stats), image_(image),
          cancel_(cancel), paths_(buffers.paths), active_(buffers.active), shadowOwners_(buffers.shadowOwners),
          rays_buffer_(buffers.rays), anyHit_(buffers.anyHit), results_(buffers.results), sum_(buffers.sum),
          hits_(buffers.hits) {
        materials_ = info.materials;
        if (materials_.empty()) materials_.push_back(Material{"default"});
        sunDirection_ = normalize(options.environment.sunDirection);
        if (image.aovs & kAovCost) cells_.assign(image.pixelCount(), 0), triangles_.assign(image.pixelCount(), 0);
    }

    uint64_t rays() const { return rays_; }

    // The AOVs come from one unjittered ray through each pixel centre, as in the reference.
    Status renderAovs(uint64_t first, uint64_t count) {
        rays_buffer_.resize(count);
        for (uint64_t i = 0; i < count; ++i) {
            const uint64_t pixel = first + i;
            const Ray ray = camera_.primary(uint32_t(pixel % image_.width), uint32_t(pixel / image_.width), 0.5f, 0.5f);
            rays_buffer_[i] = StreamRay{ray.origin, 0.0f, ray.direction, kInfinity};
        }
        anyHit_.clear();
        VASTRAY_TRY(trace());
        const Clock::time_point start = Clock::now();
        parallelFor(count, [&](size_t i) {
            const uint64_t pixel = first + i;
            const StreamResult& r = results_[i];
            if (!(r.hit.flags & kStreamHitFound)) return;
            const Material& material = materialAt(materials_, r.hit.material);
            const SurfacePoint point = makeSurfacePoint(r.hit.position, r.hit.normal, rays_buffer_[i].direction, material);
            if (image_.aovs & kAovDepth) image_.depth[pixel] = r.hit.t;
            if (image_.aovs & kAovNormal)
                for (int c = 0; c < 3; ++c) image_.normal[3 * pixel + c] = point.normal[c];
            if (image_.aovs & kAovAlbedo)
                for (int c = 0; c < 3; ++c) image_.albedo[3 * pixel + c] = material.baseColor[c];
            if (image_.aovs & kAovPrimId) image_.primId[pixel] = r.hit.primitive;
            if (image_.aovs & kAovChunkId) image_.chunkId[pixel] = r.chunk;
        });
        countCost([&](size_t i) { return first + i; });
        stats_.shadeSeconds += secondsSince(start);
        return Status::ok();
    }

    // Paths [first, first + count) in path order (index = sample * pixels + pixel); each path's
    // radiance is added to its pixel in that order, as the reference sums samples.
    template <typename Progress>
    Status renderPaths(uint64_t first, uint64_t count, Progress&& bounceDone) {
        const uint64_t pixels = image_.pixelCount();
        paths_.resize(count);  // reset in parallel below (one serial pass over ~250 MB cost ~30 ms)
        parallelFor(count, [&](size_t i) {
            PathState& p = paths_[i];
            p = PathState{};
            p.pixel = uint32_t((first + i) % pixels), p.sample = uint32_t((first + i) / pixels);
            const RandomKey key{p.pixel, p.sample, 0};
            p.ray = camera_.primary(p.pixel % image_.width, p.pixel / image_.width,
                                    randomFloat(key, kDimPixelX, options_.seed),
                                    randomFloat(key, kDimPixelY, options_.seed));
        });
        const bool ao = options_.integrator == IntegratorKind::AmbientOcclusion;
        // One ray stream per bounce: the closest-hit rays of bounce k together with the shadow
        // rays of bounce k - 1 (a path's next direction does not depend on its shadow ray), so
        // out of core each bounce pages the scene through once, not twice. Shadow results are
        // applied before bounce k is shaded: the reference's order of additions.
        shadowOwners_.clear();
        for (uint32_t bounce = 0;; ++bounce) {
            active_.clear();
            for (uint32_t i = 0; i < count; ++i)
                if (paths_[i].alive) active_.push_back(i);
            if (active_.empty() && shadowOwners_.empty()) break;
            const size_t closest = active_.size();
            rays_buffer_.resize(closest + shadowOwners_.size());
            anyHit_.assign(rays_buffer_.size(), 0);
            parallelFor(rays_buffer_.size(), [&](size_t k) {
                if (k < closest) {
                    const Ray& r = paths_[active_[k]].ray;
                    rays_buffer_[k] = StreamRay{r.origin, 0.0f, r.direction, kInfinity};
                } else {
                    const PathState& p = paths_[shadowOwners_[k - closest]];
                    rays_buffer_[k] = StreamRay{p.shadow.origin, 0.0f, p.shadow.direction, p.shadowRange};
                    anyHit_[k] = 1;
                }
            });
            VASTRAY_TRY(trace());
            countCost([&](size_t k) {
                return k < closest ? paths_[active_[k]].pixel : paths_[shadowOwners_[k - closest]].pixel;
            });
            const Clock::time_point start = Clock::now();
            parallelFor(shadowOwners_.size(), [&](size_t k) {
                PathState& p = paths_[shadowOwners_[k]];
                const bool blocked = results_[closest + k].hit.flags & kStreamHitFound;
                if (ao)
                    p.radiance = blocked ? Vec3f{0, 0, 0} : Vec3f{1, 1, 1};
                else if (!blocked)  // the reference adds a zero vector when blocked: no change
                    p.radiance = p.radiance + p.pendingSun;
                p.shadowPending = false;
            });
            parallelFor(closest, [&](size_t k) {
                ao ? shadeAmbientOcclusion(paths_[active_[k]], results_[k])
                   : shadePath(paths_[active_[k]], results_[k], bounce);
            });
            shadowOwners_.clear();
            for (uint32_t i : active_)
                if (paths_[i].shadowPending) shadowOwners_.push_back(i);
            stats_.shadeSeconds += secondsSince(start);
            bounceDone();
        }
        // Per pixel, its samples in sample order (paths j, j + pixels, ... of this wave), as the
        // reference sums them; pixels in parallel.
        parallelFor(std::min<uint64_t>(count, pixels), [&](size_t j) {
            for (uint64_t i = j; i < count; i += pixels) {
                const PathState& p = paths_[i];
                for (int c = 0; c < 3; ++c) sum_[3 * p.pixel + c] += p.radiance[c];
                hits_[p.pixel] += p.cameraRayHit;
            }
        });
        return Status::ok();
    }

    void begin() {
        sum_.assign(3 * image_.pixelCount(), 0.0);
        hits_.assign(image_.pixelCount(), 0);
    }

    void finish() {
        const double spp = options_.samplesPerPixel;
        parallelFor(image_.pixelCount(), [&](size_t p) {
            for (int c = 0; c < 3; ++c) image_.rgb[3 * p + c] = float(sum_[3 * p + c] / spp);
            image_.alpha[p] = float(double(hits_[p]) / spp);
        });
        if (image_.aovs & kAovCost)
            for (uint64_t p = 0; p < image_.pixelCount(); ++p)
                image_.cost[2 * p] = float(cells_[p]), image_.cost[2 * p + 1] = float(triangles_[p]);
    }

private:
    // Traces rays_buffer_ (anyHit_: per ray, or empty for all closest) into results_.
    Status trace() {
        if (cancel_ && cancel_->load()) return Status::error("render cancelled");
        rays_ += rays_buffer_.size();
        return streamer_.trace(rays_buffer_, anyHit_, results_);
    }

    template <typename PixelOf>
    void countCost(PixelOf&& pixelOf) {
        if (!(image_.aovs & kAovCost)) return;
        for (size_t k = 0; k < results_.size(); ++k) {
            cells_[pixelOf(k)] += results_[k].cellsTraced;
            triangles_[pixelOf(k)] += results_[k].trianglesTested;
        }
    }

    // One step of tracePath (cpu/src/Integrators.cpp) after its closest hit.
    void shadePath(PathState& p, const StreamResult& r, uint32_t bounce) {
        p.alive = false, p.shadowPending = false;
        if (!(r.hit.flags & kStreamHitFound)) {
            p.radiance = p.radiance + mul(p.throughput, skyRadiance(options_.environment, p.ray.direction));
            return;
        }
        if (bounce == 0) p.cameraRayHit = true;
        const RandomKey key{p.pixel, p.sample, bounce};
        const SurfacePoint point =
            makeSurfacePoint(r.hit.position, r.hit.normal, p.ray.direction, materialAt(materials_, r.hit.material));
        p.radiance = p.radiance + mul(p.throughput, emission(*point.material));
        if (bounce == options_.maxDepth) return;
        const Vec3f origin = offsetRayOrigin(point.position, point.normal);
        Vec3f light;
        if (unshadowedSunLight(options_.environment, sunDirection_, point, &light)) {
            p.shadowPending = true;
            p.pendingSun = mul(p.throughput, light);
            p.shadow = {origin, sunDirection_};
            p.shadowRange = kInfinity;
        }
        Vec3f throughput = mul(p.throughput, baseColor(*point.material));
        if (!surviveRoulette(throughput, bounce, key, options_.seed)) return;
        p.throughput = throughput;
        p.alive = true;
        p.ray = {origin, cosineDirection(point.normal, key, options_.seed)};
    }

    void shadeAmbientOcclusion(PathState& p, const StreamResult& r) {
        p.alive = false, p.shadowPending = false;
        if (!(r.hit.flags & kStreamHitFound)) {
            p.radiance = {1, 1, 1};
            return;
        }
        p.cameraRayHit = true;
        const RandomKey key{p.pixel, p.sample, 0};
        const SurfacePoint point =
            makeSurfacePoint(r.hit.position, r.hit.normal, p.ray.direction, materialAt(materials_, r.hit.material));
        p.shadowPending = true;
        p.shadow = {offsetRayOrigin(point.position, point.normal), cosineDirection(point.normal, key, options_.seed)};
        p.shadowRange = options_.aoDistance > 0.0f ? options_.aoDistance : kInfinity;
    }

    const RenderOptions& options_;
    const CameraRays& camera_;
    RayStreamer& streamer_;
    StreamingStats& stats_;
    RenderImage& image_;
    const std::atomic<bool>* cancel_;
    std::vector<Material> materials_;
    Vec3f sunDirection_;
    uint64_t rays_ = 0;
    std::vector<PathState>& paths_;
    std::vector<uint32_t>& active_;
    std::vector<uint32_t>& shadowOwners_;
    std::vector<StreamRay>& rays_buffer_;
    std::vector<uint8_t>& anyHit_;
    std::vector<StreamResult>& results_;
    std::vector<double>& sum_;
    std::vector<uint32_t>& hits_;
    std::vector<uint64_t> cells_, triangles_;
};

}  // namespace

struct StreamingScene::State {
    const PackageReader& reader;
    ChunkAttributes attributes;
    StreamingOptions options;
    std::unique_ptr<ChunkBackend> backend;
    std::unique_ptr<ChunkCache> cache;
    std::unique_ptr<RayStreamer> streamer;  // host wavefront (backends that do not render on a device)
    std::unique_ptr<DemandPager> pager;     // device wavefront (ChunkBackend::rendersOnDevice)
    StreamingStats totals;  // what the streamer counts into; each render reports its difference
    IntegratorBuffers buffers;
    explicit State(const PackageReader& r) : reader(r) {}
};

ChunkAttributes requiredAttributes(const PackageInfo& info, const RenderOptions& options) {
    ChunkAttributes a;
    a.primitiveIds = (options.aovs & kAovPrimId) != 0;
    a.materialIds = info.materials.size() > 1;
    for (const Material& m : info.materials) a.singleSided |= !m.doubleSided;
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
    auto backend = factory(reader.info(), attributes);
    if (!backend) return backend.status();
    s.backend = std::move(backend).value();
    // One worker per core but one (the render thread's), except on two cores, where a cold
    // render mostly waits for decoding: two workers there (1M-4M city on the 2-core machine).
    const uint32_t cores = std::max(1u, std::thread::hardware_concurrency());
    const uint32_t workers = options.decodeThreads > 0 ? options.decodeThreads : cores <= 2 ? cores : cores - 1;
    s.cache = std::make_unique<ChunkCache>(reader, options.hostCacheBytes, workers);
    if (s.backend->rendersOnDevice())
        s.pager = std::make_unique<DemandPager>(reader.info(), attributes, *s.backend, *s.cache, s.totals);
    else
        s.streamer = std::make_unique<RayStreamer>(reader.info(), attributes, *s.backend, *s.cache, s.totals);
    return scene;
}

const ChunkAttributes& StreamingScene::attributes() const { return state_->attributes; }
ChunkBackend& StreamingScene::backend() { return *state_->backend; }

Result<RenderImage> StreamingScene::render(const RenderOptions& options, RenderStats* stats,
                                           StreamingStats* streamingStats, const StreamingProgress& progress,
                                           const std::atomic<bool>* cancel) {
    VASTRAY_TRY(validateRenderOptions(options));
    State& st = *state_;
    const PackageInfo& info = st.reader.info();
    const ChunkAttributes needed = requiredAttributes(info, options);
    if ((needed.primitiveIds && !st.attributes.primitiveIds) || (needed.materialIds && !st.attributes.materialIds) ||
        (needed.singleSided && !st.attributes.singleSided))
        return Status::error("this render needs chunk attributes the scene was not opened with (primid AOV?)");
    std::optional<tbb::global_control> threadLimit;
    if (options.threads > 0) threadLimit.emplace(tbb::global_control::max_allowed_parallelism, options.threads);

    const Camera camera = options.frameScene ? frameBounds(info.bounds, options.camera.fovYDegrees,
                                                           float(options.width) / float(options.height))
                                             : options.camera;
    VASTRAY_TRY(validateCamera(camera).withContext("camera: "));

    // The streamer counts into st.totals across renders; this render reports the difference.
    StreamingStats before = st.totals;
    before.bytesRead = st.cache->bytesRead(), before.decodes = st.cache->decodes();
    before.decodeSeconds = st.cache->decodeSeconds(), before.uploadSeconds = st.backend->uploadSeconds();
    before.deviceSeconds = st.backend->deviceSeconds(), before.bytesUploaded = st.backend->bytesUploaded();
    RenderImage image;
    image.allocate(options.width, options.height, options.aovs);
    const Clock::time_point start = Clock::now();
    uint64_t rays = 0;
    if (st.pager) {
        st.pager->beginRender();
        DeviceRenderJob job;
        job.options = &options;
        job.camera = camera;
        job.materials = info.materials;
        const Material fallback{"default"};
        if (job.materials.empty()) job.materials = std::span<const Material>(&fallback, 1);
        job.maxPathsPerWave = st.options.maxPathsPerWave;
        job.progress = progress;
        job.cancel = cancel;
        VASTRAY_TRY(st.backend->renderOnDevice(job, *st.pager, image, st.totals));
        rays = st.totals.walkedRays - before.walkedRays;
    } else {
        VASTRAY_TRY(renderOnHost(st, options, camera, image, progress, cancel, rays));
    }
    reportStats(st, before, stats, streamingStats, start, rays);
    return image;
}

Status StreamingScene::renderOnHost(State& st, const RenderOptions& options, const Camera& camera, RenderImage& image,
                                    const StreamingProgress& progress, const std::atomic<bool>* cancel,
                                    uint64_t& rays) {
    const PackageInfo& info = st.reader.info();
    st.streamer->beginRender();
    const CameraRays cameraRays(camera, options.width, options.height);
    Integrator integrator(info, options, cameraRays, *st.streamer, st.totals, image, cancel, st.buffers);
    integrator.begin();

    const uint64_t pixels = image.pixelCount();
    const uint64_t wave = std::min<uint64_t>(st.options.maxPathsPerWave, pixels * options.samplesPerPixel);
    const bool wantsAovs = (options.aovs & ~kAovCost) != 0;
    const uint64_t aovWaves = wantsAovs ? (pixels + wave - 1) / wave : 0;
    const uint64_t pathWaves = (pixels * options.samplesPerPixel + wave - 1) / wave;
    const uint64_t steps = options.integrator == IntegratorKind::Path ? options.maxDepth + 1ull : 1ull;
    const uint64_t total = aovWaves + pathWaves * steps;
    uint64_t done = 0;
    auto report = [&](uint64_t d) {
        done = std::min(d, total);
        if (progress) progress(done, total);
    };
    for (uint64_t w = 0; w < aovWaves; ++w) {
        VASTRAY_TRY(integrator.renderAovs(w * wave, std::min(wave, pixels - w * wave)));
        report(done + 1);
    }
    const uint64_t totalPaths = pixels * options.samplesPerPixel;
    for (uint64_t w = 0; w < pathWaves; ++w) {
        const uint64_t waveStart = done;
        VASTRAY_TRY(integrator.renderPaths(w * wave, std::min(wave, totalPaths - w * wave), [&] {
            if (done + 1 < waveStart + steps) report(done + 1);
        }));
        report(waveStart + steps);
    }
    integrator.finish();
    rays = integrator.rays();
    return Status::ok();
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
        s.chunksTouched = st.pager ? st.pager->chunksTouchedThisRender() : st.streamer->chunksTouchedThisRender();
        s.chunkLoads = t.chunkLoads - before.chunkLoads;
        s.streamChunksTouched = t.streamChunksTouched - before.streamChunksTouched;
        s.streamReloads = t.streamReloads - before.streamReloads;
        s.traceSeconds = t.traceSeconds - before.traceSeconds;
        s.walkSeconds = t.walkSeconds - before.walkSeconds;
        s.shadeSeconds = t.shadeSeconds - before.shadeSeconds;
        s.streams = t.streams - before.streams;
        s.chunkTraces = t.chunkTraces - before.chunkTraces;
        s.walkedRays = t.walkedRays - before.walkedRays;
        s.submits = t.submits - before.submits;
        s.walkPasses = t.walkPasses - before.walkPasses;
        s.hostToDeviceBytes = t.hostToDeviceBytes - before.hostToDeviceBytes;
        s.deviceToHostBytes = t.deviceToHostBytes - before.deviceToHostBytes;
        for (int k = 0; k < StreamingStats::kKernels; ++k) s.kernelSeconds[k] = t.kernelSeconds[k] - before.kernelSeconds[k];
        s.bytesRead = st.cache->bytesRead() - before.bytesRead;
        s.decodes = st.cache->decodes() - before.decodes;
        s.decodeSeconds = st.cache->decodeSeconds() - before.decodeSeconds;
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
