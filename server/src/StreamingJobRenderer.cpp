// The streaming Vulkan renderer behind the JobRenderer seam. The device is opened once, when
// the renderer is made (at server start). Scenes stay open after their jobs (device slots, host
// chunk cache, residency), so a later job on an open scene and budget loads nothing again, also
// when jobs alternate between scenes. Every open scene draws on two budgets of its renderer
// (one renderer per service worker): the device pool (`serve --memory-budget`: the sum of the
// open scenes' device allocations stays within it) and the host chunk cache (the worker's share
// of `--host-cache`: the sum of their host caches stays within it; a scene's cache is sized to
// its decoded chunks when those are smaller). A scene that does not fit beside the others
// closes the least recently used ones first. A scene is open once at most: a job that needs its
// pool planned anew (another budget, a larger environment map) replaces the scene's open entry.
#include <algorithm>
#include <atomic>
#include <memory>
#include <mutex>
#include <string_view>
#include <vector>

#include "vastray/core/ByteSize.h"
#include "vastray/core/EnvironmentMap.h"
#include "vastray/gpu/VulkanChunkBackend.h"
#include "vastray/gpu/VulkanDevice.h"
#include "vastray/server/JobRenderer.h"
#include "vastray/streamer/ScenePackage.h"
#include "vastray/streamer/StreamingRenderer.h"

namespace vastray::server {
namespace {

// The scene's backend, counting chunk loads as they happen: the pager makes every load through
// it, on the render thread. A render sets `onLoad` to report them in its progress, so a watcher
// sees chunk loads while the render pages, not only in the final figures.
class LoadCountingBackend final : public ChunkBackend {
public:
    explicit LoadCountingBackend(std::unique_ptr<ChunkBackend> inner) : inner_(std::move(inner)) {}

    std::function<void()> onLoad;  // set for the length of one render

    std::string name() const override { return inner_->name(); }
    uint32_t slotCount() const override { return inner_->slotCount(); }
    Status load(uint32_t slot, const DecodedChunk& chunk, std::span<const uint8_t> singleSided) override {
        Status loaded = inner_->load(slot, chunk, singleSided);
        if (loaded && onLoad) onLoad();
        return loaded;
    }
    Status renderOnDevice(const DeviceRenderJob& job, ChunkPager& pager, RenderImage& image,
                          StreamingStats& stats) override {
        return inner_->renderOnDevice(job, pager, image, stats);
    }
    uint64_t bytesUploaded() const override { return inner_->bytesUploaded(); }
    uint64_t peakDeviceBytes() const override { return inner_->peakDeviceBytes(); }
    double uploadSeconds() const override { return inner_->uploadSeconds(); }
    double deviceSeconds() const override { return inner_->deviceSeconds(); }

private:
    std::unique_ptr<ChunkBackend> inner_;
};

// The progress of one render: passes and rays from the wavefront's tiles, chunk loads from the
// backend, the pool's device bytes (allocated up front); each report carries all of them, so
// none goes back to 0 when another moves.
class RenderProgressReporter {
public:
    RenderProgressReporter(const JobProgressCallback& progress, LoadCountingBackend& backend,
                           const StreamingScene& scene)
        : progress_(progress), backend_(backend), scene_(scene), raysBefore_(scene.raysWalked()) {
        now_.deviceBytes = backend.peakDeviceBytes();
        if (!progress_) return;
        backend_.onLoad = [this] {
            ++now_.chunkLoads;
            progress_(now_);
        };
    }
    ~RenderProgressReporter() { backend_.onLoad = nullptr; }

