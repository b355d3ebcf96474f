// The job half of the service: open and recovery, submit (admission, idempotency), get,
// list, cancel, watch, results, shutdown.
#include <google/protobuf/util/message_differencer.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "JobRequest.h"
#include "vastray/server/Service.h"

namespace vastray::server {
namespace {

constexpr auto kWatchPoll = std::chrono::milliseconds(250);

// Within one watch no figure goes back: a job that FAILED or was CANCELLED mid-render has no
// stored pass count, and its final event keeps the last one the stream showed.
void keepMonotone(const v1::JobEvent& last, v1::JobEvent& event) {
    event.set_percent(std::max(event.percent(), last.percent()));
    event.set_passes_total(std::max(event.passes_total(), last.passes_total()));
    event.set_passes_done(std::max(event.passes_done(), last.passes_done()));
    event.set_chunk_loads(std::max(event.chunk_loads(), last.chunk_loads()));
    event.set_rays(std::max(event.rays(), last.rays()));
    event.set_device_bytes(std::max(event.device_bytes(), last.device_bytes()));
}

// "HOST-XXXXXXXX": unique per start, readable in the task rows.
std::string replicaName() {
    char host[256] = {};
    if (::gethostname(host, sizeof host - 1) != 0 || !host[0]) std::snprintf(host, sizeof host, "replica");
    return std::string(host) + "-" + randomHex(8);
}

ServiceStatus checkJobId(const std::string& id) {
    if (id.empty()) return invalidArgument("id", "required");
    return {};
}

}  // namespace

Service::Service(const ServiceOptions& options) : options_(options) {}

Result<std::unique_ptr<Service>> Service::open(const ServiceOptions& options,
                                               std::unique_ptr<JobRenderer> renderer) {
    std::vector<std::unique_ptr<JobRenderer>> renderers;
    renderers.push_back(std::move(renderer));
    return open(options, std::move(renderers));
}

Result<std::unique_ptr<Service>> Service::open(const ServiceOptions& options,
                                               std::vector<std::unique_ptr<JobRenderer>> renderers) {
    if (options.dataDir.empty()) return Status::error("a data folder is required");
    if (options.maxAttempts == 0) return Status::error("--max-attempts must be at least 1");
    if (renderers.empty() || renderers.size() > kMaxWorkers)
        return Status::error("between 1 and " + std::to_string(kMaxWorkers) + " workers are possible, not " +
                             std::to_string(renderers.size()));
    std::unique_ptr<Service> service(new Service(options));
    for (auto& renderer : renderers) {
        auto worker = std::make_unique<Worker>();
        worker->index = uint32_t(service->workers_.size());
        worker->device = renderer->deviceDescription();
        worker->renderer = std::move(renderer);
        service->workers_.push_back(std::move(worker));
    }
    if (options.sharedStorage && options.databaseUrl.empty())
        return Status::error("--storage needs --database (the replicas share a PostgreSQL database)");
    if (options.sharedStorage && !(options.leaseSeconds >= 1))
        return Status::error("--lease-seconds must be at least 1");
    if (options.sharedStorage) service->replicaId_ = replicaName();
    auto objects = options.sharedStorage ? openSharedFileObjectStore(options.dataDir, service->replicaId_)
                                         : openFileObjectStore(options.dataDir);
    if (!objects) return objects.status();
    service->objects_ = std::move(*objects);
    auto stores = options.databaseUrl.empty()
                      ? openSqliteStores(options.dataDir / "jobs.db")
                      : openPostgresStores(options.databaseUrl, options.sharedStorage);
    if (!stores) return stores.status();
    service->stores_ = *stores;
    // Replicas recover nothing at start: an interrupted tile's lease expires and another
    // replica takes it over.
    if (!options.sharedStorage) VASTRAY_TRY(service->recoverJobs());
    for (auto& worker : service->workers_)
        worker->thread = std::thread([s = service.get(), w = worker.get()] {
            s->options_.sharedStorage ? s->replicaLoop(*w) : s->workerLoop(*w);
        });
    service->importWorker_ = std::thread([s = service.get()] { s->importLoop(); });
    return service;
}

Service::~Service() {
    shutdown(std::chrono::hours(24));
    for (auto& worker : workers_)
        if (worker->thread.joinable()) worker->thread.join();
    if (importWorker_.joinable()) importWorker_.join();
}

// Jobs a previous server accepted but did not finish go back into the queue; a RUNNING one
// was interrupted mid-render and runs again from the start (its result was never stored),
// unless that makes --max-attempts failed attempts.
Status Service::recoverJobs() {
    auto jobs = stores_.jobs->unfinishedJobs();
    if (!jobs) return jobs.status();
    std::lock_guard<std::mutex> lock(mutex_);
    for (v1::Job& job : *jobs) {
        if (job.has_import()) {  // its upload was in tmp/, which open() emptied
            job.set_state(v1::JOB_STATE_FAILED);
            job.set_error("the server stopped before this import finished; upload " + job.import().name() + " again");
            *job.mutable_end_time() = nowTimestamp();
            VASTRAY_TRY(stores_.jobs->updateJob(job));
            continue;
        }
        // RUNNING here: the server stopped mid-render without handing the job back (a crash, a
        // kill, a lost machine). Each such attempt counts as failed; a job that crashes the
        // server every time fails after --max-attempts instead of crashing it at every start.
        if (job.state() == v1::JOB_STATE_RUNNING) {
            job.add_attempt_errors(
                "attempt " + std::to_string(job.attempts()) + " (started " + timestampText(job.start_time()) +
                "): the server stopped while rendering it (a crash, a kill or a lost machine)");
            if (uint32_t(job.attempt_errors_size()) >= options_.maxAttempts) {
                job.set_state(v1::JOB_STATE_FAILED);
                job.set_error(failedAttemptsMessage(job, options_.maxAttempts));
                *job.mutable_end_time() = nowTimestamp();
                VASTRAY_TRY(stores_.jobs->updateJob(job));
                ++metrics_.jobsFailed;
                continue;
            }
            job.set_state(v1::JOB_STATE_QUEUED);
            job.set_progress(0);
            VASTRAY_TRY(stores_.jobs->updateJob(job));
        }
        queue_.insert({job.request().priority(), nextOrder_++, job.id()});
        ++metrics_.jobsRequeued;
    }
    return Status::ok();
}

ServiceResult<SubmitOutcome> Service::submitJob(const v1::SubmitJobRequest& request) {
    auto normalized = normalizeSubmitRequest(request, options_.memoryBudgetBytes);
    if (!normalized) return normalized.status();
    // chunkid and cost exist only where chunks stream: refused at submit, not when the job runs.
    if (!workers_.empty() && workers_.front()->renderer->name() == "embree")
        for (const std::string& aov : normalized->aovs())
            if (auto flags = parseAovList(aov); flags && (*flags & kAovStreamingOnly))
                return ServiceStatus{StatusCode::InvalidArgument,
                                     "aovs: '" + aov + "' needs the vulkan backend; this server renders with embree"};
    std::lock_guard<std::mutex> lock(mutex_);
    if (!accepting_) return ServiceStatus{StatusCode::Unavailable, "the server is shutting down"};
    if (!normalized->request_id().empty()) {
        auto earlier = stores_.jobs->findJobByRequestId(normalized->request_id());
        if (!earlier) return internalError(earlier.message());
        if (*earlier) {
            if (!google::protobuf::util::MessageDifferencer::Equals((*earlier)->request(), *normalized))
                return ServiceStatus{StatusCode::FailedPrecondition,
                                     "request_id '" + normalized->request_id() +
                                         "' was used for a different request (job " + (*earlier)->id() + ")"};
            v1::Job job = **earlier;
            overlayLiveLocked(job);
            return SubmitOutcome{job, false};
        }
    }
    auto scene = stores_.scenes->getScene(normalized->scene_id());
    if (!scene) return internalError(scene.message());
    if (!*scene) return notFound("scene_id: no scene " + normalized->scene_id() + importNoteLocked(normalized->scene_id()));
    if (normalized->has_environment()) {
        auto environment = stores_.environments->getEnvironment(normalized->environment().id());
        if (!environment) return internalError(environment.message());
        if (!*environment) return notFound("environment.id: no environment " + normalized->environment().id());
    }
    if (queue_.size() >= options_.maxQueue) {
        ++metrics_.jobsRejectedFull;
        return ServiceStatus{StatusCode::ResourceExhausted,
                             "the queue is full (" + std::to_string(queue_.size()) +
                                 " jobs queued, --max-queue " + std::to_string(options_.maxQueue) + ")"};
    }
    v1::Job job;
    job.set_id(newJobId());
    job.set_state(v1::JOB_STATE_QUEUED);
    *job.mutable_request() = std::move(*normalized);
    *job.mutable_create_time() = nowTimestamp();
    job.set_result_content_type(resultContentType(job.request()));
    if (job.request().tiles_size() != 0 && !options_.sharedStorage)
        return invalidArgument("tiles", "needs a server started with --storage and --database (replicas)");
    auto inserted = options_.sharedStorage ? stores_.tasks->insertJobWithTasks(job, tileCount(job.request()))
                                           : stores_.jobs->insertJob(job);
    if (!inserted) return internalError(inserted.message());
    if (!options_.sharedStorage) queue_.insert({job.request().priority(), nextOrder_++, job.id()});
    ++metrics_.jobsSubmitted;
    options_.sharedStorage ? workAvailable_.notify_all() : workAvailable_.notify_one();
    notifyChangeLocked();
    return SubmitOutcome{inserted->job, true};
}

ServiceResult<v1::Job> Service::getJob(const v1::GetJobRequest& request) {
    if (auto s = checkJobId(request.id()); !s) return s;
    auto job = stores_.jobs->getJob(request.id());
    if (!job) return internalError(job.message());
    if (!*job) return notFound("no job " + request.id());
    std::lock_guard<std::mutex> lock(mutex_);
    overlayLiveLocked(**job);
    return **job;
}

ServiceResult<v1::ListJobsResponse> Service::listJobs(const v1::ListJobsRequest& request) {
    auto size = pageSize(request.page_size());
    if (!size) return size.status();
    auto before = parsePageToken(request.page_token());
    if (!before) return before.status();
    if (!v1::JobState_IsValid(request.state())) return invalidArgument("state", "not a job state");
    auto page = stores_.jobs->listJobs(request.state(), *before, *size);
    if (!page) return internalError(page.message());
    v1::ListJobsResponse response;
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto& job : page->jobs) {
        overlayLiveLocked(job);
        *response.add_jobs() = std::move(job);
    }
    if (page->more) response.set_next_page_token(std::to_string(page->last));
    return response;
}

