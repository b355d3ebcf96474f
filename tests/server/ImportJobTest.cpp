// Imports as jobs: an asynchronous upload (HTTP ?async=true, gRPC UploadSceneRequest.async)
// returns as soon as its bytes are stored, with an import job that reports state and errors
// through the same Job resource as renders; imports run one after another on their own thread.
#include <grpcpp/grpcpp.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <ctime>

#include "GrpcUpload.h"
#include "ServerTestSupport.h"
#include "vastray/v1/render_service.grpc.pb.h"
#include "vastray/v1/scene_service.grpc.pb.h"

namespace vastray::test {
namespace {

namespace fs = std::filesystem;

// Seconds since the epoch of a proto3 JSON timestamp ("2026-12-02T02:10:08.865847Z").
double epochSeconds(const std::string& text) {
    std::tm tm{};
    double seconds = 0;
    EXPECT_EQ(std::sscanf(text.c_str(), "%d-%d-%dT%d:%d:%lfZ", &tm.tm_year, &tm.tm_mon, &tm.tm_mday, &tm.tm_hour,
                          &tm.tm_min, &seconds),
              6)
        << text;
    tm.tm_year -= 1900;
    tm.tm_mon -= 1;
    return double(timegm(&tm)) + seconds;
}

class ImportJobTest : public ServerTest {
protected:
    // A mesh that takes the importer a while (about a second here): 300k triangles.
    fs::path bigMesh() {
        const fs::path path = dir_ / "big.ply";
        GenerateOptions sphere;
        sphere.kind = GeneratorKind::Sphere;
        sphere.triangles = 300000;
        EXPECT_TRUE(generateToPly(sphere, path.string()).isOk());
        return path;
    }

    httplib::Result putAsync(const std::string& bytes, const std::string& name) {
        return http().Put(("/v1/scenes?async=true&name=" + name).c_str(), bytes, "application/octet-stream");
    }

    // Polls the job until it leaves QUEUED and RUNNING (60 s at most).
    json waitForEnd(const std::string& id) {
        json job;
        for (int i = 0; i < 3000; ++i) {
            job = getJob(id);
            if (job.value("state", "") != "JOB_STATE_QUEUED" && job.value("state", "") != "JOB_STATE_RUNNING")
                return job;
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        ADD_FAILURE() << "import job " << id << " never ended: " << job.dump();
        return job;
    }
};

TEST_F(ImportJobTest, AsyncUploadReturnsAnImportJobAndTheSceneFollows) {
    startServer({"--backend", "embree"});
    const std::string bytes = readBytes(bigMesh());
    auto res = putAsync(bytes, "big.ply");
    ASSERT_TRUE(res);
    ASSERT_EQ(res->status, 202) << res->body;
    const json queued = json::parse(res->body);
    const std::string sceneId = queued["id"], jobId = queued["import_job_id"];
    EXPECT_EQ(res->get_header_value("Location"), "/v1/jobs/" + jobId);
    EXPECT_EQ(queued["triangles"], "0") << "not imported yet";
    // The scene is not there yet, and says which job brings it.
    auto early = http().Get(("/v1/scenes/" + sceneId).c_str());
    EXPECT_EQ(early->status, 404);
    EXPECT_NE(early->body.find("job " + jobId + " is importing it"), std::string::npos) << early->body;
    auto submitEarly = submit(smallJob(sceneId));
    EXPECT_EQ(submitEarly->status, 404);
    EXPECT_NE(submitEarly->body.find("is importing it"), std::string::npos) << submitEarly->body;

    // The job's events end at SUCCEEDED; then the scene is stored.
    std::string events;
    http().Get(("/v1/jobs/" + jobId + "/events").c_str(), [&](const char* data, size_t size) {
        events.append(data, size);
        return true;
    });
    EXPECT_NE(events.find("\"state\":\"JOB_STATE_SUCCEEDED\""), std::string::npos) << events;
    // Its progress rises as the import goes (10 % read, up to 90 % built, 95 % written), never back.
    std::vector<int> progress;
    for (size_t at = events.find("\"percent\":"); at != std::string::npos; at = events.find("\"percent\":", at + 1))
        progress.push_back(std::stoi(events.substr(at + 10)));
    EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end())) << events;
    EXPECT_TRUE(std::any_of(progress.begin(), progress.end(), [](int p) { return p > 0 && p < 100; }))
        << "no step between 0 and 100: " << events;
    const json job = getJob(jobId);
    EXPECT_EQ(job["state"], "JOB_STATE_SUCCEEDED") << job.dump();
    EXPECT_EQ(job["progress"], 100);
    EXPECT_EQ(job["import"]["name"], "big.ply");
    EXPECT_EQ(job["import"]["scene_id"], sceneId);
    EXPECT_EQ(job["import"]["upload_bytes"], std::to_string(bytes.size()));
    const json scene = json::parse(http().Get(("/v1/scenes/" + sceneId).c_str())->body);
    EXPECT_GT(std::stoull(scene["triangles"].get<std::string>()), 100000u) << scene.dump();
    EXPECT_EQ(scene["import_job_id"], "") << "a stored scene has no import in flight";