    StreamingProgress passReporter() {
        if (!progress_) return {};
        return [this](uint64_t done, uint64_t total) {
            now_.passesDone = done;
            now_.passesTotal = total;
            now_.rays = scene_.raysWalked() - raysBefore_;
            progress_(now_);
        };
    }
    // The last report again with the render's own count of loads (the same number when every
    // load went through the backend).
    void finish(uint64_t chunkLoads) {
        now_.chunkLoads = std::max(now_.chunkLoads, chunkLoads);
        now_.rays = scene_.raysWalked() - raysBefore_;
        if (progress_) progress_(now_);
    }
    uint64_t passesTotal() const { return now_.passesTotal; }

private:
    const JobProgressCallback& progress_;
    LoadCountingBackend& backend_;
    const StreamingScene& scene_;
    const uint64_t raysBefore_;
    JobRenderProgress now_;
};

// planPool's refusal of a job's budget in the service's words: the job's memory_budget_bytes
// rather than the CLI's --memory-budget; and when the scene's smallest pool fits the budget
// without the environment map, the map named, with its device bytes and what the budget leaves it.
Status budgetRefusal(const PackageInfo& info, const ChunkAttributes& needed, const JobRenderRequest& request,
                     uint64_t volumeBytes, const Status& refused) {
    const uint64_t budget = request.memoryBudgetBytes;
    const std::shared_ptr<const EnvironmentMap>& map = request.options.environment.map;
    auto withoutMap = gpu::planPool(info, needed, budget, true, gpu::kWaveShareOutOfCore, 0, volumeBytes);
    if (map && withoutMap) {
        const uint64_t bytes = map->deviceBytes();
        return Status::error(
            (request.environmentName.empty() ? std::string("the environment map") : request.environmentName) +
            " needs " + formatBytes(bytes) + " = " + std::to_string(bytes) +
            " bytes of device memory; the job's memory_budget_bytes of " + formatBytes(budget) + " = " +
            std::to_string(budget) + " bytes leaves it at most " +
            formatBytes(budget - withoutMap->minimumBytes) + " beside this scene's smallest pool of " +
            formatBytes(withoutMap->minimumBytes));
    }
    constexpr std::string_view kFlag = "--memory-budget ";
    std::string message = refused.message();
    if (message.starts_with(kFlag)) message = "memory_budget_bytes " + message.substr(kFlag.size());
    return Status::error(message);
}

class StreamingJobRenderer final : public JobRenderer {
public:
    StreamingJobRenderer(uint64_t hostCacheBytes, uint64_t devicePoolBytes, int deviceIndex,
                         std::unique_ptr<gpu::VulkanDevice> device)
        : hostCacheBytes_(hostCacheBytes), devicePoolBytes_(devicePoolBytes), deviceIndex_(deviceIndex),
          device_(std::move(device)) {}

    std::string name() const override { return "vulkan"; }
    uint64_t deviceBytesHeld() const override { return held_; }
    uint64_t deviceScenesOpen() const override { return scenesOpen_; }
    std::string deviceDescription() const override {
        return "Vulkan device " + (deviceIndex_ >= 0 ? "[" + std::to_string(deviceIndex_) + "] " : std::string()) +
               device_->info().name;
    }

