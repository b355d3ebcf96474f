// The HTTP front end of a real `vastray serve`, driven with cpp-httplib's client.
#include <set>

#include "ServerTestSupport.h"
#include "vastray/server/Sha256.h"
#include "vastray/v1/render_service.pb.h"
#include "vastray/v1/scene_service.pb.h"

namespace vastray::test {
namespace {

std::string errorCode(const httplib::Result& res) {
    if (!res) return "no response";
    auto body = json::parse(res->body, nullptr, false);
    return body.is_object() && body.contains("error") ? body["error"].value("code", "")
                                                      : "no error body: " + res->body;
}

TEST_F(ServerTest, HttpUploadSubmitWatchAndDownloadMatchesCliRender) {
    startServer();
    const json scene = uploadSphere();
    const std::string bytes = readBytes(spherePath_);
    EXPECT_EQ(scene["id"], server::sha256Hex(bytes.data(), bytes.size()))
        << "scenes are addressed by SHA-256";
    EXPECT_EQ(scene["format"], "ply");
    EXPECT_GT(std::stoull(scene["triangles"].get<std::string>()), 1000u);
    EXPECT_EQ(uploadSphere()["id"], scene["id"]) << "the same content is the same scene";
    auto info = runVastray("info " + (dataDir() / "scenes" / (scene["id"].get<std::string>() + ".vast")).string() +
                           " --json");
    ASSERT_EQ(info.exitCode, 0) << info.output;
    EXPECT_EQ(scene["chunks"], std::to_string(json::parse(info.output)["chunks"].get<uint64_t>()))
        << "the scene's chunk count is its package's";

    auto submitted = submit(smallJob(scene["id"]));
    ASSERT_TRUE(submitted);
    ASSERT_EQ(submitted->status, 202) << submitted->body;
    const json job = json::parse(submitted->body);
    EXPECT_EQ(submitted->get_header_value("Location"), "/v1/jobs/" + job["id"].get<std::string>());
    EXPECT_EQ(job["request"]["priority"], 50) << "defaults are filled in";
    EXPECT_EQ(job["request"]["integrator"], "path");

    // SSE: a snapshot first, the stream ends after the final state.
    std::string events;
    auto watched = http().Get(("/v1/jobs/" + job["id"].get<std::string>() + "/events").c_str(),
                              [&](const char* data, size_t size) {
                                  events.append(data, size);
                                  return true;
                              });
    ASSERT_TRUE(watched);
    EXPECT_EQ(watched->get_header_value("Content-Type"), "text/event-stream");
    EXPECT_EQ(events.rfind("event: KIND_SNAPSHOT\ndata: {", 0), 0u) << events;
    const size_t lastData = events.rfind("data: ");
    ASSERT_NE(lastData, std::string::npos);
    const json last = json::parse(events.substr(lastData + 6, events.find('\n', lastData) - lastData - 6));
    EXPECT_EQ(last["state"], "JOB_STATE_SUCCEEDED") << events;

    const json done = getJob(job["id"]);
    EXPECT_EQ(done["state"], "JOB_STATE_SUCCEEDED");
    EXPECT_EQ(done["progress"], 100.0);
    EXPECT_EQ(done["attempts"], 1);
    const std::string image = result(job["id"]);
    EXPECT_EQ(std::to_string(image.size()), done["result_bytes"].get<std::string>());
    EXPECT_EQ(image, cliRender(scene["id"], "--resolution 32x32 --spp 2"))
        << "the service renders through the same functions as `vastray render`";

    auto range = http().Get(("/v1/jobs/" + job["id"].get<std::string>() + "/result").c_str(),
                            httplib::Headers{{"Range", "bytes=1-8"}});
    ASSERT_TRUE(range);
    EXPECT_EQ(range->status, 206);
    EXPECT_EQ(range->body, image.substr(1, 8));
    EXPECT_EQ(range->get_header_value("Content-Range"), "bytes 1-8/" + std::to_string(image.size()));

    auto list = http().Get("/v1/jobs?state=JOB_STATE_SUCCEEDED");
    ASSERT_TRUE(list && list->status == 200);
    EXPECT_EQ(json::parse(list->body)["jobs"].size(), 1u);
}

TEST_F(ServerTest, HttpInvalidRequestsAreRejectedNamingTheField) {
    startServer({"--paused"});
    const std::string sceneId = uploadSphere()["id"];
    json body = smallJob(sceneId);
    body["width"] = 0;
    auto res = submit(body);
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 400);
    EXPECT_EQ(errorCode(res), "INVALID_ARGUMENT");
    EXPECT_EQ(errorMessage(res).rfind("width:", 0), 0u) << errorMessage(res);

