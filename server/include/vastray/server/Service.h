#pragma once
// The render service's domain functions. The gRPC and HTTP front ends are thin adapters over
// exactly these calls: they translate requests, call one function, and map the
// ServiceStatus at their boundary. Every function is thread-safe.
//
// Jobs run on worker threads owned by the service, one per JobRenderer given to open() (one
// per `serve --gpu-device` entry), each worker one job at a time; all take from the one queue,
// highest priority first (equal priorities in submission order). Import jobs (asynchronous
// uploads) run one at a time on a further thread, in upload order.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "vastray/core/EnvironmentMap.h"
#include "vastray/server/JobRenderer.h"
#include "vastray/server/Metrics.h"
#include "vastray/server/ServiceStatus.h"
#include "vastray/server/Sha256.h"
#include "vastray/server/Storage.h"

namespace vastray::server {

// Defaults are those of `vastray serve`; flags map one-to-one onto these fields.
struct ServiceOptions {
    std::filesystem::path dataDir;             // required: jobs.db, scenes/, results/, tmp/
    std::string databaseUrl;    // postgresql://… job store; empty: SQLite dataDir/jobs.db (--database)
    uint32_t maxAttempts = 3;   // failed attempts (crashes included) before a job FAILS (--max-attempts)
    // dataDir is a folder replicas share (--storage; needs databaseUrl): jobs are tiles in task
    // rows that any replica leases (TileTasks.cpp) instead of this server's own queue.
    bool sharedStorage = false;
    double leaseSeconds = 30;  // a tile's lease, renewed every third of it while it renders (--lease-seconds)
    uint64_t memoryBudgetBytes = 4ull << 30;   // device memory one job may use, per worker (--memory-budget)
    uint64_t hostCacheBytes = 2ull << 30;      // decoded scenes in host memory, all workers (--host-cache)
    uint32_t maxQueue = 1000;                  // QUEUED jobs; one more is RESOURCE_EXHAUSTED (--max-queue)
    uint64_t maxUploadBytes = 16ull << 30;     // one scene upload (--max-upload)
    uint64_t diskReserveBytes = 256ull << 20;  // an upload that would leave less free disk is refused
    bool paused = false;                       // accept and store jobs but start none (--paused)
};

// How far an import has come, in percent (rising; called from worker threads): 10 once the model
// is read, up to 90 as the package builder places triangles, 95 once written.
using ImportProgress = std::function<void(int percent)>;

class Service;

// One upload in progress (a scene's, or an environment map's): append() the bytes as they
// arrive, then finish() or finishEnvironment(). Destroying an unfinished upload deletes what
// was written.
class SceneUpload {
public:
    ~SceneUpload();
    ServiceStatus append(const void* data, size_t size);
    // Hashes, then imports (mesh, zip) or validates (.vast) the file and stores the scene;
    // content already stored returns the stored scene. `async`: queues the import as an
    // import job instead and returns at once, the scene's import_job_id naming the job.
    ServiceResult<v1::Scene> finish(bool async = false);
    // An upload begun with beginEnvironmentUpload: hashes, decodes the image with the reader
    // `vastray render --environment` uses (readEnvironmentMap) and stores the environment.
    ServiceResult<v1::Environment> finishEnvironment();

private:
    friend class Service;
    SceneUpload(Service& service, std::string name, std::filesystem::path file, uint64_t maxBytes);
    Service& service_;
    std::string name_;
    std::filesystem::path file_;
    std::ofstream out_;
    Sha256 hash_;
    uint64_t maxBytes_ = 0;  // --max-upload, or kMaxEnvironmentUploadBytes when that is smaller
    uint64_t bytes_ = 0, nextDiskCheck_ = 0;
    bool finished_ = false;
};

// The largest environment map upload (besides --max-upload): an uncompressed float RGB EXR at
// the texel limit of an environment map (kMaxEnvironmentTexels) is 768 MiB.
constexpr uint64_t kMaxEnvironmentUploadBytes = 1ull << 30;

struct SubmitOutcome {
    v1::Job job;
    bool created = false;  // false: an earlier request with the same request_id made it
};

struct ResultFile {
    std::filesystem::path path;
    uint64_t bytes = 0;
    std::string contentType;
};

class Service {
public:
    // Opens (or creates) the stores in options.dataDir and requeues every job that was QUEUED
    // or RUNNING when the last server stopped.
    static Result<std::unique_ptr<Service>> open(const ServiceOptions& options,
                                                 std::unique_ptr<JobRenderer> renderer);
    // One worker per renderer (at least one, at most kMaxWorkers), in this order: worker i
    // renders through renderers[i] and reports i in JobStats.worker.
    static Result<std::unique_ptr<Service>> open(const ServiceOptions& options,
                                                 std::vector<std::unique_ptr<JobRenderer>> renderers);
    static constexpr size_t kMaxWorkers = 16;
    ~Service();
    Service(const Service&) = delete;
    Service& operator=(const Service&) = delete;