    // An import job has no image and cannot be cancelled; known content needs no job.
    EXPECT_EQ(http().Get(("/v1/jobs/" + jobId + "/result").c_str())->status, 409);
    EXPECT_EQ(http().Post(("/v1/jobs/" + jobId + ":cancel").c_str(), "", "application/json")->status, 409);
    auto again = putAsync(bytes, "big.ply");
    EXPECT_EQ(again->status, 200) << again->body;
    EXPECT_EQ(json::parse(again->body)["triangles"], scene["triangles"]);
    auto render = submit(smallJob(sceneId));
    ASSERT_EQ(render->status, 202) << render->body;
    waitForState(json::parse(render->body)["id"], "JOB_STATE_SUCCEEDED");
    EXPECT_TRUE(fs::is_empty(dataDir() / "tmp"));
}

// What a model holds and the package does not carry comes back as warnings: on the scene of
// a synchronous upload, and on the import job (and then the scene) of an asynchronous one.
// An STL goes through assimp, as `vastray import` reads it.
TEST_F(ImportJobTest, ImporterWarningsReachTheSceneAndTheImportJob) {
    startServer({"--backend", "embree"});
    // Texture coordinates are read and not carried yet (shading normals are: no warning for them).
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\nf 1/1/1 2/1/1 3/1/1\n";
    auto sync = http().Put("/v1/scenes?name=uv.obj", obj, "application/octet-stream");
    ASSERT_TRUE(sync);
    ASSERT_LT(sync->status, 300) << sync->body;
    const json scene = json::parse(sync->body);
    ASSERT_EQ(scene["import_warnings"].size(), 1u) << scene.dump();
    EXPECT_EQ(scene["import_warnings"][0], "1 texture coordinates read but not used (no material has a texture map)");

    const std::string uvs = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n";
    auto res = putAsync(uvs, "uvs.obj");
    ASSERT_TRUE(res);
    ASSERT_EQ(res->status, 202) << res->body;
    const json queued = json::parse(res->body);
    const json job = waitForEnd(queued["import_job_id"]);
    EXPECT_EQ(job["state"], "JOB_STATE_SUCCEEDED") << job.dump();
    ASSERT_EQ(job["import"]["warnings"].size(), 1u) << job.dump();
    EXPECT_EQ(job["import"]["warnings"][0], "3 texture coordinates read but not used (no material has a texture map)");
    const json stored = json::parse(http().Get(("/v1/scenes/" + queued["id"].get<std::string>()).c_str())->body);
    EXPECT_EQ(stored["format"], "obj");
    EXPECT_EQ(stored["import_warnings"], job["import"]["warnings"]);
}

TEST_F(ImportJobTest, SeveralUploadsImportOneAfterAnother) {
    startServer({"--backend", "embree"});
    std::vector<std::string> jobs;
    for (uint64_t triangles : {2000, 3000, 4000}) {
        const fs::path path = dir_ / ("s" + std::to_string(triangles) + ".ply");
        GenerateOptions sphere;
        sphere.kind = GeneratorKind::Sphere;
        sphere.triangles = triangles;
        ASSERT_TRUE(generateToPly(sphere, path.string()).isOk());
        auto res = putAsync(readBytes(path), path.filename().string());
        ASSERT_EQ(res->status, 202) << res->body;
        jobs.push_back(json::parse(res->body)["import_job_id"]);
    }
    double previousEnd = 0;
    for (const std::string& id : jobs) {
        const json job = waitForEnd(id);
        EXPECT_EQ(job["state"], "JOB_STATE_SUCCEEDED") << job.dump();
        // Each starts after the one before ended.
        EXPECT_GE(epochSeconds(job["start_time"]), previousEnd) << job.dump();
        previousEnd = epochSeconds(job["end_time"]);
        EXPECT_EQ(http().Get(("/v1/scenes/" + job["import"]["scene_id"].get<std::string>()).c_str())->status, 200);
    }
}

TEST_F(ImportJobTest, AFailedImportIsAFailedJobNamingTheFile) {
    startServer({"--backend", "embree"});
    auto res = putAsync("v 0 0 0\nv 1 0 0\nf 1 2 9\n", "broken.obj");
    ASSERT_EQ(res->status, 202) << res->body;
    const json queued = json::parse(res->body);
    const json job = waitForEnd(queued["import_job_id"]);
    EXPECT_EQ(job["state"], "JOB_STATE_FAILED");
    const std::string error = job["error"];
    EXPECT_EQ(error.rfind("data: broken.obj: line 3", 0), 0u) << error;
    EXPECT_EQ(http().Get(("/v1/scenes/" + queued["id"].get<std::string>()).c_str())->status, 404);
    EXPECT_TRUE(fs::is_empty(dataDir() / "tmp"));
    EXPECT_EQ(http().Put("/v1/scenes?async=maybe&name=x.obj", "v 0 0 0", "application/octet-stream")->status, 400);
}

TEST_F(ImportJobTest, GrpcAsyncUploadIsWatchedThroughRenderService) {
    startServer({"--backend", "embree"});
    auto channel = grpc::CreateChannel(server_.grpcAddress(), grpc::InsecureChannelCredentials());
    auto scenes = v1::SceneService::NewStub(channel);
    auto renders = v1::RenderService::NewStub(channel);
    v1::Scene scene;
    const grpc::Status status = uploadSceneOverGrpc(*scenes, "sphere.ply", readBytes(spherePath_), 65536, true, &scene);
    ASSERT_TRUE(status.ok()) << status.error_message();
    ASSERT_FALSE(scene.import_job_id().empty());
    grpc::ClientContext context;
    v1::WatchJobRequest watch;
    watch.set_id(scene.import_job_id());
    auto reader = renders->WatchJob(&context, watch);
    v1::WatchJobResponse response;
    v1::JobEvent last;
    while (reader->Read(&response)) last = response.event();
    EXPECT_TRUE(reader->Finish().ok());
    EXPECT_EQ(last.state(), v1::JOB_STATE_SUCCEEDED);
    grpc::ClientContext getContext;
    v1::GetSceneRequest get;
    get.set_id(scene.id());
    v1::GetSceneResponse stored;
    ASSERT_TRUE(scenes->GetScene(&getContext, get, &stored).ok());
    EXPECT_EQ(stored.scene().triangles(), 2000u);
}

// Its upload lived in tmp/, which a start empties: an import cut off by a crash fails, by name.
TEST_F(ImportJobTest, AnImportCutOffByACrashFailsAtTheNextStart) {
    startServer({"--backend", "embree"});
    auto res = putAsync(readBytes(bigMesh()), "big.ply");
    ASSERT_EQ(res->status, 202) << res->body;
    const std::string jobId = json::parse(res->body)["import_job_id"];
    server_.kill(SIGKILL);
    startServer({"--backend", "embree"});
    const json job = getJob(jobId);
    EXPECT_EQ(job["state"], "JOB_STATE_FAILED") << job.dump();
    EXPECT_NE(job["error"].get<std::string>().find("the server stopped before this import finished; upload big.ply again"),
              std::string::npos)
        << job.dump();
}

}  // namespace
}  // namespace vastray::test
