// The worker threads (one per renderer): each takes the next job from the one queue, renders
// it through its own JobRenderer and stores the image atomically (scratch file, then
// ObjectStore::put) before the job's record says SUCCEEDED. A crash at any point leaves either
// no result and an unfinished job (run again at the next start) or a whole result.

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>

#include "JobRequest.h"
#include "vastray/core/ImageFile.h"
#include "vastray/core/RenderMemory.h"
#include "vastray/server/Service.h"

namespace vastray::server {

void Service::workerLoop(Worker& worker) {
    std::unique_lock<std::mutex> lock(mutex_);
    while (true) {
        workAvailable_.wait(lock, [&] { return stopping_ || (!options_.paused && !queue_.empty()); });
        if (stopping_) break;
        const QueueEntry next = *queue_.begin();
        queue_.erase(queue_.begin());
        worker.runningId = next.id;
        worker.live = worker.published = {};
        worker.livePercent = 0;
        worker.cancel = false;
        lock.unlock();
        runJob(worker, next.id);
        lock.lock();
        worker.runningId.clear();
        notifyChangeLocked();
    }
    worker.stopped = true;
    ++workersStopped_;
    workerIdle_.notify_all();
}

Service::Worker* Service::runningWorkerLocked(const std::string& id) const {
    if (id.empty()) return nullptr;
    for (const auto& worker : workers_)
        if (worker->runningId == id) return worker.get();
    return nullptr;
}

namespace {

// Test-only (docs/SERVICE.md, "Attempts"): with VASTRAY_TEST_CRASH_ON_JOB=REQUEST_ID in its
// environment the server aborts (SIGABRT, a real crash of the process) when a worker starts
// the job of that request_id, after the attempt is stored: how the tests make a job that
// crashes its server every time. Unset, it costs one getenv per job.
void crashIfTestAsks(const v1::Job& job) {
    const char* crashOn = std::getenv("VASTRAY_TEST_CRASH_ON_JOB");
    if (!crashOn || !*crashOn || job.request().request_id() != crashOn) return;
    std::fprintf(stderr, "vastray serve: VASTRAY_TEST_CRASH_ON_JOB: aborting on job %s\n", job.id().c_str());
    std::abort();
}

}  // namespace

void Service::runJob(Worker& worker, const std::string& id) {
    v1::Job job;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        auto stored = stores_.jobs->getJob(id);
        // A job cancelled while queued leaves the queue at once; this covers a lost race.
        if (!stored || !*stored || (*stored)->state() != v1::JOB_STATE_QUEUED) return;
        job = **stored;
        job.set_state(v1::JOB_STATE_RUNNING);
        job.set_attempts(job.attempts() + 1);
        job.set_progress(0);
        job.clear_error();
        *job.mutable_start_time() = nowTimestamp();
        // Which worker runs it is known (and stored) from the start: a RUNNING job says so.
        job.mutable_stats()->set_worker(worker.index);
        job.mutable_stats()->set_device(worker.device);
        metrics_.queueWait.observe(secondsBetween(job.create_time(), job.start_time()));
        if (Status updated = stores_.jobs->updateJob(job); !updated) {
            job.set_state(v1::JOB_STATE_FAILED);
            job.set_error(updated.message());
        }
        notifyChangeLocked();
    }
    if (job.state() == v1::JOB_STATE_FAILED) return finishJob(job, internalError(job.error()));
    crashIfTestAsks(job);
    finishJob(job, renderAndStoreGuarded(worker, job));
}

// An allocation failure anywhere in a job fails that job; the server and its other jobs go on.
ServiceStatus Service::renderAndStoreGuarded(Worker& worker, v1::Job& job) {
    try {
        return renderAndStore(worker, job);
    } catch (const std::bad_alloc&) {
        return {StatusCode::ResourceExhausted, "out of host memory while rendering"};
    } catch (const std::exception& e) {
        return internalError(std::string("render failed: ") + e.what());
    }
}

