// Several workers per server: `serve --gpu-device 0,0` runs two workers on device 0 (lavapipe
// here), each with its own pool, taking jobs from the one queue at the same time. Their images
// equal those of a one-worker server bit for bit; cancelling, SIGTERM and progress events
// work per job as they do with one worker; a bad --gpu-device list stops the start.
#include <google/protobuf/util/time_util.h>

#include <set>
#include <thread>

#include "ServerTestSupport.h"

namespace vastray::test {
namespace {

using google::protobuf::util::TimeUtil;

const std::vector<std::string> kTwoWorkers = {"--backend", "vulkan", "--gpu-device", "0,0"};

// slowJob (ServerTestSupport.h) with a seed of its own: two of them overlap on two workers.
json seededSlowJob(const std::string& sceneId, int seed) {
    json body = slowJob(sceneId);
    body["seed"] = seed;
    return body;
}

uint64_t u64(const json& value) {
    return value.is_string() ? std::stoull(value.get<std::string>()) : value.get<uint64_t>();
}

google::protobuf::Timestamp timeOf(const json& job, const char* field) {
    google::protobuf::Timestamp t;
    EXPECT_TRUE(TimeUtil::FromString(job.value(field, ""), &t)) << job.dump();
    return t;
}

// Events of a job over a client of its own (the watches run on two threads at once).
std::vector<json> watchEventsOn(int httpPort, const std::string& jobId) {
    httplib::Client client("127.0.0.1", httpPort);
    client.set_read_timeout(120, 0);
    return watchEvents(std::move(client), jobId);
}

class WorkersTest : public ServerTest {
protected:
    std::string submitId(const json& body) {
        auto res = submit(body);
        EXPECT_TRUE(res && res->status == 202) << (res ? res->body : "no response");
        return res ? json::parse(res->body, nullptr, false).value("id", "") : "";
    }