    // `expectedBytes` (0: unknown) lets an upload that cannot fit be refused before any byte.
    ServiceResult<std::unique_ptr<SceneUpload>> beginUpload(const std::string& name, uint64_t expectedBytes);
    ServiceResult<v1::FindMissingResponse> findMissing(const v1::FindMissingRequest& request);
    ServiceResult<v1::Scene> getScene(const v1::GetSceneRequest& request);
    ServiceResult<v1::ListScenesResponse> listScenes(const v1::ListScenesRequest& request);
    ServiceResult<v1::DeleteSceneResponse> deleteScene(const v1::DeleteSceneRequest& request);

    // Environment maps (SceneService.UploadEnvironment and the rest; EnvironmentFunctions.cpp).
    // The upload's limit is the smaller of --max-upload and kMaxEnvironmentUploadBytes.
    ServiceResult<std::unique_ptr<SceneUpload>> beginEnvironmentUpload(const std::string& name,
                                                                       uint64_t expectedBytes);
    ServiceResult<v1::Environment> getEnvironment(const v1::GetEnvironmentRequest& request);
    ServiceResult<v1::ListEnvironmentsResponse> listEnvironments(const v1::ListEnvironmentsRequest& request);
    ServiceResult<v1::DeleteEnvironmentResponse> deleteEnvironment(const v1::DeleteEnvironmentRequest& request);

    ServiceResult<SubmitOutcome> submitJob(const v1::SubmitJobRequest& request);
    ServiceResult<v1::Job> getJob(const v1::GetJobRequest& request);
    ServiceResult<v1::ListJobsResponse> listJobs(const v1::ListJobsRequest& request);
    ServiceResult<v1::Job> cancelJob(const v1::CancelJobRequest& request);
    // Blocks, calling `emit` (on the caller's thread) with a snapshot and then every change,
    // until the job reaches a final state (OK), `emit` returns false or `clientGone` returns
    // true (CANCELLED), or the server shuts down (UNAVAILABLE).
    ServiceStatus watchJob(const v1::WatchJobRequest& request,
                           const std::function<bool(const v1::JobEvent&)>& emit,
                           const std::function<bool()>& clientGone);
    ServiceResult<ResultFile> resultFile(const std::string& jobId);
    // One channel group of a SUCCEEDED job's image as an 8-bit PNG for display (`aov`: beauty,
    // depth, normal, albedo, primid, chunkid or cost; docs/SERVICE.md, "Result previews"). An AOV
    // the job did not render, or an unknown name, is INVALID_ARGUMENT naming `aov`.
    ServiceResult<std::string> resultPreviewPng(const std::string& jobId, const std::string& aov);

    // Ready: stores open, workers running, not shutting down.
    bool ready() const;
    Metrics& metrics() { return metrics_; }
    const ServiceOptions& options() const { return options_; }
    // Prometheus text exposition of every figure (vastray_ prefix, base units).
    std::string metricsText();

    // Refuses new uploads and jobs, starts no further job and ends every watch (UNAVAILABLE).
    void stopAccepting();
    // stopAccepting(), then waits up to `grace` for the
    // running jobs (one per busy worker). Past the grace every running job is asked to stop; it
    // stays RUNNING in the store and is re-run at the next start. True when every worker has
    // stopped.
    bool shutdown(std::chrono::milliseconds grace);
    // After shutdown(): the jobs left RUNNING for the next start (empty when none).
    std::vector<std::string> jobsLeftRunning() const;
    // With sharedStorage: this replica's name in the task rows (host name and a random suffix).
    const std::string& replicaId() const { return replicaId_; }
    // Test-only: called by watchJob on the watcher's thread right after it has read the job for
    // its snapshot, before the snapshot is built (WatchJobTest finishes the job there). Set it
    // before any watch starts.
    void setWatchSnapshotReadHookForTest(std::function<void()> hook) {
        watchSnapshotReadHook_ = std::move(hook);
    }

private:
    friend class SceneUpload;
    struct QueueEntry {
        uint32_t priority = 0;
        uint64_t order = 0;
        std::string id;
        bool operator<(const QueueEntry& o) const {
            return priority != o.priority ? priority > o.priority : order < o.order;
        }
    };

    // One render worker: a thread with its own renderer (its own device and pool). Its job
    // fields are guarded by Service::mutex_.
    struct Worker {
        uint32_t index = 0;
        std::unique_ptr<JobRenderer> renderer;
        std::string device;  // renderer->deviceDescription(), for JobStats.device
        std::thread thread;
        std::string runningId;
        // The running job's progress: the latest figures, and those last published to watchers.
        JobRenderProgress live, published;
        std::chrono::steady_clock::time_point publishedAt;
        int livePercent = 0;
        std::atomic<bool> cancel{false};
        bool stopped = false;
    };