ServiceStatus Service::renderRequest(Worker& worker, const v1::Job& job, std::optional<PixelBounds> region,
                                     JobRenderStats& stats, std::optional<RenderImage>& image) {
    auto options = renderOptionsOf(job.request());
    if (!options) return invalidArgument("request", options.message());
    options->region = region;
    if (Status memory = checkRenderHostMemory(*options, job.request().output_format() == "exr"); !memory)
        return {StatusCode::ResourceExhausted, memory.message()};
    auto scenePath = objects_->localPath(sceneKey(job.request().scene_id()));
    if (!scenePath) return notFound("scene " + job.request().scene_id() + " is no longer stored");
    std::string environmentName;
    auto environment = jobEnvironmentMap(job.request(), environmentName);
    if (!environment) return environment.status();
    options->environment.map = std::move(*environment);
    JobRenderRequest request{scenePath->string(), *options, job.request().memory_budget_bytes(),
                             job.request().scene_camera(), !job.request().no_lights(), environmentName};
    auto rendered = worker.renderer->render(
        request, [this, &worker](const JobRenderProgress& p) { onProgress(worker, p); }, worker.cancel, &stats);
    metrics_.chunkLoads += stats.chunkLoads;
    metrics_.notePeakDeviceBytes(stats.peakDeviceBytes);
    if (worker.cancel) return {StatusCode::Cancelled, "cancelled"};
    // A request its budget cannot hold would be refused again: RESOURCE_EXHAUSTED fails the job
    // at once (finishJob runs only internal errors again).
    if (!rendered)
        return {stats.overBudget ? StatusCode::ResourceExhausted : StatusCode::Internal, rendered.message()};
    metrics_.rays += stats.render.rays;
    metrics_.renderMicroseconds += uint64_t(stats.render.renderSeconds * 1e6);
    static_assert(Metrics::kKernels == StreamingStats::kKernels);
    for (int k = 0; k < Metrics::kKernels; ++k) metrics_.kernelMicroseconds[k] += uint64_t(stats.kernelSeconds[k] * 1e6);
    image = std::move(rendered).value();
    return {};
}

ServiceStatus Service::renderAndStore(Worker& worker, v1::Job& job) {
    JobRenderStats stats;
    std::optional<RenderImage> image;
    const ServiceStatus rendered = renderRequest(worker, job, std::nullopt, stats, image);
    v1::JobStats* out = job.mutable_stats();
    out->set_backend(worker.renderer->name());
    out->set_render_seconds(stats.render.renderSeconds);
    out->set_rays(stats.render.rays);
    out->set_triangles(stats.render.triangles);
    out->set_chunk_loads(stats.chunkLoads);
    out->set_passes(stats.passes);
    out->set_peak_device_bytes(stats.peakDeviceBytes);
    out->set_memory_budget_bytes(job.request().memory_budget_bytes());
    if (!rendered.isOk()) return rendered;
    // The scratch name keeps the extension: the image writer picks the format by it.
    const std::filesystem::path scratch =
        objects_->scratchDir() / (job.id() + "." + job.request().output_format());
    if (Status written = writeImageFile(scratch.string(), *image); !written)
        return internalError(written.message());
    std::error_code error;
    job.set_result_bytes(std::filesystem::file_size(scratch, error));
    if (Status stored = objects_->put(resultKey(job), scratch); !stored)
        return internalError(stored.message());
    return {};
}

