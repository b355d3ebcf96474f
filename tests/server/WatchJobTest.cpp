// A watch that begins while its job ends still ends with the job's final state: Service::watchJob
// in process, with the job finished at the one moment a lost wake-up could hide it (after the
// watch read the job for its snapshot, before it built the snapshot).
#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <fstream>
#include <iterator>
#include <mutex>
#include <thread>
#include <vector>

#include "TestTmp.h"
#include "vastray/server/Service.h"
#include "vastray/streamer/Generate.h"

namespace vastray::test {
namespace {

using namespace std::chrono_literals;

// Long enough for a 32x32 Embree render on a loaded two-core machine; a watch that lost the
// final state would wait for ever, so any bound tells the two apart.
constexpr auto kWatchBound = 20s;

// The Embree renderer, holding each render until open() is called.
class GatedRenderer final : public server::JobRenderer {
public:
    std::string name() const override { return inner_->name(); }
    Result<RenderImage> render(const server::JobRenderRequest& request,
                               const server::JobProgressCallback& progress, const std::atomic<bool>& cancel,
                               server::JobRenderStats* stats) override {
        std::unique_lock<std::mutex> lock(mutex_);
        entered_ = true;
        changed_.notify_all();
        changed_.wait(lock, [&] { return open_; });
        lock.unlock();
        return inner_->render(request, progress, cancel, stats);
    }
    void waitEntered() {
        std::unique_lock<std::mutex> lock(mutex_);
        changed_.wait(lock, [&] { return entered_; });
    }
    void open() {
        std::lock_guard<std::mutex> lock(mutex_);
        open_ = true;
        changed_.notify_all();
    }

private:
    std::unique_ptr<server::JobRenderer> inner_ = server::makeEmbreeJobRenderer(64ull << 20);
    std::mutex mutex_;
    std::condition_variable changed_;
    bool entered_ = false, open_ = false;
};

v1::JobState stateOf(server::Service& service, const std::string& id) {
    v1::GetJobRequest get;
    get.set_id(id);
    auto job = service.getJob(get);
    return job ? job->state() : v1::JOB_STATE_UNSPECIFIED;
}

// Polls (a test's wait, bounded) until the job is final and its worker has let it go: the last
// change the service announces for a job.
bool waitUntilFinishedAndIdle(server::Service& service, const std::string& id) {
    const auto deadline = std::chrono::steady_clock::now() + kWatchBound;
    while (std::chrono::steady_clock::now() < deadline) {
        if (stateOf(service, id) == v1::JOB_STATE_SUCCEEDED &&
            service.metricsText().find("\nvastray_jobs_running 0\n") != std::string::npos)
            return true;
        std::this_thread::sleep_for(5ms);
    }
    return false;
}

// The job SUCCEEDS after the watch has read it RUNNING and before the watch subscribes (its
// worker's last announcement included): the watch still sends SUCCEEDED and ends, well within
// the bound. Before the fix the watch took its change count after reading the job, counted the
// final change as seen, and waited for ever with the snapshot's RUNNING.
TEST(WatchJob, AJobThatEndsWhileTheWatchSubscribesEndsTheWatch) {
    const std::filesystem::path dir = testTmpDir("server") / "WatchJob";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::filesystem::path sphere = dir / "sphere.ply";
    ASSERT_TRUE(generateToPly({GeneratorKind::Sphere, 2000, 1}, sphere.string()).isOk());

    server::ServiceOptions options;
    options.dataDir = dir / "data";
    auto owned = std::make_unique<GatedRenderer>();
    GatedRenderer& renderer = *owned;
    auto opened = server::Service::open(options, std::move(owned));
    ASSERT_TRUE(opened.isOk()) << opened.message();
    server::Service& service = **opened;

    std::ifstream in(sphere, std::ios::binary);
    const std::string bytes{std::istreambuf_iterator<char>(in), {}};
    auto upload = service.beginUpload("sphere.ply", bytes.size());
    ASSERT_TRUE(upload) << upload.status().message();
    ASSERT_TRUE((*upload)->append(bytes.data(), bytes.size()));
    auto scene = (*upload)->finish();
    ASSERT_TRUE(scene) << scene.status().message();

    v1::SubmitJobRequest submit;
    submit.set_scene_id(scene->id());
    submit.set_width(32);
    submit.set_height(32);
    submit.set_spp(2);
    auto submitted = service.submitJob(submit);
    ASSERT_TRUE(submitted) << submitted.status().message();
    const std::string id = submitted->job.id();
    renderer.waitEntered();
    ASSERT_EQ(stateOf(service, id), v1::JOB_STATE_RUNNING);

    bool finished = false;
    service.setWatchSnapshotReadHookForTest([&] {
        renderer.open();
        finished = waitUntilFinishedAndIdle(service, id);
    });
    std::vector<v1::JobEvent> events;
    v1::WatchJobRequest watch;
    watch.set_id(id);
    const auto start = std::chrono::steady_clock::now();
    const server::ServiceStatus status = service.watchJob(
        watch,
        [&](const v1::JobEvent& event) {
            events.push_back(event);
            return true;
        },
        [&] { return std::chrono::steady_clock::now() - start > 2 * kWatchBound; });
    ASSERT_TRUE(finished) << "the job did not finish within the bound";
    EXPECT_TRUE(status.isOk()) << "the watch ended without the final state: " << status.message();
    ASSERT_GE(events.size(), 2u);
    EXPECT_EQ(events.front().kind(), v1::JobEvent::KIND_SNAPSHOT);
    EXPECT_EQ(events.front().state(), v1::JOB_STATE_RUNNING) << "the snapshot was read before the job ended";
    EXPECT_EQ(events.back().kind(), v1::JobEvent::KIND_STATE_CHANGED);
    EXPECT_EQ(events.back().state(), v1::JOB_STATE_SUCCEEDED);
    service.shutdown(5s);
}

}  // namespace
}  // namespace vastray::test