ServiceResult<v1::Job> Service::cancelJob(const v1::CancelJobRequest& request) {
    if (auto s = checkJobId(request.id()); !s) return s;
    std::lock_guard<std::mutex> lock(mutex_);
    auto stored = stores_.jobs->getJob(request.id());
    if (!stored) return internalError(stored.message());
    if (!*stored) return notFound("no job " + request.id());
    v1::Job job = **stored;
    if (job.has_import())
        return ServiceStatus{StatusCode::FailedPrecondition,
                             "job " + job.id() + " is an import job; an import runs to its end"};
    if (isFinal(job.state()))
        return ServiceStatus{StatusCode::FailedPrecondition,
                             "job " + job.id() + " is " + jobStateName(job.state()) +
                                 "; only JOB_STATE_QUEUED or JOB_STATE_RUNNING jobs can be cancelled"};
    job.set_state(v1::JOB_STATE_CANCELLED);
    job.set_error(request.reason().empty() ? "cancelled" : "cancelled: " + request.reason());
    *job.mutable_end_time() = nowTimestamp();
    if (Status updated = stores_.jobs->updateJob(job); !updated) return internalError(updated.message());
    for (auto it = queue_.begin(); it != queue_.end(); ++it)
        if (it->id == job.id()) {
            queue_.erase(it);
            break;
        }
    if (Worker* worker = runningWorkerLocked(job.id())) {
        // Only this job's render stops; the other workers' jobs go on.
        worker->cancel = true;
        metrics_.durationCancelled.observe(secondsBetween(job.start_time(), job.end_time()));
    }
    ++metrics_.jobsCancelled;
    notifyChangeLocked();
    return job;
}