    body = smallJob(sceneId);
    body["aovs"] = {"depth"};
    body["output_format"] = "png";
    res = submit(body);
    EXPECT_EQ(res->status, 400);
    EXPECT_EQ(errorMessage(res).rfind("output_format:", 0), 0u) << errorMessage(res);

    body = smallJob(sceneId);
    body["colour"] = "red";
    res = submit(body);
    EXPECT_EQ(res->status, 400) << "unknown fields are errors";
    EXPECT_NE(errorMessage(res).find("colour"), std::string::npos) << errorMessage(res);

    res = submit(smallJob("not-a-digest"));
    EXPECT_EQ(res->status, 400);
    EXPECT_EQ(errorMessage(res).rfind("scene_id:", 0), 0u) << errorMessage(res);

    const std::pair<const char*, json> environment[] = {
        {"up_axis:", {{"up_axis", "x"}}},
        {"sun.direction:", {{"sun", {{"direction", {0, 0, 0}}, {"intensity", 3}}}}},
        {"sun.direction:", {{"sun", {{"direction", {1, 1}}, {"intensity", 3}}}}},
        {"sun.intensity:", {{"sun", {{"direction", {1, 1, 1}}, {"intensity", -1}}}}}};
    for (const auto& [field, patch] : environment) {
        body = smallJob(sceneId);
        body.update(patch);
        res = submit(body);
        EXPECT_EQ(res->status, 400) << patch.dump();
        EXPECT_EQ(errorMessage(res).rfind(field, 0), 0u) << errorMessage(res);
    }
    body = smallJob(sceneId);
    body.update(json{{"up_axis", "z"}, {"sun", {{"direction", {0.2, -0.3, 0.9}}, {"intensity", 2.5}}}});
    res = submit(body);
    EXPECT_EQ(res->status, 202) << res->body;
    EXPECT_EQ(json::parse(res->body)["request"]["up_axis"], "z") << res->body;

    res = http().Put("/v1/scenes?name=notes.txt", "hello", "application/octet-stream");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 400);
    EXPECT_EQ(errorMessage(res).rfind("name:", 0), 0u) << errorMessage(res);

    res = http().Put("/v1/scenes?name=broken.obj", "v 0 0 0\nf 1 2 3\n", "application/octet-stream");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 400) << res->body;
    EXPECT_NE(errorMessage(res).find("broken.obj"), std::string::npos)
        << "names the client's file: " << errorMessage(res);
}

// chunkid and cost need chunks that stream: an embree server refused the job only when it ran
// (FAILED); now at submit, naming the AOV and the backend. A vulkan server takes them.
TEST_F(ServerTest, StreamingOnlyAovsAreRefusedAtSubmitByAnEmbreeServer) {
    startServer({"--backend", "embree", "--paused"});
    const std::string sceneId = uploadSphere()["id"];
    for (const char* aov : {"chunkid", "cost"}) {
        json body = smallJob(sceneId);
        body["aovs"] = {"depth", aov};
        auto res = submit(body);
        ASSERT_TRUE(res);
        EXPECT_EQ(res->status, 400) << res->body;
        EXPECT_EQ(errorMessage(res), std::string("aovs: '") + aov + "' needs the vulkan backend; this server renders with embree");
    }
    json bad = smallJob(sceneId);
    bad["aovs"] = {"bogus"};
    auto res = submit(bad);
    EXPECT_EQ(res->status, 400);
    EXPECT_NE(errorMessage(res).find("expected depth, normal, albedo, primid, chunkid, cost or uv"), std::string::npos)
        << errorMessage(res);
    json fine = smallJob(sceneId);
    fine["aovs"] = {"depth", "primid"};
    EXPECT_EQ(submit(fine)->status, 202);
}