void Service::finishJob(v1::Job job, const ServiceStatus& outcome) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto stored = stores_.jobs->getJob(job.id());
    const bool cancelled = stored && *stored && (*stored)->state() == v1::JOB_STATE_CANCELLED;
    if (cancelled || (shutdownCancel_ && outcome.code() == StatusCode::Cancelled)) {
        // Cancelled by a client (already recorded) or stopped by shutdown: no result may
        // remain. A job stopped by shutdown is handed back QUEUED (not a failed attempt) and
        // runs again at the next start; should that update fail it stays RUNNING, which the
        // next start counts as a failed attempt.
        objects_->remove(resultKey(job));
        if (cancelled) return;
        leftRunning_.push_back(job.id());
        job.set_state(v1::JOB_STATE_QUEUED);
        job.set_progress(0);
        if (Status updated = stores_.jobs->updateJob(job); !updated)
            std::fprintf(stderr, "vastray serve: job %s: %s\n", job.id().c_str(), updated.message().c_str());
        return;
    }
    if (!outcome.isOk()) {
        job.add_attempt_errors("attempt " + std::to_string(job.attempts()) + " (started " +
                               timestampText(job.start_time()) + "): " + outcome.message());
        // An internal error (a lost device, a failed write) may not recur: the job runs again
        // until --max-attempts attempts failed. Any other error would recur: FAILED at once.
        if (outcome.code() == StatusCode::Internal &&
            uint32_t(job.attempt_errors_size()) < options_.maxAttempts) {
            job.set_state(v1::JOB_STATE_QUEUED);
            job.set_progress(0);
            if (Status updated = stores_.jobs->updateJob(job); !updated) {
                std::fprintf(stderr, "vastray serve: job %s: %s\n", job.id().c_str(),
                             updated.message().c_str());
                return;
            }
            // Stopping: it stays QUEUED in the store for the next start.
            if (!stopping_) queue_.insert({job.request().priority(), nextOrder_++, job.id()});
            ++metrics_.jobsRequeued;
            workAvailable_.notify_one();
            notifyChangeLocked();
            return;
        }
    }
    job.set_state(outcome.isOk() ? v1::JOB_STATE_SUCCEEDED : v1::JOB_STATE_FAILED);
    job.set_error(job.attempt_errors_size() > 1 ? failedAttemptsMessage(job, options_.maxAttempts)
                                                : outcome.message());
    if (outcome.isOk()) job.set_progress(100);
    *job.mutable_end_time() = nowTimestamp();
    if (Status updated = stores_.jobs->updateJob(job); !updated) {
        // The record still says RUNNING: the job runs again at the next start.
        std::fprintf(stderr, "vastray serve: job %s: %s\n", job.id().c_str(), updated.message().c_str());
        return;
    }
    ++(outcome.isOk() ? metrics_.jobsSucceeded : metrics_.jobsFailed);
    (outcome.isOk() ? metrics_.durationSucceeded : metrics_.durationFailed)
        .observe(secondsBetween(job.start_time(), job.end_time()));
    notifyChangeLocked();
}

// From the renderer's threads. Each figure only goes up (a report from a thread that fell
// behind is merged, not taken whole). A change is published when the percent moves, when the
// last pass ends, or when chunk loads moved and kLoadPublishInterval has passed since the last
// publication (a cold render loads thousands of chunks; watchers need not wake for each).
void Service::onProgress(Worker& worker, const JobRenderProgress& progress) {
    std::lock_guard<std::mutex> lock(mutex_);
    JobRenderProgress& live = worker.live;
    JobRenderProgress& published = worker.published;
    live.passesTotal = std::max(live.passesTotal, progress.passesTotal);
    live.passesDone = std::min(std::max(live.passesDone, progress.passesDone), live.passesTotal);
    live.chunkLoads = std::max(live.chunkLoads, progress.chunkLoads);
    live.rays = std::max(live.rays, progress.rays);
    live.deviceBytes = std::max(live.deviceBytes, progress.deviceBytes);
    const int percent = live.passesTotal ? int(100 * live.passesDone / live.passesTotal) : 0;
    const auto now = std::chrono::steady_clock::now();
    const bool lastPass = live.passesTotal > 0 && live.passesDone == live.passesTotal;
    const bool passesMoved =
        live.passesDone != published.passesDone || live.passesTotal != published.passesTotal;
    // Rays move with passes; device bytes are known from the first report on.
    const bool loadsMoved = live.chunkLoads != published.chunkLoads || live.rays != published.rays ||
                            live.deviceBytes != published.deviceBytes;
    if (percent == worker.livePercent && !(lastPass && (passesMoved || loadsMoved)) &&
        !(loadsMoved && now - worker.publishedAt >= kLoadPublishInterval))
        return;
    worker.livePercent = percent;
    published = live;
    worker.publishedAt = now;
    notifyChangeLocked();
}

}  // namespace vastray::server
