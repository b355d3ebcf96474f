#pragma once
// A fixture per test: a fresh data folder, a 2k-triangle sphere, a running `vastray serve`,
// and small HTTP helpers (cpp-httplib client) that the HTTP, gRPC and durability tests share.
#include <gtest/gtest.h>
#include <httplib.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "CommandRunner.h"
#include "ServerProcess.h"
#include "vastray/streamer/Generate.h"

namespace vastray::test {

using nlohmann::json;

class ServerTest : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = testTmpDir("server") / (std::string(info->test_suite_name()) + "." + info->name());
        std::filesystem::remove_all(dir_);
        std::filesystem::create_directories(dir_);
        spherePath_ = dir_ / "sphere.ply";
        GenerateOptions sphere;
        sphere.kind = GeneratorKind::Sphere;
        sphere.triangles = 2000;
        const Status generated = generateToPly(sphere, spherePath_.string());
        ASSERT_TRUE(generated.isOk()) << generated.message();
    }

    std::filesystem::path dataDir() const { return dir_ / "data"; }

    void startServer(const std::vector<std::string>& extra = {}) {
        ASSERT_TRUE(server_.start(dataDir(), extra)) << server_.log();
    }

    httplib::Client http() const {
        httplib::Client client("127.0.0.1", server_.httpPort());
        client.set_read_timeout(30, 0);
        if (!token_.empty()) client.set_bearer_token_auth(token_.c_str());
        return client;
    }

    // PUT /v1/scenes?name=sphere.ply; the scene's JSON.
    json uploadSphere() {
        auto res =
            http().Put("/v1/scenes?name=sphere.ply", readBytes(spherePath_), "application/octet-stream");
        EXPECT_TRUE(res);
        if (!res) return {};
        EXPECT_EQ(res->status, 200) << res->body;
        return json::parse(res->body, nullptr, false);
    }

    // POST /v1/jobs; the response (status checked by the caller).
    httplib::Result submit(const json& body, const httplib::Headers& headers = {}) {
        return http().Post("/v1/jobs", headers, body.dump(), "application/json");
    }

    json getJob(const std::string& id) {
        auto res = http().Get(("/v1/jobs/" + id).c_str());
        EXPECT_TRUE(res && res->status == 200) << (res ? res->body : "no response");
        return res ? json::parse(res->body, nullptr, false) : json();
    }

    // Polls GET /v1/jobs/ID until its state is `state` (or 60 s pass); the last JSON.
    json waitForState(const std::string& id, const std::string& state) {
        json job;
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
        while (std::chrono::steady_clock::now() < deadline) {
            job = getJob(id);
            if (job.value("state", "") == state) return job;
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        ADD_FAILURE() << "job " << id << " never reached " << state << ": " << job.dump();
        return job;
    }

    std::string result(const std::string& id) {
        auto res = http().Get(("/v1/jobs/" + id + "/result").c_str());
        EXPECT_TRUE(res && res->status == 200) << (res ? res->body : "no response");
        return res ? res->body : "";
    }

    // The same render through `vastray render --backend vulkan` on the stored package: the
    // reference image (the service renders through the Embree JobRenderer today).
    std::string cliRender(const std::string& sceneId, const std::string& flags) {
        const auto out = dir_ / ("cli-" + std::to_string(++cliRenders_) + ".png");
        const auto package = dataDir() / "scenes" / (sceneId + ".vast");
        auto run = runVastray("render " + package.string() + " -o " + out.string() +
                              " --backend vulkan --progress none " + flags);
        EXPECT_EQ(run.exitCode, 0) << run.output;
        return readBytes(out);
    }

    std::filesystem::path dir_, spherePath_;
    ServerProcess server_;
    std::string token_;
    int cliRenders_ = 0;
};

// The data of every SSE block of GET /v1/jobs/ID/events, in order (the stream ends after the
// job's final state).
inline std::vector<json> watchEvents(httplib::Client client, const std::string& jobId) {
    std::string stream;
    auto res = client.Get(("/v1/jobs/" + jobId + "/events").c_str(), [&](const char* data, size_t size) {
        stream.append(data, size);
        return true;
    });
    EXPECT_TRUE(res && res->status == 200);
    std::vector<json> events;
    for (size_t at = stream.find("data: "); at != std::string::npos; at = stream.find("data: ", at + 1))
        events.push_back(json::parse(stream.substr(at + 6, stream.find('\n', at) - at - 6)));
    return events;
}

// A small job: 32x32, 2 spp, the sphere framed by the default camera.
inline json smallJob(const std::string& sceneId) {
    return {{"scene_id", sceneId}, {"width", 32}, {"height", 32}, {"spp", 2}};
}

// A job large enough to be caught RUNNING by a 20 ms poll, and on a two-worker server to run
// while the other worker runs another: 128x128, 16 spp (lavapipe, 2 cores: ~1-2 s of pipeline
// builds, then ~1-2 s of walk and shade kernels; the 160x160, 48 spp job before it took 6-7 s
// of CPU a render, and some tests render it six times). kSlowJobFlags: the same job for
// `vastray render` (cliRender).
inline json slowJob(const std::string& sceneId) {
    return {{"scene_id", sceneId}, {"width", 128}, {"height", 128}, {"spp", 16}};
}
inline const std::string kSlowJobFlags = "--resolution 128x128 --spp 16";

// The message of an HTTP error body ({"error": {"message": ...}}); empty without one.
inline std::string errorMessage(const httplib::Result& res) {
    auto body = json::parse(res ? res->body : "", nullptr, false);
    return body.is_object() && body.contains("error") ? body["error"].value("message", "") : "";
}

}  // namespace vastray::test