v1::JobEvent Service::eventLocked(const v1::Job& job, v1::JobEvent::Kind kind) const {
    v1::JobEvent event;
    event.set_kind(kind);
    event.set_job_id(job.id());
    event.set_state(job.state());
    event.set_percent(job.progress());
    event.set_error(job.error());
    event.set_chunk_loads(job.stats().chunk_loads());
    if (job.state() == v1::JOB_STATE_SUCCEEDED) {
        event.set_passes_done(job.stats().passes());
        event.set_passes_total(job.stats().passes());
        event.set_rays(job.stats().rays());
        event.set_device_bytes(job.stats().peak_device_bytes());
    }
    const Worker* worker = job.state() == v1::JOB_STATE_RUNNING && !options_.sharedStorage
                               ? runningWorkerLocked(job.id())
                               : nullptr;
    if (worker) {
        event.set_passes_done(worker->published.passesDone);
        event.set_passes_total(worker->published.passesTotal);
        event.set_chunk_loads(worker->published.chunkLoads);
        event.set_rays(worker->published.rays);
        event.set_device_bytes(worker->published.deviceBytes);
    }
    *event.mutable_time() = nowTimestamp();
    return event;
}

void Service::overlayLiveLocked(v1::Job& job) const {
    // Replicas: the stored progress is the job's (tiles done); a worker's is one tile's.
    if (job.state() != v1::JOB_STATE_RUNNING || options_.sharedStorage) return;
    if (const Worker* worker = runningWorkerLocked(job.id())) job.set_progress(worker->livePercent);
}

