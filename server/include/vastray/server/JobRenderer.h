#pragma once
// The one seam between the render service and a render backend. The service owns jobs,
// queues, storage and front ends; a JobRenderer only turns (scene package, options) into an
// image. To add a backend (the streaming Vulkan renderer), implement this class and pass it
// to Service::open; nothing else in server/ knows which backend renders.
//
// Contract:
//  - render() runs on one worker thread of the service, one job at a time: each worker has
//    a renderer of its own (`serve --gpu-device 0,1`: one per device). The renderer may use
//    as many threads of its own as it likes.
//  - `progress` may be called from any thread, as often as the backend likes; the service
//    throttles what it stores and publishes. Each report carries every figure (passes and
//    chunk loads so far); none goes back within one render.
//  - `cancel` becomes true when the job is cancelled or the server shuts down. A backend
//    should return soon after (any error: the service records the job as CANCELLED); one
//    that cannot stop mid-render may finish, and the service discards the image.
//  - The renderer may keep state between jobs (a host chunk cache, a device buffer pool),
//    shared by every job: that is how a second job on a resident scene loads nothing again.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "vastray/core/RenderImage.h"
#include "vastray/core/RenderOptions.h"
#include "vastray/core/RenderStats.h"
#include "vastray/core/Result.h"
#include "vastray/streamer/StreamingRenderer.h"

namespace vastray::server {

struct JobRenderRequest {
    std::string scenePath;           // a validated scene package (.vast) on local disk
    RenderOptions options;           // validated with validateRenderOptions()
    uint64_t memoryBudgetBytes = 0;  // device memory this job may use
    // A camera of the scene by name or index (SubmitJobRequest.scene_camera); empty: the
    // scene's first camera unless `options` place the camera (applySceneCamera).
    std::string sceneCamera;
    // The scene's punctual lights are rendered (applySceneLights) unless this is false
    // (SubmitJobRequest.no_lights, `vastray render --no-lights`).
    bool sceneLights = true;
    // How an error names the environment map of `options` (`environment map ID (NAME)`); empty
    // without one.
    std::string environmentName;
};

struct JobRenderProgress {
    uint64_t passesDone = 0;   // units of work finished (tiles, passes: the backend's choice)
    uint64_t passesTotal = 0;  // 0 while unknown
    uint64_t chunkLoads = 0;   // chunks loaded from storage for this job so far
    uint64_t rays = 0;         // rays traced for this job so far (at least per finished pass)
    uint64_t deviceBytes = 0;  // device memory the render holds (0: none, or not known yet)
};

struct JobRenderStats {
    RenderStats render;
    uint64_t chunkLoads = 0;  // chunks loaded from storage for this job (0: all were resident)
    uint64_t passes = 0;      // passesTotal of the render's last progress report
    // Device memory the job's render held at its peak (the streaming pool: chunk slots,
    // tables, path state), in bytes; 0 for a backend without device memory (Embree).
    uint64_t peakDeviceBytes = 0;
    // Device time per kernel of the device wavefront (StreamingStats::kernelSeconds, named by
    // StreamingStats::kKernelNames); zero for Embree.
    double kernelSeconds[StreamingStats::kKernels] = {};
    // Set with a failed render() that was refused before rendering because the request does not
    // fit its memory budget (the scene's smallest pool, the environment map beside it): the error
    // names what and the budget, and the same request would be refused again, so the service
    // fails the job at once instead of running it again.
    bool overBudget = false;
};

using JobProgressCallback = std::function<void(const JobRenderProgress&)>;

class JobRenderer {
public:
    virtual ~JobRenderer() = default;
    virtual std::string name() const = 0;
    // What it renders on, for the start-up message ("Vulkan device [0] NAME"); may be empty.
    virtual std::string deviceDescription() const { return ""; }
    // Device memory held now by what stays open between jobs (the open scenes' pools); safe to
    // call while a job renders.
    virtual uint64_t deviceBytesHeld() const { return 0; }
    // Scenes open on the device between jobs (each with a pool of its own, one at most per
    // scene); safe to call while a job renders. 0 for a backend that keeps none (embree).
    virtual uint64_t deviceScenesOpen() const { return 0; }
    virtual Result<RenderImage> render(const JobRenderRequest& request, const JobProgressCallback& progress,
                                       const std::atomic<bool>& cancel, JobRenderStats* stats) = 0;
};

// The Embree reference renderer (in core, whole scene). Decoded scenes stay in a host cache
// of at most `hostCacheBytes` (least recently used evicted first), shared by every job.
// It cannot stop inside a render: `cancel` is checked before loading and before rendering.
std::unique_ptr<JobRenderer> makeEmbreeJobRenderer(uint64_t hostCacheBytes);

// The streaming Vulkan renderer (the default): the device opens here, so that a device index
// that does not exist (or cannot run the tracer) is an error at start-up naming the devices
// Vulkan reports, not at the first job. Scenes stay open after their jobs (device slots within
// the job's budget, a host chunk cache, residency), several at a time: the sum of the open
// scenes' device allocations stays within `devicePoolBytes` and the sum of their host caches
// within `hostCacheBytes`; a scene that does not fit closes the least recently used ones. So a
// job on a scene still open loads no chunk, also when jobs alternate between scenes. A scene is
// open once at most; a job whose budget cannot hold the scene's smallest pool, or its environment
// map beside it, is refused (JobRenderStats::overBudget) and closes nothing. Stops between ray
// streams when `cancel` is set.
Result<std::unique_ptr<JobRenderer>> makeStreamingJobRenderer(uint64_t hostCacheBytes, uint64_t devicePoolBytes,
                                                              int deviceIndex = -1);

}  // namespace vastray::server
