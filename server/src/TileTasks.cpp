// Replicas (`serve --storage DIR --database URL`): every render job is split into tiles
// (SubmitJobRequest.tiles, one when absent), stored as task rows that the workers of every
// replica lease (TaskStore). While a worker renders a tile a heartbeat renews its lease; a
// lease that cannot be renewed stops the render (the task has been or will be taken over).
// Tiles are region renders written to the shared folder (scratch file, then an atomic
// rename); the replica that finishes the last tile leases the assemble task in the same
// transaction and joins the tiles, channel by channel as stored (as `vastray assemble`), into
// the result: it equals the whole-frame render bit for bit.
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <exception>
#include <mutex>
#include <new>
#include <thread>

#include "JobRequest.h"
#include "vastray/core/ImageFile.h"
#include "vastray/core/RenderMemory.h"
#include "vastray/server/Service.h"

namespace vastray::server {
namespace {

constexpr auto kLeasePoll = std::chrono::milliseconds(200);

std::string tileKey(const v1::Job& job, int32_t tile) {
    return "tiles/" + job.id() + "/" + std::to_string(tile) + "." + job.request().output_format();
}

// Renews a lease every third of its length on a thread of its own until stopped; when a
// renewal fails (the lease was lost, the job cancelled, or the database unreachable until the
// lease ran out) it sets `cancel`, which stops the render.
class Heartbeat {
public:
    Heartbeat(TaskStore& tasks, const TaskStore::Lease& lease, const std::string& owner, double seconds,
              std::atomic<bool>& cancel)
        : thread_([&, seconds] {
              const auto period = std::chrono::milliseconds(int64_t(seconds * 1000 / 3));
              std::unique_lock<std::mutex> lock(mutex_);
              while (!stop_) {
                  if (cv_.wait_for(lock, period, [&] { return stop_; })) break;
                  lock.unlock();
                  auto renewed = tasks.renewLease(lease, owner, seconds);
                  lock.lock();
                  if (!renewed || !*renewed) {
                      lost_ = true;
                      cancel = true;
                      break;
                  }
              }
          }) {}
    ~Heartbeat() { stop(); }

    void stop() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        cv_.notify_all();
        if (thread_.joinable()) thread_.join();
    }
    bool lost() {
        std::lock_guard<std::mutex> lock(mutex_);
        return lost_;
    }

private:
    std::mutex mutex_;
    std::condition_variable cv_;
    bool stop_ = false, lost_ = false;
    std::thread thread_;  // last: starts once the fields above exist
};

std::string taskName(int32_t tile) {
    return tile == TaskStore::kAssembleTile ? std::string("assembling") : "tile " + std::to_string(tile);
}

void copyInto(const StoredImage& tile, StoredImage& frame) {
    const uint64_t pixelBytes = frame.pixelBytes(), rowBytes = uint64_t(tile.width) * pixelBytes;
    for (uint32_t row = 0; row < tile.height; ++row)
        std::memcpy(frame.pixels.data() + ((uint64_t(tile.originY) + row) * frame.width + tile.originX) * pixelBytes,
                    tile.pixels.data() + row * rowBytes, rowBytes);
}

}  // namespace

void Service::replicaLoop(Worker& worker) {
    while (true) {
        {
            std::unique_lock<std::mutex> lock(mutex_);
            if (stopping_) break;
            if (options_.paused) {
                workAvailable_.wait_for(lock, kLeasePoll);
                continue;
            }
        }
        auto lease = stores_.tasks->leaseTask(replicaId_, options_.leaseSeconds, options_.maxAttempts);
        if (!lease || !*lease) {
            if (!lease) std::fprintf(stderr, "vastray serve: leasing a task: %s\n", lease.message().c_str());
            std::unique_lock<std::mutex> lock(mutex_);
            workAvailable_.wait_for(lock, kLeasePoll, [&] { return stopping_; });
            continue;
        }
        {
            std::lock_guard<std::mutex> lock(mutex_);
            worker.runningId = (*lease)->jobId;
            worker.live = worker.published = {};
            worker.livePercent = 0;
            worker.cancel = false;
            notifyChangeLocked();
        }
        runTask(worker, **lease);
        std::lock_guard<std::mutex> lock(mutex_);
        worker.runningId.clear();
        notifyChangeLocked();
    }
    std::lock_guard<std::mutex> lock(mutex_);
    worker.stopped = true;
    ++workersStopped_;
    workerIdle_.notify_all();
}

