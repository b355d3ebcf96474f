// Replicas: three `vastray serve --storage S --database URL` on their own loopback ports share
// one PostgreSQL (started by the test) and one storage folder. A 4x4-tile job's tiles are
// leased by all of them; one replica is SIGKILLed while it holds a lease. The job still
// succeeds, every tile is done (the killed replica's by another after its lease expired), the
// result equals `vastray render` of the whole frame bit for bit, and it was assembled once.
#include <array>
#include <fstream>
#include <memory>
#include <set>

#include <grpcpp/grpcpp.h>

#include "PostgresCluster.h"
#include "ServerTestSupport.h"
#include "vastray/v1/render_service.grpc.pb.h"

namespace vastray::test {
namespace {

constexpr int kReplicas = 3;

class ReplicasTest : public ServerTest {
protected:
    void SetUp() override {
        ServerTest::SetUp();
        const std::string failed = cluster_.start();
        ASSERT_EQ(failed, "") << failed;
    }

    // Starts replica i; its replica id (from the "replica ID," line).
    std::string startReplica(int i, const std::vector<std::string>& extra = {}) {
        std::vector<std::string> flags = {"--storage",       storage().string(), "--database", cluster_.url(),
                                          "--lease-seconds", "2"};
        flags.insert(flags.end(), extra.begin(), extra.end());
        auto& replica = replicas_[i];
        replica = std::make_unique<ServerProcess>();
        EXPECT_TRUE(replica->startLogged(dir_ / ("replica-" + std::to_string(i) + ".log"), flags)) << replica->log();
        const std::string log = replica->log();
        const size_t at = log.find("vastray serve: replica ");
        if (at == std::string::npos) return "";
        const size_t start = at + std::string("vastray serve: replica ").size();
        return log.substr(start, log.find(',', start) - start);
    }

    httplib::Client client(int i) const {
        httplib::Client c("127.0.0.1", replicas_[i]->httpPort());
        c.set_read_timeout(30, 0);
        return c;
    }

    std::filesystem::path storage() const { return dir_ / "storage"; }

    std::string sql(const std::string& query) {
        const CommandResult run = cluster_.psql("vastray", query);
        EXPECT_EQ(run.exitCode, 0) << run.output;
        std::string out = run.output;
        while (!out.empty() && out.back() == '\n') out.pop_back();
        return out;
    }

    // vastray_tasks_waiting on replica i once it reads `expected` (it is refreshed once a
    // second), else the last figure read within 10 s; -1: absent from /metrics.
    long waitingTiles(int i, long expected) {
        long value = -2;
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        do {
            auto metrics = client(i).Get("/metrics");
            if (!metrics || metrics->status != 200) return -3;
            const size_t at = metrics->body.find("\nvastray_tasks_waiting ");
            value = at == std::string::npos ? -1 : std::stol(metrics->body.substr(at + 23));
            if (value == expected) break;
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
        } while (std::chrono::steady_clock::now() < deadline);
        return value;
    }