    explicit Service(const ServiceOptions& options);
    Status recoverJobs();
    // An upload's checks shared by scenes and environments: accepting, the name, the size.
    ServiceStatus checkUploadStart(const std::string& name, uint64_t expectedBytes, uint64_t maxBytes);
    ServiceResult<v1::Environment> storeEnvironment(const std::string& name, const std::filesystem::path& file,
                                                    const std::string& digest, uint64_t bytes);
    // The job's environment map read as `vastray render --environment FILE --environment-scale S`
    // reads it (the last one read is kept for the next job that asks for the same), or null when
    // the request has none; `name` is set to how errors name it (`environment map ID (NAME)`).
    ServiceResult<std::shared_ptr<const EnvironmentMap>> jobEnvironmentMap(
        const v1::SubmitJobRequest& request, std::string& name);
    ServiceResult<v1::Scene> storeUpload(const std::string& name, const std::filesystem::path& file,
                                         const std::string& digest, uint64_t bytes,
                                         const ImportProgress& progress = {});
    ServiceResult<v1::Scene> importUpload(const std::string& name, const std::filesystem::path& file,
                                          const std::string& digest, uint64_t bytes, const ImportProgress& progress);
    ServiceStatus importZip(const std::string& name, const std::filesystem::path& file,
                            const std::filesystem::path& package, std::vector<std::string>& warnings,
                            const ImportProgress& progress);
    // An import job for the uploaded `file` (moved into the job's keeping); the scene to return.
    ServiceResult<v1::Scene> queueImport(const std::string& name, const std::filesystem::path& file,
                                         const std::string& digest, uint64_t bytes);
    void importLoop();
    void runImport(const std::string& jobId, const std::filesystem::path& file);
    // "" or " (job ID is importing it)" for a scene id being imported.
    std::string importNoteLocked(const std::string& sceneId) const;

    void workerLoop(Worker& worker);
    // sharedStorage: each worker leases tasks (TileTasks.cpp) instead of taking the queue's jobs.
    void replicaLoop(Worker& worker);
    void runTask(Worker& worker, const TaskStore::Lease& lease);
    ServiceStatus renderTile(Worker& worker, const TaskStore::Lease& lease);
    ServiceStatus assembleResult(const TaskStore::Lease& lease);
    void runJob(Worker& worker, const std::string& id);
    ServiceStatus renderAndStore(Worker& worker, v1::Job& job);
    // What a whole-frame job and a tile share: the request's options (`region`, if any), the
    // host-memory check, the stored scene, the render on `worker`, and the metrics every render
    // adds to. `image` is set when the status is OK.
    ServiceStatus renderRequest(Worker& worker, const v1::Job& job, std::optional<PixelBounds> region,
                                JobRenderStats& stats, std::optional<RenderImage>& image);
    ServiceStatus renderAndStoreGuarded(Worker& worker, v1::Job& job);
    void finishJob(v1::Job job, const ServiceStatus& outcome);
    void onProgress(Worker& worker, const JobRenderProgress& progress);
    // The worker rendering job `id` now, or nullptr.
    Worker* runningWorkerLocked(const std::string& id) const;
    bool allWorkersStoppedLocked() const { return workersStopped_ == workers_.size(); }
    void notifyChangeLocked() {
        ++changeCounter_;
        changed_.notify_all();
    }
    v1::JobEvent eventLocked(const v1::Job& job, v1::JobEvent::Kind kind) const;
    void overlayLiveLocked(v1::Job& job) const;

    // vastray_tasks_waiting: with a task store (replicas), its leaseable tiles; none when the
    // query failed (logged).
    std::optional<uint64_t> countWaitingTiles();

    ServiceOptions options_;
    std::string replicaId_;
    // The task store is queried for vastray_tasks_waiting at most once per this period, however
    // often /metrics is scraped (Prometheus scrapes every 15-60 s; several scrapers may share it).
    static constexpr auto kWaitingTilesPeriod = std::chrono::seconds(1);
    CachedGauge waitingTiles_{kWaitingTilesPeriod, [this] { return countWaitingTiles(); }};
    std::vector<std::unique_ptr<Worker>> workers_;
    std::unique_ptr<ObjectStore> objects_;
    MetadataStores stores_;
    Metrics metrics_;

    mutable std::mutex mutex_;  // queue, running jobs, state transitions in the store
    std::mutex importMutex_;    // one import at a time (imports use every core)
    std::condition_variable workAvailable_, changed_, workerIdle_;
    std::set<QueueEntry> queue_;
    uint64_t nextOrder_ = 0;
    uint64_t changeCounter_ = 0;  // bumped under mutex_ at every change a watcher may see
    std::function<void()> watchSnapshotReadHook_;
    std::vector<std::string> leftRunning_;
    static constexpr auto kLoadPublishInterval = std::chrono::milliseconds(100);
    size_t workersStopped_ = 0;
    bool stopping_ = false, accepting_ = true, shutdownCancel_ = false;
    // Import jobs: queued (job id, the upload's file), and the scene ids being imported (queued
    // or running) -> their job.
    std::deque<std::pair<std::string, std::filesystem::path>> importQueue_;
    std::map<std::string, std::string> importing_;
    std::condition_variable importAvailable_;
    std::thread importWorker_;
    // jobEnvironmentMap's last map, by "ID SCALE"; the mutex also makes every environment decode
    // (uploads' and jobs') one at a time.
    std::mutex environmentMutex_;
    std::string environmentKey_;
    std::shared_ptr<const EnvironmentMap> environmentMap_;
    std::string environmentName_;  // environmentMap_'s, as jobEnvironmentMap's `name`
};

}  // namespace vastray::server