ServiceStatus Service::watchJob(const v1::WatchJobRequest& request,
                                const std::function<bool(const v1::JobEvent&)>& emit,
                                const std::function<bool()>& clientGone) {
    v1::GetJobRequest get;
    get.set_id(request.id());
    // `seen` is always taken before the job is read, never after: a change that lands between
    // the two leaves the counter past `seen`, so the wait below returns at once and reads the
    // job again. Taken after the read, the job's last change (its final state) could count as
    // seen while the snapshot still said RUNNING, and the watch would wait for a change that
    // never comes.
    uint64_t seen = 0;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        seen = changeCounter_;
    }
    auto job = getJob(get);
    if (!job) return job.status();
    if (watchSnapshotReadHook_) watchSnapshotReadHook_();
    v1::JobEvent last;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        last = eventLocked(*job, v1::JobEvent::KIND_SNAPSHOT);
    }
    if (!emit(last)) return {StatusCode::Cancelled, "the client went away"};
    while (!isFinal(last.state())) {
        {
            std::unique_lock<std::mutex> lock(mutex_);
            changed_.wait_for(lock, kWatchPoll, [&] { return changeCounter_ != seen || stopping_; });
            if (stopping_) return {StatusCode::Unavailable, "the server is shutting down"};
            // Replicas: other servers change the job; read it at every poll.
            if (changeCounter_ == seen && !options_.sharedStorage) {
                lock.unlock();
                if (clientGone && clientGone()) return {StatusCode::Cancelled, "the client went away"};
                continue;
            }
            seen = changeCounter_;
        }
        auto current = getJob(get);
        if (!current) return current.status();
        v1::JobEvent event;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            event = eventLocked(*current, v1::JobEvent::KIND_PROGRESS);
        }
        keepMonotone(last, event);
        if (event.state() != last.state())
            event.set_kind(v1::JobEvent::KIND_STATE_CHANGED);
        else if (event.percent() == last.percent() && event.passes_done() == last.passes_done() &&
                 event.passes_total() == last.passes_total() && event.chunk_loads() == last.chunk_loads() &&
                 event.rays() == last.rays() && event.device_bytes() == last.device_bytes())
            continue;
        if (!emit(event)) return {StatusCode::Cancelled, "the client went away"};
        last = event;
    }
    return {};
}