TEST_F(ServerTest, HttpUnknownIdsAre404AndWrongStatesAre409) {
    startServer({"--paused"});
    const std::string sceneId = uploadSphere()["id"];
    const std::string unknownScene(64, 'a');
    EXPECT_EQ(http().Get(("/v1/scenes/" + unknownScene).c_str())->status, 404);
    EXPECT_EQ(submit(smallJob(unknownScene))->status, 404);
    EXPECT_EQ(http().Get("/v1/jobs/job-00000000000000000000000000000000")->status, 404);
    EXPECT_EQ(errorCode(http().Get("/v1/jobs/job-00000000000000000000000000000000")), "NOT_FOUND");

    auto res = submit(smallJob(sceneId));
    ASSERT_EQ(res->status, 202);
    const std::string jobId = json::parse(res->body)["id"];
    EXPECT_EQ(http().Get(("/v1/jobs/" + jobId + "/result").c_str())->status, 409) << "no result while QUEUED";
    res = http().Delete(("/v1/scenes/" + sceneId).c_str());
    EXPECT_EQ(res->status, 409) << "a scene a queued job uses cannot be deleted";
    EXPECT_EQ(errorCode(res), "FAILED_PRECONDITION");

    res = http().Post(("/v1/jobs/" + jobId + ":cancel").c_str(), R"({"reason": "test"})", "application/json");
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(json::parse(res->body)["state"], "JOB_STATE_CANCELLED");
    EXPECT_EQ(json::parse(res->body)["error"], "cancelled: test");
    EXPECT_EQ(getJob(jobId)["state"], "JOB_STATE_CANCELLED");
    EXPECT_EQ(http().Post(("/v1/jobs/" + jobId + ":cancel").c_str(), "", "application/json")->status, 409);

    EXPECT_EQ(http().Delete(("/v1/scenes/" + sceneId).c_str())->status, 200) << "free once no job uses it";
    EXPECT_EQ(http().Get(("/v1/scenes/" + sceneId).c_str())->status, 404);
}

TEST_F(ServerTest, HttpFullQueueIs429WithRetryAfter) {
    startServer({"--paused", "--max-queue", "2"});
    const std::string sceneId = uploadSphere()["id"];
    EXPECT_EQ(submit(smallJob(sceneId))->status, 202);
    EXPECT_EQ(submit(smallJob(sceneId))->status, 202);
    const auto start = std::chrono::steady_clock::now();
    auto res = submit(smallJob(sceneId));
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 429);
    EXPECT_EQ(errorCode(res), "RESOURCE_EXHAUSTED");
    EXPECT_FALSE(res->get_header_value("Retry-After").empty());
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1)) << "refused at once";
    auto metrics = http().Get("/metrics");
    ASSERT_TRUE(metrics);
    EXPECT_NE(metrics->body.find("vastray_jobs_rejected_total 1\n"), std::string::npos) << metrics->body;
    EXPECT_NE(metrics->body.find("vastray_jobs_queued 2\n"), std::string::npos) << metrics->body;
    // One server: its queued jobs are the tasks waiting (each job one task).
    EXPECT_NE(metrics->body.find("\n# TYPE vastray_tasks_waiting gauge\nvastray_tasks_waiting 2\n"), std::string::npos)
        << metrics->body;
}

TEST_F(ServerTest, HttpIdempotencyKeyReturnsTheSameJob) {
    startServer({"--paused"});
    const std::string sceneId = uploadSphere()["id"];
    auto first = submit(smallJob(sceneId), {{"Idempotency-Key", "render-42"}});
    ASSERT_EQ(first->status, 202);
    auto again = submit(smallJob(sceneId), {{"Idempotency-Key", "render-42"}});
    ASSERT_EQ(again->status, 200) << again->body;
    EXPECT_EQ(json::parse(first->body)["id"], json::parse(again->body)["id"]);
    EXPECT_EQ(json::parse(again->body)["request"]["request_id"], "render-42");
    json other = smallJob(sceneId);
    other["spp"] = 4;
    EXPECT_EQ(submit(other, {{"Idempotency-Key", "render-42"}})->status, 409)
        << "same key, different request";
    auto list = http().Get("/v1/jobs");
    EXPECT_EQ(json::parse(list->body)["jobs"].size(), 1u);
}

