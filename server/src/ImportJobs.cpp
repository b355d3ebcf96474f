// Import jobs: an asynchronous upload (UploadSceneRequest.async, HTTP ?async=true) stores its
// bytes and returns at once; a job resource (the same Job as renders, with `import` set instead
// of `request`) reports the import's state and error. Imports run one at a time on their own
// thread, in upload order, so they neither hold client connections nor wait behind renders.
// Their progress rises as they go: 10 % once the model is read, to 90 % as the package builder
// places triangles, 95 % once the package is written, 100 % when it is verified and stored.
// The upload's file waits in tmp/, which the next start empties: an import job that was not
// finished when the server stopped is FAILED at the next start (recoverJobs), never re-run.
#include <chrono>
#include <cstdio>
#include <mutex>

#include "JobRequest.h"
#include "vastray/server/Service.h"

namespace vastray::server {

namespace fs = std::filesystem;

ServiceResult<v1::Scene> Service::queueImport(const std::string& name, const fs::path& file,
                                              const std::string& digest, uint64_t bytes) {
    auto known = stores_.scenes->getScene(digest);
    if (!known) return internalError(known.message());
    if (*known) return **known;
    v1::Scene scene;
    scene.set_id(digest);
    scene.set_name(name);
    scene.set_upload_bytes(bytes);
    std::lock_guard<std::mutex> lock(mutex_);
    if (!accepting_) return ServiceStatus{StatusCode::Unavailable, "the server is shutting down"};
    if (auto it = importing_.find(digest); it != importing_.end()) {
        scene.set_import_job_id(it->second);  // the same content is being imported already
        return scene;
    }
    if (importQueue_.size() >= options_.maxQueue)
        return ServiceStatus{StatusCode::ResourceExhausted, "the import queue is full (" +
                                                                std::to_string(importQueue_.size()) +
                                                                " imports queued, --max-queue " +
                                                                std::to_string(options_.maxQueue) + ")"};
    v1::Job job;
    job.set_id(newJobId());
    job.set_state(v1::JOB_STATE_QUEUED);
    job.mutable_import()->set_name(name);
    job.mutable_import()->set_scene_id(digest);
    job.mutable_import()->set_upload_bytes(bytes);
    *job.mutable_create_time() = nowTimestamp();
    const fs::path kept = objects_->scratchDir() / (job.id() + ".upload");
    std::error_code error;
    fs::rename(file, kept, error);
    if (error) return internalError(kept.string() + ": " + error.message());
    if (auto inserted = stores_.jobs->insertJob(job); !inserted) {
        fs::remove(kept, error);
        return internalError(inserted.message());
    }
    importQueue_.emplace_back(job.id(), kept);
    importing_[digest] = job.id();
    importAvailable_.notify_one();
    notifyChangeLocked();
    scene.set_import_job_id(job.id());
    return scene;
}

// Queued imports left at shutdown stay QUEUED in the store; the next start fails them.
void Service::importLoop() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (true) {
        importAvailable_.wait(lock, [&] { return stopping_ || !importQueue_.empty(); });
        if (stopping_) break;
        const auto [jobId, file] = importQueue_.front();
        importQueue_.pop_front();
        lock.unlock();
        runImport(jobId, file);
        lock.lock();
    }
}

void Service::runImport(const std::string& jobId, const fs::path& file) {
    v1::Job job;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        auto stored = stores_.jobs->getJob(jobId);
        if (!stored || !*stored) {  // the store failed us: drop the upload, keep the record as it is
            std::error_code error;
            fs::remove(file, error);
            std::erase_if(importing_, [&](const auto& entry) { return entry.second == jobId; });
            return;
        }
        job = **stored;
        job.set_state(v1::JOB_STATE_RUNNING);
        job.set_attempts(1);
        *job.mutable_start_time() = nowTimestamp();
        (void)stores_.jobs->updateJob(job);  // a lost update leaves QUEUED: failed at the next start
        notifyChangeLocked();
    }
    const v1::ImportDetails details = job.import();
    // The job's progress as the import goes: stored and announced when it has risen by 5 points,
    // or by less after 0.2 s (the builder reports from its worker threads, often).
    std::mutex progressMutex;
    int reported = 0;
    auto lastWrite = std::chrono::steady_clock::now();
    const ImportProgress progress = [&](int percent) {
        std::lock_guard<std::mutex> progressLock(progressMutex);
        const auto now = std::chrono::steady_clock::now();
        if (percent <= reported || (percent < reported + 5 && now - lastWrite < std::chrono::milliseconds(200))) return;
        reported = percent, lastWrite = now;
        std::lock_guard<std::mutex> lock(mutex_);
        job.set_progress(percent);
        (void)stores_.jobs->updateJob(job);  // a lost update only loses a progress figure
        notifyChangeLocked();
    };
    // storeUpload consumes the file (moved into the package, or removed by the importer's caller).
    auto scene = storeUpload(details.name(), file, details.scene_id(), details.upload_bytes(), progress);
    std::error_code error;
    fs::remove(file, error);
    std::lock_guard<std::mutex> lock(mutex_);
    job.set_state(scene ? v1::JOB_STATE_SUCCEEDED : v1::JOB_STATE_FAILED);
    job.set_progress(scene ? 100 : 0);
    job.set_error(scene ? "" : scene.status().message());
    if (scene) *job.mutable_import()->mutable_warnings() = scene->import_warnings();
    *job.mutable_end_time() = nowTimestamp();
    if (Status updated = stores_.jobs->updateJob(job); !updated)
        std::fprintf(stderr, "vastray serve: import job %s: %s\n", jobId.c_str(), updated.message().c_str());
    importing_.erase(details.scene_id());
    notifyChangeLocked();
}

std::string Service::importNoteLocked(const std::string& sceneId) const {
    auto it = importing_.find(sceneId);
    return it == importing_.end() ? "" : " (job " + it->second + " is importing it)";
}

}  // namespace vastray::server