    // Job `id` as replica 0 reports it once it is neither queued nor running (or after 60 s).
    json finishedJob(const std::string& id) {
        json job;
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
        while (std::chrono::steady_clock::now() < deadline) {
            job = json::parse(client(0).Get(("/v1/jobs/" + id).c_str())->body);
            if (job["state"] != "JOB_STATE_QUEUED" && job["state"] != "JOB_STATE_RUNNING") break;
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        return job;
    }

    PostgresCluster cluster_;
    std::array<std::unique_ptr<ServerProcess>, kReplicas> replicas_;
};

TEST_F(ReplicasTest, ATiledJobSurvivesAReplicaKilledWhileItHoldsALease) {
    std::array<std::string, kReplicas> ids;
    for (int i = 0; i < kReplicas; ++i) {
        ids[i] = startReplica(i);
        ASSERT_FALSE(ids[i].empty()) << replicas_[i]->log();
    }
    ASSERT_EQ(std::set<std::string>(ids.begin(), ids.end()).size(), size_t(kReplicas)) << "replica ids differ";
    auto put = client(0).Put("/v1/scenes?name=sphere.ply", readBytes(spherePath_), "application/octet-stream");
    ASSERT_TRUE(put && put->status == 200) << (put ? put->body : "no response");
    const std::string sceneId = json::parse(put->body)["id"];
    // Long enough to catch leases held: a 32x32 tile at 64 spp is ~0.2-0.8 s of walk and shade
    // kernels on lavapipe (2 cores). At 256 spp the tiles and the whole-frame render below took
    // ~40 s of CPU.
    const json body = {{"scene_id", sceneId}, {"width", 128}, {"height", 128}, {"spp", 64}, {"tiles", {4, 4}}};
    auto res = client(1).Post("/v1/jobs", body.dump(), "application/json");
    ASSERT_TRUE(res && res->status == 202) << (res ? res->body : "no response");
    const std::string jobId = json::parse(res->body)["id"];

    // A replica seen holding a lease is frozen (SIGSTOP: it can neither finish nor renew); if
    // the table still says it holds a tile it is killed, else it goes on and the search too.
    int victim = -1;
    std::string heldTile;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (victim < 0 && std::chrono::steady_clock::now() < deadline) {
        const std::string owner =
            sql("SELECT owner FROM tasks WHERE job_id = '" + jobId + "' AND state = 1 AND tile >= 0 LIMIT 1");
        for (int i = 0; i < kReplicas && victim < 0 && !owner.empty(); ++i) {
            if (ids[i] != owner) continue;
            replicas_[i]->signal(SIGSTOP);
            heldTile = sql("SELECT min(tile) FROM tasks WHERE job_id = '" + jobId +
                           "' AND state = 1 AND tile >= 0 AND owner = '" + ids[i] + "'");
            if (!heldTile.empty())
                victim = i;
            else
                replicas_[i]->signal(SIGCONT);
        }
    }
    ASSERT_GE(victim, 0) << "no replica was seen holding a lease";
    replicas_[victim]->kill(SIGKILL);

    const int survivor = (victim + 1) % kReplicas;
    json job;
    const auto doneBy = std::chrono::steady_clock::now() + std::chrono::seconds(180);
    while (std::chrono::steady_clock::now() < doneBy) {
        auto got = client(survivor).Get(("/v1/jobs/" + jobId).c_str());
        ASSERT_TRUE(got && got->status == 200);
        job = json::parse(got->body);
        if (job["state"] != "JOB_STATE_QUEUED" && job["state"] != "JOB_STATE_RUNNING") break;
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    ASSERT_EQ(job["state"], "JOB_STATE_SUCCEEDED") << job.dump();
    EXPECT_EQ(job["progress"], 100);

    // Every tile done, none by the killed replica's lost lease; the one it held was taken over
    // after its lease expired (a second attempt), and that is recorded in attempt_errors.
    EXPECT_EQ(sql("SELECT count(*) FROM tasks WHERE job_id = '" + jobId + "' AND tile >= 0 AND state = 2"), "16");
    EXPECT_EQ(sql("SELECT attempts > 1 AND owner <> '" + ids[victim] + "' FROM tasks WHERE job_id = '" + jobId +
                  "' AND tile = " + heldTile),
              "t");
    bool expiryRecorded = false;
    for (const json& e : job["attempt_errors"])
        expiryRecorded |= e.get<std::string>().find("tile " + heldTile + " attempt 1 (replica " + ids[victim] +
                                                    "): its lease expired") == 0;
    EXPECT_TRUE(expiryRecorded) << job.dump();
    EXPECT_EQ(sql("SELECT state || ',' || attempts FROM tasks WHERE job_id = '" + jobId + "' AND tile = -1"), "2,1")
        << "assembled once";
    int assembled = 0;
    for (int i = 0; i < kReplicas; ++i) {
        const std::string log = replicas_[i]->log();
        for (size_t at = log.find("job " + jobId + ": assembled 16 tiles"); at != std::string::npos;
             at = log.find("job " + jobId + ": assembled", at + 1))
            ++assembled;
    }
    EXPECT_EQ(assembled, 1) << "exactly one replica assembled the result";
    EXPECT_TRUE(std::filesystem::is_empty(storage() / "tiles" / jobId)) << "tiles removed after assembly";

    // Any live replica serves the result; it equals the whole-frame render bit for bit.
    auto result = client(survivor).Get(("/v1/jobs/" + jobId + "/result").c_str());
    ASSERT_TRUE(result && result->status == 200);
    const auto out = dir_ / "whole.png";
    const auto run = runVastray("render " + (storage() / "scenes" / (sceneId + ".vast")).string() + " -o " +
                                out.string() + " --backend vulkan --progress none --resolution 128x128 --spp 64");
    ASSERT_EQ(run.exitCode, 0) << run.output;
    EXPECT_EQ(result->body, readBytes(out)) << "assembled tiles = the whole-frame render";
}

// Without --storage a tiled job is refused naming the field; replicas need --database; with
// replicas the field works over gRPC too.
TEST_F(ReplicasTest, TilesNeedReplicasAndReplicasNeedADatabase) {
    startServer({"--database", cluster_.url()});
    const std::string sceneId = uploadSphere()["id"];
    json body = smallJob(sceneId);
    body["tiles"] = {2, 2};
    auto res = submit(body);
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 400) << res->body;
    EXPECT_NE(res->body.find("tiles"), std::string::npos) << res->body;
    server_.kill(SIGTERM);

    const std::string serve =
        "timeout 60 " + std::string(VASTRAY_BINARY) + " serve --grpc 127.0.0.1:0 --http 127.0.0.1:0 ";
    const CommandResult noDatabase = runShell(serve + "--storage " + storage().string());
    EXPECT_EQ(noDatabase.exitCode, 2) << noDatabase.output;
    EXPECT_NE(noDatabase.output.find("--storage needs --database"), std::string::npos) << noDatabase.output;
    const CommandResult both = runShell(serve + "--storage " + storage().string() + " --data-dir " +
                                        dataDir().string() + " --database '" + cluster_.url() + "'");
    EXPECT_EQ(both.exitCode, 2) << both.output;
    EXPECT_NE(both.output.find("give one of --data-dir (one server) or --storage"), std::string::npos) << both.output;

    ASSERT_FALSE(startReplica(0).empty());
    // The scene is in the catalog already (the single server stored it); its file goes to the
    // shared folder as a replica's upload would have put it.
    std::filesystem::copy_file(dataDir() / "scenes" / (sceneId + ".vast"), storage() / "scenes" / (sceneId + ".vast"));
    // The same field over gRPC: a 2x2-tile job on one replica equals the whole-frame render.
    auto channel = grpc::CreateChannel(replicas_[0]->grpcAddress(), grpc::InsecureChannelCredentials());
    auto renders = v1::RenderService::NewStub(channel);
    v1::SubmitJobRequest request;
    request.set_scene_id(sceneId);
    request.set_width(32);
    request.set_height(32);
    request.set_spp(2);
    request.add_tiles(2);
    request.add_tiles(2);
    v1::SubmitJobResponse submitted;
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(30));
    const grpc::Status status = renders->SubmitJob(&context, request, &submitted);
    ASSERT_TRUE(status.ok()) << status.error_message();
    json job = finishedJob(submitted.job().id());
    ASSERT_EQ(job["state"], "JOB_STATE_SUCCEEDED") << job.dump();
    EXPECT_EQ(job["request"]["tiles"], json({2, 2})) << job.dump();
    const auto out = dir_ / "whole32.png";
    const auto run = runVastray("render " + (storage() / "scenes" / (sceneId + ".vast")).string() + " -o " +
                                out.string() + " --backend vulkan --progress none --resolution 32x32 --spp 2");
    ASSERT_EQ(run.exitCode, 0) << run.output;
    EXPECT_EQ(client(0).Get(("/v1/jobs/" + submitted.job().id() + "/result").c_str())->body, readBytes(out));