TEST_F(ServerTest, HttpListingPagesThroughEveryJobOnce) {
    startServer({"--paused"});
    const std::string sceneId = uploadSphere()["id"];
    std::set<std::string> submitted;
    for (int i = 0; i < 5; ++i)
        submitted.insert(json::parse(submit(smallJob(sceneId))->body)["id"].get<std::string>());
    std::set<std::string> listed;
    std::string token;
    int pages = 0;
    do {
        auto res = http().Get(("/v1/jobs?state=JOB_STATE_QUEUED&page_size=2&page_token=" + token).c_str());
        ASSERT_TRUE(res && res->status == 200) << (res ? res->body : "");
        const json page = json::parse(res->body);
        EXPECT_LE(page["jobs"].size(), 2u);
        for (const json& job : page["jobs"]) EXPECT_TRUE(listed.insert(job["id"].get<std::string>()).second);
        token = page["next_page_token"];
        ++pages;
    } while (!token.empty() && pages < 10);
    EXPECT_EQ(pages, 3);
    EXPECT_EQ(listed, submitted);
    auto bad = http().Get("/v1/jobs?page_size=lots");
    EXPECT_EQ(bad->status, 400);
    EXPECT_EQ(errorMessage(bad).rfind("page_size:", 0), 0u) << errorMessage(bad);
    bad = http().Get("/v1/jobs?state=DONE");
    EXPECT_EQ(bad->status, 400);
    EXPECT_EQ(errorMessage(bad).rfind("state:", 0), 0u) << errorMessage(bad);
    EXPECT_NE(errorMessage(bad).find("JOB_STATE_QUEUED"), std::string::npos) << errorMessage(bad);
    // The names the states had before the protos followed buf's lint rules still filter.
    auto shortName = http().Get("/v1/jobs?state=QUEUED&page_size=1000");
    ASSERT_TRUE(shortName && shortName->status == 200) << (shortName ? shortName->body : "");
    EXPECT_EQ(json::parse(shortName->body)["jobs"].size(), submitted.size());
    for (const json& job : json::parse(shortName->body)["jobs"]) EXPECT_EQ(job["state"], "JOB_STATE_QUEUED");
    auto none = http().Get("/v1/jobs?state=RUNNING");
    ASSERT_TRUE(none && none->status == 200);
    EXPECT_EQ(json::parse(none->body)["jobs"].size(), 0u) << "a paused server runs nothing";
}

TEST_F(ServerTest, HttpAuthTokenIsRequiredWhenConfigured) {
    const auto tokenFile = dir_ / "token";
    std::ofstream(tokenFile) << "s3cret-token\n";
    startServer({"--auth-token-file", tokenFile.string()});
    EXPECT_EQ(http().Get("/v1/jobs")->status, 401);
    EXPECT_EQ(errorCode(http().Get("/v1/jobs")), "UNAUTHENTICATED");
    token_ = "wrong";
    EXPECT_EQ(http().Get("/v1/jobs")->status, 401);
    EXPECT_EQ(http().Put("/v1/scenes?name=sphere.ply", "ply", "application/octet-stream")->status, 401);
    token_ = "s3cret-token";
    EXPECT_EQ(http().Get("/v1/jobs")->status, 200);
    EXPECT_EQ(uploadSphere()["format"], "ply");
    token_.clear();
    EXPECT_EQ(http().Get("/healthz")->status, 200) << "health checks need no token";
    EXPECT_EQ(http().Get("/readyz")->status, 200);
}

TEST_F(ServerTest, HttpOpenApiDescribesEveryProtoField) {
    startServer();
    auto res = http().Get("/openapi.json");
    ASSERT_TRUE(res && res->status == 200);
    const json doc = json::parse(res->body);
    for (const auto* descriptor :
         {v1::SubmitJobRequest::descriptor(), v1::Job::descriptor(), v1::JobStats::descriptor(),
          v1::Scene::descriptor(), v1::JobEvent::descriptor(), v1::ListJobsResponse::descriptor()}) {
        const json& properties = doc["components"]["schemas"][descriptor->name()]["properties"];
        ASSERT_TRUE(properties.is_object()) << descriptor->name();
        EXPECT_EQ(properties.size(), size_t(descriptor->field_count())) << descriptor->name();
        for (int i = 0; i < descriptor->field_count(); ++i)
            EXPECT_TRUE(properties.contains(descriptor->field(i)->name()))
                << descriptor->full_name() << "." << descriptor->field(i)->name();
    }
    for (const char* path : {"/v1/scenes", "/v1/jobs", "/v1/jobs/{id}", "/v1/jobs/{id}:cancel",
                             "/v1/jobs/{id}/events", "/v1/jobs/{id}/result"})
        EXPECT_TRUE(doc["paths"].contains(path)) << path;
}

TEST_F(ServerTest, SigtermStopsGracefully) {
    startServer();
    const std::string sceneId = uploadSphere()["id"];
    ASSERT_EQ(submit(smallJob(sceneId))->status, 202);
    const int status = server_.kill(SIGTERM);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << server_.log();
    EXPECT_NE(server_.log().find("stopped"), std::string::npos) << server_.log();
}

}  // namespace
}  // namespace vastray::test