    // Polls GET /v1/jobs?state=RUNNING (one snapshot of the store and the workers) until it
    // lists both jobs; false when 60 s pass or either job leaves QUEUED/RUNNING first.
    bool waitUntilBothRunning(const std::string& a, const std::string& b) {
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
        while (std::chrono::steady_clock::now() < deadline) {
            auto res = http().Get("/v1/jobs?state=JOB_STATE_RUNNING");
            if (!res || res->status != 200) return false;
            std::set<std::string> running;
            for (const json& job : json::parse(res->body).value("jobs", json::array()))
                running.insert(job["id"].get<std::string>());
            if (running.count(a) && running.count(b)) return true;
            for (const std::string& id : {a, b}) {
                const std::string state = getJob(id).value("state", "");
                if (state != "JOB_STATE_QUEUED" && state != "JOB_STATE_RUNNING") {
                    ADD_FAILURE() << "job " << id << " reached " << state << " before both ran at once";
                    return false;
                }
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return false;
    }
};

TEST_F(WorkersTest, TwoWorkersRenderTwoJobsAtOnceAsOneWorkerDoes) {
    startServer(kTwoWorkers);
    EXPECT_NE(server_.log().find("backend vulkan, 2 workers\n"), std::string::npos) << server_.log();
    EXPECT_NE(server_.log().find("worker 1 on Vulkan device [0] "), std::string::npos) << server_.log();
    const std::string sceneId = uploadSphere()["id"];
    const std::string a = submitId(seededSlowJob(sceneId, 1)), b = submitId(seededSlowJob(sceneId, 2));
    // Both jobs watched from the start: each stream's progress is its own job's.
    std::vector<json> eventsA, eventsB;
    std::thread watchA([&] { eventsA = watchEventsOn(server_.httpPort(), a); });
    std::thread watchB([&] { eventsB = watchEventsOn(server_.httpPort(), b); });
    const bool together = waitUntilBothRunning(a, b);
    const json doneA = waitForState(a, "JOB_STATE_SUCCEEDED"), doneB = waitForState(b, "JOB_STATE_SUCCEEDED");
    watchA.join();
    watchB.join();
    EXPECT_TRUE(together) << "both jobs RUNNING at once";
    // The stored times agree: each started before the other ended.
    EXPECT_LT(timeOf(doneA, "start_time"), timeOf(doneB, "end_time"));
    EXPECT_LT(timeOf(doneB, "start_time"), timeOf(doneA, "end_time"));
    EXPECT_EQ(std::set<int>({doneA["stats"]["worker"].get<int>(), doneB["stats"]["worker"].get<int>()}),
              std::set<int>({0, 1}))
        << "one job on each worker: " << doneA.dump() << doneB.dump();
    for (const json& job : {doneA, doneB})
        EXPECT_EQ(job["stats"]["device"].get<std::string>().rfind("Vulkan device [0] ", 0), 0u) << job.dump();
    for (const auto& [events, job] : {std::pair{&eventsA, &doneA}, std::pair{&eventsB, &doneB}}) {
        ASSERT_FALSE(events->empty());
        std::string dump;
        uint64_t passesDone = 0;
        bool sawProgress = false;
        for (const json& e : *events) {
            dump += e.dump() + "\n";
            EXPECT_GE(u64(e["passes_done"]), passesDone) << "progress never goes back: " << e.dump();
            passesDone = u64(e["passes_done"]);
            sawProgress |= e["state"] == "JOB_STATE_RUNNING" && passesDone > 0;
        }
        EXPECT_TRUE(sawProgress) << "passes reported while the job ran:\n" << dump;
        EXPECT_EQ(events->back()["state"], "JOB_STATE_SUCCEEDED") << dump;
        EXPECT_EQ(events->back()["percent"], 100) << dump;
        // The stream carries its own job's figures, not the other worker's.
        EXPECT_EQ(u64(events->back()["passes_done"]), u64((*job)["stats"]["passes"])) << dump;
        EXPECT_EQ(u64(events->back()["rays"]), u64((*job)["stats"]["rays"])) << dump;
    }
    const std::string imageA = result(a), imageB = result(b);
    EXPECT_NE(imageA, imageB) << "different seeds";
    server_.kill(SIGTERM);

    // The same jobs on a one-worker server (the default --gpu-device): the same bytes.
    startServer({"--backend", "vulkan"});
    const std::string a1 = submitId(seededSlowJob(sceneId, 1)), b1 = submitId(seededSlowJob(sceneId, 2));
    EXPECT_EQ(waitForState(a1, "JOB_STATE_SUCCEEDED")["stats"]["worker"], 0);
    waitForState(b1, "JOB_STATE_SUCCEEDED");
    EXPECT_EQ(result(a1), imageA);
    EXPECT_EQ(result(b1), imageB);
}

TEST_F(WorkersTest, CancellingOneOfTwoRunningJobsLeavesTheOther) {
    startServer(kTwoWorkers);
    const std::string sceneId = uploadSphere()["id"];
    const std::string a = submitId(seededSlowJob(sceneId, 1)), b = submitId(seededSlowJob(sceneId, 2));
    ASSERT_TRUE(waitUntilBothRunning(a, b));
    auto res = http().Post(("/v1/jobs/" + a + ":cancel").c_str(), "{}", "application/json");
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(json::parse(res->body)["state"], "JOB_STATE_CANCELLED");
    // The freed worker takes the next job while the other still renders, or after it.
    const std::string next = submitId(smallJob(sceneId));
    waitForState(b, "JOB_STATE_SUCCEEDED");
    waitForState(next, "JOB_STATE_SUCCEEDED");
    EXPECT_EQ(getJob(a)["state"], "JOB_STATE_CANCELLED");
    EXPECT_EQ(http().Get(("/v1/jobs/" + a + "/result").c_str())->status, 409);
    EXPECT_FALSE(std::filesystem::exists(dataDir() / "results" / (a + ".png")));
    EXPECT_EQ(result(b), cliRender(sceneId, kSlowJobFlags + " --seed 2"))
        << "the other job's image is whole";
}

// SIGTERM with both workers busy: within the grace both finish (1 attempt each); with grace 0
// both are handed over (one log line each) and the next start renders them again.
TEST_F(WorkersTest, SigtermFinishesOrHandsOverBothRunningJobs) {
    for (const char* grace : {"30", "0"}) {
        SCOPED_TRACE(std::string("--shutdown-grace ") + grace);
        std::vector<std::string> flags = kTwoWorkers;
        flags.insert(flags.end(), {"--shutdown-grace", grace});
        startServer(flags);
        const std::string sceneId = uploadSphere()["id"];
        const std::string a = submitId(seededSlowJob(sceneId, 1)), b = submitId(seededSlowJob(sceneId, 2));
        ASSERT_TRUE(waitUntilBothRunning(a, b));
        const int status = server_.kill(SIGTERM);
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << server_.log();
        const bool handedOver = std::string(grace) == "0";
        for (const std::string& id : {a, b})
            EXPECT_EQ(server_.log().find("job " + id + " did not finish within --shutdown-grace") !=
                          std::string::npos,
                      handedOver)
                << server_.log();
        startServer(kTwoWorkers);
        for (const std::string& id : {a, b})
            EXPECT_EQ(waitForState(id, "JOB_STATE_SUCCEEDED")["attempts"], handedOver ? 2 : 1) << id;
        server_.kill(SIGTERM);
    }
}

TEST_F(WorkersTest, BadGpuDeviceListsAreRefusedByName) {
    std::string seventeen = "0";
    for (int i = 1; i < 17; ++i) seventeen += ",0";
    const std::string start = "timeout 60 " + std::string(VASTRAY_BINARY) + " serve --data-dir " +
                              (dir_ / "bad").string() + " --grpc 127.0.0.1:0 --http 127.0.0.1:0 ";
    const std::vector<std::string> lists = {"",  "0,", ",0", "0,,0",       "x",      "0,1x",
                                            "-2", "1.5", "+1", "2147483648", seventeen};
    for (const std::string& list : lists) {
        SCOPED_TRACE("--gpu-device '" + list + "'");
        const CommandResult run = runShell(start + "--gpu-device '" + list + "'");
        EXPECT_EQ(run.exitCode, 2) << run.output;
        EXPECT_EQ(run.output.find("ready"), std::string::npos) << run.output;
        EXPECT_NE(run.output.find("--gpu-device '" + list + "': "), std::string::npos) << run.output;
        EXPECT_NE(run.output.find("at most 16"), std::string::npos) << run.output;
    }
    const CommandResult embree = runShell(start + "--backend embree --gpu-device 0,0");
    EXPECT_EQ(embree.exitCode, 2) << embree.output;
    EXPECT_NE(embree.output.find("--gpu-device '0,0': the embree backend runs one worker"), std::string::npos)
        << embree.output;
}

}  // namespace
}  // namespace vastray::test