    body["tiles"] = {2, 200};
    res = client(0).Post("/v1/jobs", body.dump(), "application/json");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 400) << "more tile rows than pixel rows: " << res->body;
    EXPECT_NE(res->body.find("tiles"), std::string::npos) << res->body;
}

// A tile whose render fails (the package damaged after its upload) is retried, by any replica,
// until --max-attempts attempts of it failed; then the job is FAILED with the reasons.
TEST_F(ReplicasTest, ATileThatKeepsFailingFailsTheJobAfterMaxAttempts) {
    ASSERT_FALSE(startReplica(0, {"--max-attempts", "2"}).empty());
    auto put = client(0).Put("/v1/scenes?name=sphere.ply", readBytes(spherePath_), "application/octet-stream");
    ASSERT_TRUE(put && put->status == 200);
    const std::string sceneId = json::parse(put->body)["id"];
    const auto package = storage() / "scenes" / (sceneId + ".vast");
    std::string bytes = readBytes(package);
    bytes.resize(bytes.size() / 2);
    std::ofstream(package, std::ios::binary | std::ios::trunc) << bytes;
    json body = smallJob(sceneId);
    body["tiles"] = {2, 1};
    auto res = client(0).Post("/v1/jobs", body.dump(), "application/json");
    ASSERT_TRUE(res && res->status == 202) << (res ? res->body : "no response");
    const std::string jobId = json::parse(res->body)["id"];
    json job = finishedJob(jobId);
    ASSERT_EQ(job["state"], "JOB_STATE_FAILED") << job.dump();
    const std::string error = job.value("error", "");
    EXPECT_EQ(error.find("failed 2 times (--max-attempts 2); not run again: tile 0 attempt 1 (replica "), 0u) << error;
    EXPECT_NE(error.find("(tile 0 failed 2 times)"), std::string::npos) << error;
    EXPECT_NE(error.find(sceneId), std::string::npos) << "the reasons name the package: " << error;
    EXPECT_EQ(sql("SELECT count(*) FROM tasks WHERE job_id = '" + jobId + "' AND state = 1"), "0")
        << "nothing leased once the job failed";
    EXPECT_EQ(client(0).Get("/healthz")->status, 200);
}

// A tile refused for the job's request (a memory_budget_bytes below the scene's minimum) would be
// refused again: the job is FAILED at that first attempt (the default --max-attempts is 3), with
// the tile's reason as its error, and nothing is left leased.
TEST_F(ReplicasTest, ATileRefusedForItsBudgetFailsTheJobAtOnce) {
    ASSERT_FALSE(startReplica(0).empty());
    auto put = client(0).Put("/v1/scenes?name=sphere.ply", readBytes(spherePath_), "application/octet-stream");
    ASSERT_TRUE(put && put->status == 200);
    json body = smallJob(json::parse(put->body)["id"]);
    body["tiles"] = {2, 1};
    body["memory_budget_bytes"] = "65536";
    auto res = client(0).Post("/v1/jobs", body.dump(), "application/json");
    ASSERT_TRUE(res && res->status == 202) << (res ? res->body : "no response");
    const std::string jobId = json::parse(res->body)["id"];
    json job = finishedJob(jobId);
    ASSERT_EQ(job["state"], "JOB_STATE_FAILED") << job.dump();
    EXPECT_EQ(job["attempts"], 1) << job.dump();
    EXPECT_EQ(job["attempt_errors"].size(), 1u) << job.dump();
    const std::string error = job.value("error", "");
    EXPECT_EQ(error.find("tile "), 0u) << error;
    EXPECT_NE(error.find(" attempt 1 (replica "), std::string::npos) << error;
    EXPECT_NE(error.find("memory_budget_bytes 64.0 KiB is below this scene's minimum of "), std::string::npos)
        << error;
    EXPECT_EQ(sql("SELECT count(*) FROM tasks WHERE job_id = '" + jobId + "' AND state = 1"), "0")
        << "nothing leased once the job failed";
}

// Replicas' queue is the tasks table (their vastray_jobs_queued stays 0): vastray_tasks_waiting
// counts, on every replica, the tiles of all jobs that a replica could lease now: waiting, or
// leased with an expired lease; not those leased and held, done, of a cancelled job, nor the
// assemble tasks. It is what the Helm chart's HPA scales on.
TEST_F(ReplicasTest, TasksWaitingGaugeCountsLeasableTilesOnEveryReplica) {
    for (int i = 0; i < 2; ++i) ASSERT_FALSE(startReplica(i, {"--paused"}).empty()) << replicas_[i]->log();
    EXPECT_EQ(waitingTiles(0, 0), 0);
    auto put = client(0).Put("/v1/scenes?name=sphere.ply", readBytes(spherePath_), "application/octet-stream");
    ASSERT_TRUE(put && put->status == 200);
    const std::string sceneId = json::parse(put->body)["id"];
    std::vector<std::string> jobs;
    for (const json& tiles : {json({2, 2}), json({3, 1})}) {
        json body = smallJob(sceneId);
        body["tiles"] = tiles;
        auto res = client(0).Post("/v1/jobs", body.dump(), "application/json");
        ASSERT_TRUE(res && res->status == 202) << (res ? res->body : "no response");
        jobs.push_back(json::parse(res->body)["id"]);
    }
    for (int i = 0; i < 2; ++i) EXPECT_EQ(waitingTiles(i, 7), 7) << "replica " << i << ": 4 + 3 tiles";
    auto metrics = client(1).Get("/metrics");
    ASSERT_TRUE(metrics);
    EXPECT_NE(metrics->body.find("\nvastray_jobs_queued 0\n"), std::string::npos) << "the in-memory queue is empty";

    // Of the first job: tile 0 held (lease in the future), tile 1 leased but expired, tile 2 done.
    const std::string first = "job_id = '" + jobs[0] + "' AND tile = ";
    sql("UPDATE tasks SET state = 1, owner = 'elsewhere', lease_until = now() + interval '1 hour' WHERE " + first + "0");
    sql("UPDATE tasks SET state = 1, owner = 'gone', lease_until = now() - interval '1 second' WHERE " + first + "1");
    sql("UPDATE tasks SET state = 2 WHERE " + first + "2");
    EXPECT_EQ(waitingTiles(1, 5), 5) << "tiles 1 and 3 of the first job, 3 of the second";

    auto cancelled = client(0).Post(("/v1/jobs/" + jobs[1] + ":cancel").c_str(), "{}", "application/json");
    ASSERT_TRUE(cancelled && cancelled->status == 200) << (cancelled ? cancelled->body : "no response");
    EXPECT_EQ(waitingTiles(0, 2), 2) << "a cancelled job's tiles wait for nobody";
}

}  // namespace
}  // namespace vastray::test