    Result<RenderImage> render(const JobRenderRequest& request, const JobProgressCallback& progress,
                               const std::atomic<bool>& cancel, JobRenderStats* stats) override {
        std::lock_guard<std::mutex> lock(mutex_);
        if (cancel) return Status::error("cancelled before loading the scene");
        bool overBudget = false;
        auto open = openScene(request, overBudget);
        held_ = deviceInUse();
        scenesOpen_ = open_.size();
        if (stats) stats->overBudget = overBudget;
        if (!open) return open.status();
        OpenScene& scene = **open;
        StreamingStats streaming;
        streaming.memoryBudgetBytes = request.memoryBudgetBytes;
        RenderOptions options = request.options;
        VASTRAY_TRY(applySceneCamera(scene.reader->info().cameras, request.sceneCamera, options));
        options.volumes = scene.volumes;
        if (request.sceneLights)
            applySceneLights(scene.reader->info().lights, scene.reader->info().bounds, options);
        options.emitters = scene.emitters;
        RenderProgressReporter reporter(progress, *scene.backend, *scene.scene);
        auto image = scene.scene->render(options, stats ? &stats->render : nullptr, &streaming,
                                          reporter.passReporter(), &cancel);
        reporter.finish(streaming.chunkLoads);
        if (stats) {
            stats->chunkLoads = streaming.chunkLoads;
            stats->passes = reporter.passesTotal();
            stats->peakDeviceBytes = streaming.peakDeviceBytes;
            for (int k = 0; k < StreamingStats::kKernels; ++k) stats->kernelSeconds[k] = streaming.kernelSeconds[k];
        }
        if (!image && cancel) return Status::error("cancelled");
        return image;
    }

private:
    struct OpenScene {
        std::string path;
        uint64_t budget = 0;       // the job budget it was opened with
        uint64_t mapBytes = 0;     // device bytes its pool keeps for an environment map
        uint64_t hostBytes = 0;    // its host cache's capacity
        uint64_t lastUse = 0;
        std::unique_ptr<PackageReader> reader;
        std::unique_ptr<StreamingScene> scene;
        LoadCountingBackend* backend = nullptr;  // owned by scene
        std::shared_ptr<const std::vector<Volume>> volumes;  // the package's; null: none
        std::shared_ptr<const EmitterTable> emitters;        // made once (sceneEmitterTable); null: none
    };

    uint64_t deviceInUse() const {
        uint64_t sum = 0;
        for (const OpenScene& o : open_) sum += o.scene->backend().peakDeviceBytes();  // allocated up front
        return sum;
    }
    uint64_t hostInUse() const {
        uint64_t sum = 0;
        for (const OpenScene& o : open_) sum += o.hostBytes;
        return sum;
    }
    // Closes the least recently used open scene; false when none is open.
    bool closeLeastRecentlyUsed() {
        if (open_.empty()) return false;
        auto oldest = std::min_element(open_.begin(), open_.end(),
                                       [](const OpenScene& a, const OpenScene& b) { return a.lastUse < b.lastUse; });
        open_.erase(oldest);
        return true;
    }

