// The streaming Vulkan renderer behind the JobRenderer seam. The device is opened once, when
// the renderer is made (at server start); the
// scene of the last job stays open (device slots, host chunk cache, residency), so the next
// job on the same scene and budget loads nothing again. A job on another scene (or needing
// another budget or attributes) closes it first: at any time one pool of at most the job's
// budget holds device memory, shared by every job that renders that scene.
#include <memory>
#include <mutex>

#include "vastray/gpu/VulkanChunkBackend.h"
#include "vastray/gpu/VulkanDevice.h"
#include "vastray/server/JobRenderer.h"
#include "vastray/streamer/ScenePackage.h"
#include "vastray/streamer/StreamingRenderer.h"

namespace vastray::server {
namespace {

class StreamingJobRenderer final : public JobRenderer {
public:
    StreamingJobRenderer(uint64_t hostCacheBytes, int deviceIndex, std::unique_ptr<gpu::VulkanDevice> device)
        : hostCacheBytes_(hostCacheBytes), deviceIndex_(deviceIndex), device_(std::move(device)) {}

    std::string name() const override { return "vulkan"; }
    std::string deviceDescription() const override {
        return "Vulkan device " + (deviceIndex_ >= 0 ? "[" + std::to_string(deviceIndex_) + "] " : std::string()) +
               device_->info().name;
    }

    Result<RenderImage> render(const JobRenderRequest& request, const JobProgressCallback& progress,
                               const std::atomic<bool>& cancel, JobRenderStats* stats) override {
        std::lock_guard<std::mutex> lock(mutex_);
        if (cancel) return Status::error("cancelled before loading the scene");
        VASTRAY_TRY(openScene(request));
        StreamingStats streaming;
        streaming.memoryBudgetBytes = request.memoryBudgetBytes;
        StreamingProgress onProgress;
        if (progress) onProgress = [&](uint64_t done, uint64_t total) { progress({done, total, 0}); };
        auto image = scene_->render(request.options, stats ? &stats->render : nullptr, &streaming, onProgress,
                                    &cancel);
        if (stats) {
            stats->chunkLoads = streaming.chunkLoads;
            stats->peakDeviceBytes = streaming.peakDeviceBytes;
        }
        if (progress) progress({1, 1, streaming.chunkLoads});
        if (!image && cancel) return Status::error("cancelled");
        return image;
    }

private:
    Status openScene(const JobRenderRequest& request) {
        if (scene_ && path_ == request.scenePath && budget_ == request.memoryBudgetBytes) return Status::ok();
        auto reader = PackageReader::open(request.scenePath);
        if (!reader) return reader.status();
        ChunkAttributes needed = requiredAttributes((*reader)->info(), request.options);
        // Open with primitive ids whenever a scene is opened, so that a later job asking for
        // the primid AOV does not force a reload.
        needed.primitiveIds = true;
        scene_.reset();
        reader_.reset();
        reader_ = std::move(reader).value();
        StreamingOptions options;
        options.hostCacheBytes = hostCacheBytes_;
        const uint64_t budget = request.memoryBudgetBytes;
        auto scene = StreamingScene::open(*reader_, needed, options,
                                          [&](const PackageInfo& info, const ChunkAttributes& attributes) {
                                              return gpu::createVulkanChunkBackend(*device_, info, attributes,
                                                                                   budget);
                                          });
        if (!scene) return scene.status();
        scene_ = std::move(scene).value();
        path_ = request.scenePath;
        budget_ = budget;
        return Status::ok();
    }

    std::mutex mutex_;
    const uint64_t hostCacheBytes_;
    const int deviceIndex_;
    const std::unique_ptr<gpu::VulkanDevice> device_;
    std::unique_ptr<PackageReader> reader_;
    std::unique_ptr<StreamingScene> scene_;
    std::string path_;
    uint64_t budget_ = 0;
};

}  // namespace

Result<std::unique_ptr<JobRenderer>> makeStreamingJobRenderer(uint64_t hostCacheBytes, int deviceIndex) {
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
        std::make_unique<StreamingJobRenderer>(hostCacheBytes, deviceIndex, std::move(device).value()));
}

}  // namespace vastray::server