ServiceResult<ResultFile> Service::resultFile(const std::string& jobId) {
    v1::GetJobRequest get;
    get.set_id(jobId);
    auto job = getJob(get);
    if (!job) return job.status();
    if (job->has_import())
        return ServiceStatus{StatusCode::FailedPrecondition, "job " + jobId + " is an import job; it has no result (its scene is " +
                                                                 job->import().scene_id() + ")"};
    if (job->state() != v1::JOB_STATE_SUCCEEDED)
        return ServiceStatus{StatusCode::FailedPrecondition,
                             "job " + jobId + " is " + jobStateName(job->state()) +
                                 "; a result exists once it is JOB_STATE_SUCCEEDED"};
    auto path = objects_->localPath(resultKey(*job));
    if (!path) return internalError(path.message());
    std::error_code error;
    const uint64_t bytes = std::filesystem::file_size(*path, error);
    if (error) return internalError(path->string() + ": " + error.message());
    return ResultFile{*path, bytes, job->result_content_type()};
}

bool Service::ready() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return accepting_ && workersStopped_ == 0;
}

void Service::stopAccepting() {
    std::lock_guard<std::mutex> lock(mutex_);
    accepting_ = false;
    stopping_ = true;
    workAvailable_.notify_all();
    importAvailable_.notify_all();
    notifyChangeLocked();
}

bool Service::shutdown(std::chrono::milliseconds grace) {
    stopAccepting();
    // open() failed before the workers started
    if (workers_.empty() || !workers_.front()->thread.joinable()) return true;
    std::unique_lock<std::mutex> lock(mutex_);
    if (workerIdle_.wait_for(lock, grace, [&] { return allWorkersStoppedLocked(); })) return true;
    // Past the grace: ask every running job to stop; each stays RUNNING in the store and runs
    // again at the next start.
    shutdownCancel_ = true;
    for (auto& worker : workers_) worker->cancel = true;
    return workerIdle_.wait_for(lock, std::chrono::seconds(2), [&] { return allWorkersStoppedLocked(); });
}

std::vector<std::string> Service::jobsLeftRunning() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::string> left = leftRunning_;
    // A render that did not stop within shutdown()'s wait: its record still says RUNNING.
    for (const auto& worker : workers_)
        if (!worker->stopped && !worker->runningId.empty() &&
            std::find(left.begin(), left.end(), worker->runningId) == left.end())
            left.push_back(worker->runningId);
    return left;
}

std::optional<uint64_t> Service::countWaitingTiles() {
    auto count = stores_.tasks->countWaitingTiles();
    if (!count) {
        std::fprintf(stderr, "vastray serve: /metrics: counting the waiting tiles: %s\n", count.message().c_str());
        return std::nullopt;
    }
    return *count;
}