void Service::runTask(Worker& worker, const TaskStore::Lease& lease) {
    const std::string name = "job " + lease.jobId + " " + taskName(lease.tile);
    ServiceStatus outcome;
    bool lost = false;
    {
        Heartbeat heartbeat(*stores_.tasks, lease, replicaId_, options_.leaseSeconds, worker.cancel);
        try {
            outcome = lease.tile == TaskStore::kAssembleTile ? assembleResult(lease) : renderTile(worker, lease);
        } catch (const std::bad_alloc&) {
            outcome = {StatusCode::ResourceExhausted, "out of host memory"};
        } catch (const std::exception& e) {
            outcome = internalError(std::string("render failed: ") + e.what());
        }
        heartbeat.stop();
        lost = heartbeat.lost();
    }
    if (lost) {
        std::fprintf(stderr, "vastray serve: %s: lease lost (taken over, or the job ended); result dropped\n",
                     name.c_str());
        return;
    }
    if (outcome.code() == StatusCode::Cancelled) return;  // shutdown: the lease expires, another replica takes it
    if (!outcome.isOk()) {
        const std::string reason = taskName(lease.tile) + " attempt " + std::to_string(lease.attempt) + " (replica " +
                                   replicaId_ + "): " + outcome.message();
        // As finishJob: only an internal error may not recur; any other fails the job now.
        const bool permanent = outcome.code() != StatusCode::Internal;
        if (Status failed = stores_.tasks->failTask(lease, replicaId_, reason, options_.maxAttempts, permanent);
            !failed)
            std::fprintf(stderr, "vastray serve: %s: %s\n", name.c_str(), failed.message().c_str());
        std::lock_guard<std::mutex> lock(mutex_);
        notifyChangeLocked();
        return;
    }
    if (lease.tile == TaskStore::kAssembleTile) return;
    auto completion = stores_.tasks->completeTile(lease, replicaId_, options_.leaseSeconds);
    if (!completion) {
        std::fprintf(stderr, "vastray serve: %s: %s\n", name.c_str(), completion.message().c_str());
        return;
    }
    {
        std::lock_guard<std::mutex> lock(mutex_);
        notifyChangeLocked();
    }
    if (completion->assemble) runTask(worker, *completion->assemble);
}

ServiceStatus Service::renderTile(Worker& worker, const TaskStore::Lease& lease) {
    const v1::Job& job = lease.job;
    JobRenderStats stats;
    std::optional<RenderImage> image;
    if (ServiceStatus rendered = renderRequest(worker, job, tileBounds(job.request(), uint32_t(lease.tile)), stats, image);
        !rendered.isOk())
        return rendered;
    const std::filesystem::path scratch = objects_->scratchDir() / (job.id() + "-" + std::to_string(lease.tile) +
                                                                    "." + job.request().output_format());
    if (Status written = writeImageFile(scratch.string(), *image); !written) return internalError(written.message());
    if (Status stored = objects_->put(tileKey(job, lease.tile), scratch); !stored)
        return internalError(stored.message());
    return {};
}

ServiceStatus Service::assembleResult(const TaskStore::Lease& lease) {
    v1::Job job = lease.job;
    const uint32_t tiles = tileCount(job.request());
    StoredImage frame;
    for (uint32_t t = 0; t < tiles; ++t) {
        auto path = objects_->localPath(tileKey(job, int32_t(t)));
        if (!path) return internalError(path.message());
        auto tile = readStoredImage(path->string());
        if (!tile) return internalError(tile.message());
        const PixelBounds expected = tileBounds(job.request(), t);
        if (tile->originX != expected.x0 || tile->originY != expected.y0 || tile->width != expected.width() ||
            tile->height != expected.height())
            return internalError(path->string() + ": not the pixels of tile " + std::to_string(t));
        if (t == 0) {
            frame = *tile;
            frame.width = tile->frameWidth, frame.height = tile->frameHeight;
            frame.originX = frame.originY = 0;
            frame.pixels.assign(uint64_t(frame.width) * frame.height * frame.pixelBytes(), 0);
        } else if (tile->channels != frame.channels || tile->types != frame.types) {
            return internalError(path->string() + ": channels differ from tile 0's");
        }
        copyInto(*tile, frame);
    }
    const std::filesystem::path scratch = objects_->scratchDir() / (job.id() + "." + job.request().output_format());
    if (Status written = writeStoredImage(scratch.string(), frame); !written) return internalError(written.message());
    std::error_code error;
    job.set_result_bytes(std::filesystem::file_size(scratch, error));
    if (Status stored = objects_->put(resultKey(job), scratch); !stored) return internalError(stored.message());
    job.set_state(v1::JOB_STATE_SUCCEEDED);
    job.set_progress(100);
    job.clear_error();
    *job.mutable_end_time() = nowTimestamp();
    auto finished = stores_.tasks->completeJob(lease, replicaId_, job);
    if (!finished) return internalError(finished.message());
    if (!*finished) return {StatusCode::Cancelled, "lost the assemble lease"};
    std::printf("vastray serve: job %s: assembled %u tiles\n", job.id().c_str(), tiles);
    std::fflush(stdout);
    for (uint32_t t = 0; t < tiles; ++t) objects_->remove(tileKey(job, int32_t(t)));
    ++metrics_.jobsSucceeded;
    metrics_.durationSucceeded.observe(secondsBetween(job.start_time(), job.end_time()));
    return {};
}

}  // namespace vastray::server