    // The scene's open entry when it was opened with the job's budget and kept enough for the
    // job's map; else the scene opened anew, replacing that entry. A job whose request does not
    // fit its budget is refused (overBudget) before anything open is closed.
    Result<OpenScene*> openScene(const JobRenderRequest& request, bool& overBudget) {
        const uint64_t budget = request.memoryBudgetBytes;
        // The job's environment map is kept from the budget, as `vastray render --environment`
        // does: an open scene whose pool kept less for it is opened again.
        const uint64_t mapBytes = gpu::environmentBytes(request.options.environment);
        for (OpenScene& o : open_)
            if (o.path == request.scenePath && o.budget == budget && o.mapBytes >= mapBytes) {
                o.lastUse = ++tick_;
                return &o;
            }
        OpenScene entry;
        auto reader = PackageReader::open(request.scenePath);
        if (!reader) return reader.status();
        entry.reader = std::move(reader).value();
        const PackageInfo& info = entry.reader->info();
        ChunkAttributes needed = requiredAttributes(info, request.options);
        // Open with primitive ids (and the scene's UVs) whenever a scene is opened, so that a later
        // job asking for the primid (uv) AOV does not force a reload.
        needed.primitiveIds = true;
        needed.uvs = info.hasUvs;  // likewise for the uv AOV (8 bytes a vertex, only in scenes with UVs)
        // The volumes stay on the device with the scene: their bytes (or a pool their bricks are
        // paged through) are kept from the budget.
        const uint64_t volumeBytes = gpu::volumeReserveBytes(info, budget);
        if (!info.volumes.empty()) {
            auto volumes = entry.reader->openVolumes();  // each brick read when a render needs it
            if (!volumes) return volumes.status();
            entry.volumes = std::move(volumes).value();
        }
        auto plan = gpu::planPool(info, needed, budget, true, gpu::kWaveShareOutOfCore, 0, mapBytes + volumeBytes);
        if (!plan) {
            overBudget = true;
            return budgetRefusal(info, needed, request, volumeBytes, plan.status());
        }
        // The same scene under another budget, or whose pool kept less for the map, is closed
        // before its new pool is allocated: never open twice.
        std::erase_if(open_, [&](const OpenScene& o) { return o.path == request.scenePath; });
        entry.hostBytes = std::min(hostCacheBytes_, info.decodedBytes());
        while ((deviceInUse() + plan->totalBytes > devicePoolBytes_ || hostInUse() + entry.hostBytes > hostCacheBytes_) &&
               closeLeastRecentlyUsed()) {
        }
        StreamingOptions options;
        options.hostCacheBytes = entry.hostBytes;
        auto scene = StreamingScene::open(*entry.reader, needed, options,
                                          [&](const PackageInfo& p, const ChunkAttributes& attributes)
                                              -> Result<std::unique_ptr<ChunkBackend>> {
                                              auto backend =
                                                  gpu::createVulkanChunkBackend(*device_, p, attributes, budget,
                                                                                gpu::kWaveShareOutOfCore, {},
                                                                                mapBytes + volumeBytes);
                                              if (!backend) return backend.status();
                                              auto counting = std::make_unique<LoadCountingBackend>(
                                                  std::move(backend).value());
                                              entry.backend = counting.get();
                                              return std::unique_ptr<ChunkBackend>(std::move(counting));
                                          });
        if (!scene) return scene.status();
        entry.scene = std::move(scene).value();
        entry.emitters = sceneEmitterTable(info.emitters, info.materials);
        entry.path = request.scenePath;
        entry.budget = budget;
        entry.mapBytes = mapBytes;
        entry.lastUse = ++tick_;
        open_.push_back(std::move(entry));
        return &open_.back();
    }

    std::mutex mutex_;
    std::atomic<uint64_t> held_{0};  // deviceInUse() after the last openScene, for /metrics
    std::atomic<uint64_t> scenesOpen_{0};  // open_.size() after the last openScene, for /metrics
    const uint64_t hostCacheBytes_;
    const uint64_t devicePoolBytes_;
    const int deviceIndex_;
    const std::unique_ptr<gpu::VulkanDevice> device_;
    std::vector<OpenScene> open_;  // destroyed before device_ (declared after it)
    uint64_t tick_ = 0;
};

}  // namespace

Result<std::unique_ptr<JobRenderer>> makeStreamingJobRenderer(uint64_t hostCacheBytes, uint64_t devicePoolBytes,
                                                              int deviceIndex) {
    if (deviceIndex >= 0) {
        // An index past the end is named as such (VulkanDevice::create calls it "not usable").
        auto devices = gpu::listVulkanDevices();
        if (!devices) return devices.status().withContext("Vulkan: ");
        if (size_t(deviceIndex) >= devices->size()) {
            std::string list;
            for (size_t i = 0; i < devices->size(); ++i)
                list += (i ? ", [" : "[") + std::to_string(i) + "] " + (*devices)[i].name +
                        ((*devices)[i].usable ? "" : " (unusable: lacks " + (*devices)[i].missing + ")");
            return Status::error("Vulkan: there is no device " + std::to_string(deviceIndex) + "; " +
                                 (devices->empty() ? std::string("Vulkan reports no device")
                                                   : "the devices are " + list));
        }
    }
    gpu::VulkanDeviceOptions options;
    options.deviceIndex = deviceIndex;
    auto device = gpu::VulkanDevice::create(options);
    if (!device) return device.status();
    return std::unique_ptr<JobRenderer>(
        std::make_unique<StreamingJobRenderer>(hostCacheBytes, devicePoolBytes, deviceIndex,
                                               std::move(device).value()));
}

}  // namespace vastray::server
