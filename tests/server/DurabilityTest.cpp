// Jobs survive `kill -9`: queued jobs run after a restart, an interrupted render runs again,
// each job finishes exactly once with the image `vastray render` makes of the same job.
#include <google/protobuf/util/time_util.h>

#include "ServerTestSupport.h"

namespace vastray::test {
namespace {

using google::protobuf::util::TimeUtil;

google::protobuf::Timestamp timeOf(const json& job, const char* field) {
    google::protobuf::Timestamp t;
    EXPECT_TRUE(TimeUtil::FromString(job.value(field, ""), &t)) << job.dump();
    return t;
}

TEST_F(ServerTest, QueuedJobsRunAfterKillAndRestartInPriorityOrder) {
    startServer({"--paused"});
    const std::string sceneId = uploadSphere()["id"];
    std::vector<std::string> ids;
    for (int seed : {1, 2, 3}) {
        json body = smallJob(sceneId);
        body["seed"] = seed;
        if (seed == 3) body["priority"] = 90;
        auto res = submit(body);
        ASSERT_EQ(res->status, 202) << res->body;
        ids.push_back(json::parse(res->body)["id"]);
    }
    server_.kill(SIGKILL);

    startServer();
    std::vector<json> done;
    for (const std::string& id : ids) done.push_back(waitForState(id, "JOB_STATE_SUCCEEDED"));
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(done[i]["attempts"], 1) << done[i].dump();
        EXPECT_EQ(result(ids[i]),
                  cliRender(sceneId, "--resolution 32x32 --spp 2 --seed " + std::to_string(i + 1)))
            << "job " << i;
    }
    EXPECT_LE(timeOf(done[2], "start_time"), timeOf(done[0], "start_time")) << "priority 90 runs before 50";
    EXPECT_LE(timeOf(done[0], "start_time"), timeOf(done[1], "start_time"))
        << "equal priorities run in order";
    auto list = http().Get("/v1/jobs");
    EXPECT_EQ(json::parse(list->body)["jobs"].size(), 3u) << "no job lost or duplicated";
}

TEST_F(ServerTest, RunningJobIsRenderedAgainAfterKill) {
    startServer();
    const std::string sceneId = uploadSphere()["id"];
    auto res = submit(slowJob(sceneId));
    ASSERT_EQ(res->status, 202);
    const std::string id = json::parse(res->body)["id"];
    waitForState(id, "JOB_STATE_RUNNING");
    server_.kill(SIGKILL);
    EXPECT_TRUE(std::filesystem::is_empty(dataDir() / "results")) << "no result of an interrupted render";

    startServer();
    const json job = waitForState(id, "JOB_STATE_SUCCEEDED");
    EXPECT_EQ(job["attempts"], 2) << "the interrupted render ran again";
    EXPECT_EQ(result(id), cliRender(sceneId, kSlowJobFlags));
    EXPECT_TRUE(std::filesystem::is_empty(dataDir() / "tmp"));
}

// The value of an unlabelled sample NAME in Prometheus text, after checking its HELP and
// TYPE lines; -1 when absent.
double metricValue(const std::string& text, const std::string& name, const std::string& type) {
    EXPECT_NE(text.find("# HELP " + name + " "), std::string::npos) << name;
    EXPECT_NE(text.find("# TYPE " + name + " " + type + "\n"), std::string::npos) << name;
    const size_t at = text.find("\n" + name + " ");
    return at == std::string::npos ? -1 : std::stod(text.substr(at + name.size() + 2));
}

// Also the device memory figures (vulkan backend, lavapipe here): every job reports its peak
// and its budget (peak within budget), and /metrics the service's peak and budget.
TEST_F(ServerTest, SecondJobOnAResidentSceneLoadsNoChunks) {
    const uint64_t budget = 64ull << 20;
    startServer({"--backend", "vulkan", "--memory-budget", "64MiB"});
    auto before = http().Get("/metrics");
    ASSERT_TRUE(before);
    EXPECT_EQ(metricValue(before->body, "vastray_device_memory_peak_bytes", "gauge"), 0) << "no job ran yet";
    EXPECT_EQ(metricValue(before->body, "vastray_device_memory_held_bytes", "gauge"), 0) << "no scene open yet";
    const std::string sceneId = uploadSphere()["id"];
    auto first = submit(smallJob(sceneId));
    const json a = waitForState(json::parse(first->body)["id"], "JOB_STATE_SUCCEEDED");
    auto second = submit(smallJob(sceneId));
    const json b = waitForState(json::parse(second->body)["id"], "JOB_STATE_SUCCEEDED");
    EXPECT_GT(std::stoull(a["stats"]["chunk_loads"].get<std::string>()), 0u) << a.dump();
    EXPECT_EQ(b["stats"]["chunk_loads"], "0") << "the host cache kept the decoded scene: " << b.dump();

    uint64_t peak = 0;
    for (const json& job : {a, b}) {
        const json& stats = job["stats"];
        ASSERT_TRUE(stats.contains("peak_device_bytes") && stats.contains("memory_budget_bytes")) << job.dump();
        const uint64_t jobPeak = std::stoull(stats["peak_device_bytes"].get<std::string>());
        EXPECT_EQ(std::stoull(stats["memory_budget_bytes"].get<std::string>()), budget) << job.dump();
        EXPECT_GT(jobPeak, 0u) << job.dump();
        EXPECT_LE(jobPeak, budget) << job.dump();
        peak = std::max(peak, jobPeak);
    }
    // The second job renders in the pool the first one opened: the same device memory.
    EXPECT_EQ(a["stats"]["peak_device_bytes"], b["stats"]["peak_device_bytes"]);

    auto metrics = http().Get("/metrics");
    ASSERT_TRUE(metrics);
    EXPECT_EQ(metricValue(metrics->body, "vastray_device_memory_peak_bytes", "gauge"), double(peak))
        << metrics->body;
    EXPECT_EQ(metricValue(metrics->body, "vastray_device_memory_budget_bytes", "gauge"), double(budget))
        << metrics->body;
    // Device time of the walk kernel, summed over the two jobs (lavapipe has timestamps).
    const size_t walk = metrics->body.find("\nvastray_device_kernel_seconds_total{kernel=\"walk\"} ");
    ASSERT_NE(walk, std::string::npos) << metrics->body;
    EXPECT_GT(std::stod(metrics->body.substr(walk + 52)), 0.0) << metrics->body;
    // The scene stays open after its jobs: its pool is still held (one scene: the jobs' peak).
    EXPECT_EQ(metricValue(metrics->body, "vastray_device_memory_held_bytes", "gauge"), double(peak))
        << metrics->body;

    // The stats are stored with the job: a restart reports the same figures.
    server_.kill(SIGTERM);
    startServer({"--backend", "vulkan", "--memory-budget", "64MiB"});
    const json stored = getJob(a["id"]);
    EXPECT_EQ(stored["stats"], a["stats"]) << stored.dump();
}

// Jobs alternating between two scenes: with a pool that holds both, each stays open and its
// second job loads nothing; with a pool that holds one, the least recently used scene is
// closed and its next job loads again.
TEST_F(ServerTest, ScenesShareThePoolAndStayOpenWhileTheyFit) {
    const std::filesystem::path terrain = dataDir().parent_path() / "terrain.ply";
    ASSERT_TRUE(generateToPly({GeneratorKind::Terrain, 3000, 2}, terrain.string()).isOk());
    auto loads = [&](const std::string& sceneId) {
        auto res = submit(smallJob(sceneId));
        EXPECT_EQ(res->status, 202) << res->body;
        const json job = waitForState(json::parse(res->body)["id"], "JOB_STATE_SUCCEEDED");
        return std::stoull(job["stats"]["chunk_loads"].get<std::string>());
    };
    for (const char* pool : {"512MiB", "64MiB"}) {
        SCOPED_TRACE(std::string("--memory-budget ") + pool);
        std::filesystem::remove_all(dataDir());
        startServer({"--backend", "vulkan", "--memory-budget", pool});
        const std::string a = uploadSphere()["id"];
        auto put = http().Put("/v1/scenes?name=terrain.ply", readBytes(terrain), "application/octet-stream");
        ASSERT_TRUE(put && put->status == 200);
        const std::string b = json::parse(put->body)["id"];
        EXPECT_GT(loads(a), 0u);
        EXPECT_GT(loads(b), 0u);
        // Each scene's pool takes about 42 MiB at a 64 MiB budget (the ray batch grows into
        // what the slots leave), so only one fits there; at 512 MiB both (about 84 MiB each).
        if (std::string(pool) == "512MiB") {
            EXPECT_EQ(loads(a), 0u) << "scene a should still be open";
            EXPECT_EQ(loads(b), 0u) << "scene b should still be open";
        } else {
            EXPECT_GT(loads(a), 0u) << "scene a should have been closed to make room for b";
        }
        server_.kill(SIGTERM);
    }
}

// SIGTERM: a running job either finishes within the grace or stays RUNNING and runs again at
// the next start; either way it finishes exactly once.
TEST_F(ServerTest, SigtermFinishesOrHandsOverTheRunningJob) {
    for (const char* grace : {"30", "0"}) {
        SCOPED_TRACE(std::string("--shutdown-grace ") + grace);
        startServer({"--shutdown-grace", grace});
        auto res = submit(slowJob(uploadSphere()["id"]));
        ASSERT_EQ(res->status, 202);
        const std::string id = json::parse(res->body)["id"];
        waitForState(id, "JOB_STATE_RUNNING");
        const int status = server_.kill(SIGTERM);
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << server_.log();
        const bool handedOver = std::string(grace) == "0";
        EXPECT_EQ(server_.log().find("runs again at the next start") != std::string::npos, handedOver)
            << server_.log();
        startServer();
        const json job = waitForState(id, "JOB_STATE_SUCCEEDED");
        EXPECT_EQ(job["attempts"], handedOver ? 2 : 1) << job.dump();
        server_.kill(SIGTERM);
    }
}

TEST_F(ServerTest, CancellingARunningJobDiscardsItsImage) {
    startServer();
    const std::string sceneId = uploadSphere()["id"];
    auto res = submit(slowJob(sceneId));
    ASSERT_EQ(res->status, 202);
    const std::string id = json::parse(res->body)["id"];
    waitForState(id, "JOB_STATE_RUNNING");
    res = http().Post(("/v1/jobs/" + id + ":cancel").c_str(), R"({"reason": "changed my mind"})",
                      "application/json");
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(json::parse(res->body)["state"], "JOB_STATE_CANCELLED") << "cancelled at once";
    // The next job runs once the cancelled render is out of the way; the cancelled job stays
    // CANCELLED and has no result.
    auto next = submit(smallJob(sceneId));
    waitForState(json::parse(next->body)["id"], "JOB_STATE_SUCCEEDED");
    EXPECT_EQ(getJob(id)["state"], "JOB_STATE_CANCELLED");
    EXPECT_EQ(getJob(id)["error"], "cancelled: changed my mind");
    EXPECT_EQ(http().Get(("/v1/jobs/" + id + "/result").c_str())->status, 409);
    EXPECT_FALSE(std::filesystem::exists(dataDir() / "results" / (id + ".png")));
}

TEST_F(ServerTest, UploadsOverTheLimitAreRefused) {
    startServer({"--max-upload", "16KiB"});
    auto res = http().Put("/v1/scenes?name=sphere.ply", readBytes(spherePath_), "application/octet-stream");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 413) << res->body;
    EXPECT_NE(res->body.find("RESOURCE_EXHAUSTED"), std::string::npos) << res->body;
    EXPECT_TRUE(std::filesystem::is_empty(dataDir() / "tmp")) << "the partial upload is removed";
    EXPECT_TRUE(std::filesystem::is_empty(dataDir() / "scenes"));
}

}  // namespace
}  // namespace vastray::test