std::string Service::metricsText() {
    size_t queued = 0, running = 0;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        queued = queue_.size();
        for (const auto& worker : workers_) running += worker->runningId.empty() ? 0 : 1;
    }
    // Replicas' work waits in the task store; a single server's waits in its queue, a job a task.
    const std::optional<uint64_t> waiting = stores_.tasks ? waitingTiles_.read() : std::optional<uint64_t>(queued);
    uint64_t held = 0;
    uint64_t scenesOpen = 0;
    for (const auto& worker : workers_) {
        held += worker->renderer->deviceBytesHeld();
        scenesOpen += worker->renderer->deviceScenesOpen();
    }
    std::string text;
    auto add = [&text](const char* name, const char* type, const char* help, const std::string& value) {
        text += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " " + type + "\n" + name +
                " " + value + "\n";
    };
    add("vastray_jobs_queued", "gauge", "Jobs waiting to run.", std::to_string(queued));
    add("vastray_jobs_running", "gauge", "Jobs rendering now.", std::to_string(running));
    if (waiting)
        add("vastray_tasks_waiting", "gauge",
            "Tiles waiting for a worker over every job in the store (not leased, or their lease expired; "
            "replicas), or jobs in this server's queue (one server). Refreshed at most once a second.",
            std::to_string(*waiting));
    add("vastray_workers", "gauge",
        "Render workers (one per --gpu-device entry), each running one job at a time.",
        std::to_string(workers_.size()));
    add("vastray_jobs_submitted_total", "counter", "New jobs accepted.",
        std::to_string(metrics_.jobsSubmitted));
    add("vastray_jobs_rejected_total", "counter", "Jobs refused because the queue was full.",
        std::to_string(metrics_.jobsRejectedFull));
    add("vastray_jobs_requeued_total", "counter", "Unfinished jobs requeued at start.",
        std::to_string(metrics_.jobsRequeued));
    text +=
        "# HELP vastray_jobs_finished_total Jobs that reached a final state, by state.\n"
        "# TYPE vastray_jobs_finished_total counter\n";
    text +=
        "vastray_jobs_finished_total{state=\"SUCCEEDED\"} " + std::to_string(metrics_.jobsSucceeded) + "\n";
    text += "vastray_jobs_finished_total{state=\"FAILED\"} " + std::to_string(metrics_.jobsFailed) + "\n";
    text +=
        "vastray_jobs_finished_total{state=\"CANCELLED\"} " + std::to_string(metrics_.jobsCancelled) + "\n";
    add("vastray_scenes_uploaded_total", "counter", "New scenes stored.",
        std::to_string(metrics_.scenesUploaded));
    add("vastray_upload_bytes_total", "counter", "Bytes received in uploads (scenes and environment maps).",
        std::to_string(metrics_.uploadBytes));
    add("vastray_rays_total", "counter", "Rays traced by finished jobs.", std::to_string(metrics_.rays));
    add("vastray_chunk_loads_total", "counter", "Scene chunks loaded from storage.",
        std::to_string(metrics_.chunkLoads));
    add("vastray_render_seconds_total", "counter", "Time spent tracing and shading.",
        std::to_string(double(metrics_.renderMicroseconds) * 1e-6));
    text +=
        "# HELP vastray_device_kernel_seconds_total Device time of the wavefront kernels over finished jobs, by "
        "kernel (timestamp queries).\n"
        "# TYPE vastray_device_kernel_seconds_total counter\n";
    for (int k = 0; k < Metrics::kKernels; ++k)
        text += std::string("vastray_device_kernel_seconds_total{kernel=\"") + StreamingStats::kKernelNames[k] +
                "\"} " + std::to_string(double(metrics_.kernelMicroseconds[k]) * 1e-6) + "\n";
    add("vastray_device_memory_peak_bytes", "gauge",
        "Largest device memory a job's render held since the server started (0 before the first job "
        "and with the embree backend).",
        std::to_string(metrics_.peakDeviceBytes));
    add("vastray_device_memory_held_bytes", "gauge",
        "Device memory the open scenes hold now, all workers together (each pool is allocated when its "
        "scene opens); at most the budget times the workers.",
        std::to_string(held));
    add("vastray_device_scenes_open", "gauge",
        "Scenes open on the device between jobs, all workers together (each with its own pool; a "
        "scene is open once at most per worker).",
        std::to_string(scenesOpen));
    add("vastray_device_memory_budget_bytes", "gauge",
        "Device memory pool of each worker (--memory-budget): the most one job may use, and the most "
        "one worker's open scenes hold together.",
        std::to_string(options_.memoryBudgetBytes));
    size_t imports = 0;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        imports = importing_.size();
    }
    add("vastray_imports_pending", "gauge", "Import jobs queued or running (asynchronous uploads).",
        std::to_string(imports));
    add("vastray_ready", "gauge", "1 when the server accepts work.", ready() ? "1" : "0");
    return text + metrics_.histogramsText() + metrics_.requestsText() + buildInfoText() + processMetricsText();
}

}  // namespace vastray::server
