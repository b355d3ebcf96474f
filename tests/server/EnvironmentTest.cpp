// Environment maps in the service (SceneService.UploadEnvironment, SubmitJobRequest.environment):
// uploads decoded by the CLI's reader and refused by name and limit, the resource listed, fetched
// and deleted, jobs lit by the map exactly as `vastray render --environment` lights them (both
// backends), the map's device bytes kept from the job's budget, and a queued job's environment
// kept over a restart.
#include <grpcpp/grpcpp.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>

#include <array>
#include <cmath>
#include <fstream>

#include "ServerTestSupport.h"
#include "vastray/core/ImageFile.h"
#include "vastray/core/RenderImage.h"
#include "vastray/server/Sha256.h"
#include "vastray/v1/render_service.grpc.pb.h"
#include "vastray/v1/scene_service.grpc.pb.h"

namespace vastray::test {
namespace {

namespace fs = std::filesystem;

// The constant map's radiance: every texel (R, G, B), each channel far from the default sky's.
constexpr float kTexel[3] = {2.0f, 0.0625f, 3.0f};

// A w x h OpenEXR of 32-bit float R, G, B (the image writer of `vastray render`), every texel
// `texel` but (x, y) = `odd` when given.
std::string writeExr(const fs::path& path, uint32_t w, uint32_t h, const float* texel, int oddX = -1,
                     float odd = 0) {
    RenderImage image;
    image.allocate(w, h, 0);
    for (uint64_t i = 0; i < image.pixelCount(); ++i)
        for (int c = 0; c < 3; ++c) image.rgb[3 * i + c] = int64_t(i) == oddX ? odd : texel[c];
    std::fill(image.alpha.begin(), image.alpha.end(), 1.0f);
    const Status written = writeImageFile(path.string(), image);
    EXPECT_TRUE(written.isOk()) << written.message();
    return readBytes(path);
}

// A w x h Radiance .hdr, flat (not run-length encoded) scanlines, every texel RGBE 80 80 80 81
// (1.0 in each channel).
std::string hdrBytes(uint32_t w, uint32_t h) {
    std::string bytes =
        "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " + std::to_string(h) + " +X " + std::to_string(w) + "\n";
    for (uint64_t i = 0; i < uint64_t(w) * h; ++i) bytes += std::string("\x80\x80\x80\x81", 4);
    return bytes;
}

// The mean of each of R, G, B of an EXR.
std::array<double, 3> channelMeans(const fs::path& exr) {
    auto rgb = readImageChannels(exr.string(), {"R", "G", "B"});
    EXPECT_TRUE(rgb.isOk()) << rgb.message();
    std::array<double, 3> mean{};
    if (!rgb) return mean;
    for (int c = 0; c < 3; ++c) {
        for (float v : rgb->planes[c]) mean[c] += v;
        mean[c] /= double(rgb->planes[c].size());
    }
    return mean;
}

// Sends `request` (all of it, at once: it fits the loopback socket's buffers, so the server has
// it before it answers) over a connection of its own; what the server answers before it closes
// (at most 5 s).
std::string rawExchange(int port, const std::string& request) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(uint16_t(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    std::string answer;
    if (fd >= 0 && ::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0) {
        timeval timeout{5, 0};
        ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
        if (::send(fd, request.data(), request.size(), MSG_NOSIGNAL) == ssize_t(request.size())) {
            char buffer[4096];
            for (ssize_t n; (n = ::recv(fd, buffer, sizeof buffer, 0)) > 0;) answer.append(buffer, size_t(n));
        }
    }
    if (fd >= 0) ::close(fd);
    return answer;
}

// A PUT of `target` whose headers are `headers` and whose body is `body`.
std::string rawPut(int port, const std::string& target, const std::string& headers, const std::string& body = "") {
    return rawExchange(port, "PUT " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\n" + headers +
                                 "Content-Type: application/octet-stream\r\nConnection: close\r\n\r\n" + body);
}

// `data` as one chunk of a chunked body, and the last chunk.
std::string oneChunk(const std::string& data) {
    char size[32];
    std::snprintf(size, sizeof size, "%zx\r\n", data.size());
    return size + data + "\r\n0\r\n\r\n";
}

class EnvironmentTest : public ServerTest {
protected:
    httplib::Result putEnvironment(const std::string& name, const std::string& bytes) {
        return http().Put(("/v1/environments?name=" + name).c_str(), bytes, "application/octet-stream");
    }

    // Uploads `bytes` as `name`; the stored environment's JSON.
    json uploadEnvironment(const std::string& name, const std::string& bytes) {
        auto res = putEnvironment(name, bytes);
        EXPECT_TRUE(res);
        if (!res) return {};
        EXPECT_EQ(res->status, 200) << res->body;
        return json::parse(res->body, nullptr, false);
    }

    // The constant map as sky.exr, uploaded; its id.
    std::string uploadConstantSky() {
        writeExr(skyPath(), 16, 8, kTexel);
        return uploadEnvironment("sky.exr", readBytes(skyPath()))["id"];
    }
    fs::path skyPath() const { return dir_ / "sky.exr"; }

    // Submits `body`, waits for SUCCEEDED; the result's bytes ("" otherwise).
    std::string render(const json& body) {
        auto res = submit(body);
        EXPECT_TRUE(res && res->status == 202) << (res ? res->body : "no response");
        if (!res || res->status != 202) return "";
        const std::string id = json::parse(res->body)["id"];
        if (waitForState(id, "JOB_STATE_SUCCEEDED")["state"] != "JOB_STATE_SUCCEEDED") return "";
        return result(id);
    }

    std::string cliRenderWith(const std::string& backend, const std::string& sceneId, const std::string& flags) {
        const auto out = dir_ / ("cli-" + backend + "-" + std::to_string(++cliRenders_) + ".png");
        const auto package = dataDir() / "scenes" / (sceneId + ".vast");
        auto run = runVastray("render " + package.string() + " -o " + out.string() + " --backend " + backend +
                              " --progress none " + flags);
        EXPECT_EQ(run.exitCode, 0) << run.output;
        return readBytes(out);
    }

    // Every pixel's camera ray misses the sphere (it lies behind the eye) and reads the map: the
    // image's mean is the map's texel times the scale. Checked on the server's backend.
    void checkMeanOfAMissOnlyImage(const std::string& sceneId, const std::string& environmentId) {
        json body = smallJob(sceneId);
        body["output_format"] = "exr";
        body["camera"] = {{"eye", {0, 0, 10}}, {"target", {0, 0, 20}}};
        const std::string sky = render(body);
        body["environment"] = {{"id", environmentId}, {"scale", 2}, {"rotation_degrees", 45}};
        const std::string lit = render(body);
        ASSERT_FALSE(sky.empty());
        ASSERT_FALSE(lit.empty());
        std::ofstream(dir_ / "sky-job.exr", std::ios::binary) << sky;
        std::ofstream(dir_ / "lit-job.exr", std::ios::binary) << lit;
        const auto skyMean = channelMeans(dir_ / "sky-job.exr"), litMean = channelMeans(dir_ / "lit-job.exr");
        for (int c = 0; c < 3; ++c) {
            // Each sample of each pixel reads the one texel value times 2 (a power of two: exact),
            // and the mean of equal floats is that float; 1e-6 allows another summation order.
            EXPECT_NEAR(litMean[c], 2.0 * kTexel[c], 1e-6) << "channel " << c;
            EXPECT_GT(std::fabs(skyMean[c] - 2.0 * kTexel[c]), 0.05)
                << "the sky alone gives the same mean, channel " << c;
        }
    }
};

TEST_F(EnvironmentTest, UploadGetListAndDeleteOverHttp) {
    startServer();
    const std::string exr = writeExr(skyPath(), 16, 8, kTexel);
    const json stored = uploadEnvironment("sky.exr", exr);
    EXPECT_EQ(stored["id"], server::sha256Hex(exr.data(), exr.size())) << "content-addressed";
    EXPECT_EQ(stored["name"], "sky.exr");
    EXPECT_EQ(stored["format"], "exr");
    EXPECT_EQ(stored["width"], 16);
    EXPECT_EQ(stored["height"], 8);
    EXPECT_EQ(stored["upload_bytes"], std::to_string(exr.size()));
    // rgb and density per texel, the marginal (h + 1) and conditional (h (w + 1)) CDFs, 4 bytes each.
    EXPECT_EQ(stored["device_bytes"], std::to_string(4 * (16 * 8 * 4 + 9 + 8 * 17)));
    EXPECT_EQ(uploadEnvironment("again.exr", exr)["name"], "sky.exr") << "known content returns the stored one";
    const json hdr = uploadEnvironment("studio.hdr", hdrBytes(8, 4));
    EXPECT_EQ(hdr["format"], "hdr");
    EXPECT_EQ(hdr["width"], 8);
    EXPECT_EQ(hdr["height"], 4);

    auto got = http().Get(("/v1/environments/" + std::string(stored["id"])).c_str());
    ASSERT_TRUE(got && got->status == 200) << (got ? got->body : "");
    EXPECT_EQ(json::parse(got->body), stored);
    auto first = http().Get("/v1/environments?page_size=1");
    ASSERT_TRUE(first && first->status == 200);
    const json page = json::parse(first->body);
    ASSERT_EQ(page["environments"].size(), 1u);
    EXPECT_EQ(page["environments"][0]["id"], stored["id"]) << "oldest first";
    const std::string next = page["next_page_token"];
    auto second = http().Get(("/v1/environments?page_size=1&page_token=" + next).c_str());
    ASSERT_TRUE(second && second->status == 200);
    EXPECT_EQ(json::parse(second->body)["environments"][0]["id"], hdr["id"]);

    auto removed = http().Delete(("/v1/environments/" + std::string(stored["id"])).c_str());
    ASSERT_TRUE(removed && removed->status == 200) << (removed ? removed->body : "");
    auto gone = http().Get(("/v1/environments/" + std::string(stored["id"])).c_str());
    ASSERT_TRUE(gone);
    EXPECT_EQ(gone->status, 404);
    EXPECT_FALSE(fs::exists(dataDir() / "environments" / (std::string(stored["id"]) + ".exr")));
    EXPECT_TRUE(fs::exists(dataDir() / "environments" / (std::string(hdr["id"]) + ".hdr")));
    auto badId = http().Get("/v1/environments/nothex");
    ASSERT_TRUE(badId);
    EXPECT_EQ(badId->status, 400);
}

// Garbage, a wrong format, sizes past the CLI's limits, NaN texels and uploads over the size
// limit: each refused naming the file (or the field) and the limit; nothing is stored.
TEST_F(EnvironmentTest, GarbageAndOversizedFilesAreRefusedByName) {
    startServer({"--max-upload", "64KiB"});
    const float nan[3] = {1, 1, 1};
    const std::vector<std::tuple<std::string, std::string, int, std::string>> cases{
        {"text.exr", "not an image at all", 400, "text.exr: not an OpenEXR file"},
        {"fake.exr", std::string("\x76\x2f\x31\x01", 4) + std::string(200, 'x'), 400, "fake.exr"},
        {"studio.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 8\n\x80\x80", 400, "studio.hdr"},
        {"sky.png", "\x89PNG", 400, "name: 'sky.png': an environment map is an OpenEXR (.exr) or Radiance (.hdr) file"},
        {"empty.exr", "", 400, "empty.exr: the upload is empty"},
        {"wide.exr", writeExr(dir_ / "wide.exr", 16385, 1, kTexel), 400,
         "wide.exr: an environment map of 16385x1 texels is outside the limits (each side 1 to 16384"},
        {"nan.exr", writeExr(dir_ / "nan.exr", 4, 2, nan, 5, std::nanf("")), 400, "nan.exr: texel (1, 1)"},
        {"a/b.exr", "x", 400, "name: a file name without '/'"},
    };
    for (const auto& [name, bytes, status, message] : cases) {
        auto res = putEnvironment(name, bytes);
        ASSERT_TRUE(res) << name;
        EXPECT_EQ(res->status, status) << name << ": " << res->body;
        EXPECT_NE(res->body.find(message), std::string::npos) << name << ": " << res->body;
    }
    // Over the limit by its Content-Length: refused from the headers, before a byte of the body
    // (none is sent here, so no refusal can cut a write short).
    const std::string refused =
        rawPut(server_.httpPort(), "/v1/environments?name=big.exr", "Content-Length: 71680\r\n");
    EXPECT_NE(refused.find("HTTP/1.1 413"), std::string::npos) << refused;
    EXPECT_NE(refused.find("a body of 71680 bytes exceeds the 65536-byte limit of PUT /v1/environments"),
              std::string::npos)
        << refused;
    // Past the limit without a Content-Length (chunked): one chunk of 100 bytes more than the
    // limit, sent whole before the server answers (a refusal cannot cut a write short).
    const std::string chunked = rawPut(server_.httpPort(), "/v1/environments?name=chunked.exr",
                                       "Transfer-Encoding: chunked\r\n", oneChunk(std::string((64 << 10) + 100, 'x')));
    EXPECT_EQ(chunked.rfind("HTTP/1.1 413", 0), 0u) << chunked;
    EXPECT_NE(chunked.find("chunked.exr: the upload was cut off before its end (a chunked body over the "
                           "65536-byte limit of PUT /v1/environments"),
              std::string::npos)
        << chunked;
    // The same for a scene: a chunked body past --max-upload is refused, not stored cut short.
    const std::string header = "ply\nformat ascii 1.0\ncomment ";
    const std::string scene =
        rawPut(server_.httpPort(), "/v1/scenes?name=chunked.ply", "Transfer-Encoding: chunked\r\n",
               oneChunk(header + std::string((64 << 10) + 100 - header.size() - 1, 'x') + "\n"));
    EXPECT_EQ(scene.rfind("HTTP/1.1 413", 0), 0u) << scene;
    EXPECT_NE(scene.find("chunked.ply: the upload was cut off before its end (a chunked body over the 65536-byte "
                         "limit of PUT /v1/scenes"),
              std::string::npos)
        << scene;
    // gRPC counts the stream's bytes against the same limit.
    {
        auto stub =
            v1::SceneService::NewStub(grpc::CreateChannel(server_.grpcAddress(), grpc::InsecureChannelCredentials()));
        grpc::ClientContext context;
        v1::UploadEnvironmentResponse response;
        auto writer = stub->UploadEnvironment(&context, &response);
        v1::UploadEnvironmentRequest message;
        message.set_name("streamed.exr");
        message.set_data(std::string(10 << 10, 'x'));
        for (int i = 0; i < 7 && writer->Write(message); ++i) message.clear_name();  // 70 KiB
        writer->WritesDone();
        const grpc::Status status = writer->Finish();
        EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();
        EXPECT_NE(status.error_message().find("streamed.exr: upload exceeds the server's limit of 65536 bytes"),
                  std::string::npos)
            << status.error_message();
    }
    auto list = http().Get("/v1/environments");
    ASSERT_TRUE(list && list->status == 200);
    EXPECT_TRUE(json::parse(list->body).value("environments", json::array()).empty()) << list->body;
    EXPECT_TRUE(fs::is_empty(dataDir() / "tmp"));
    EXPECT_FALSE(fs::exists(dataDir() / "environments") && !fs::is_empty(dataDir() / "environments"));
}

// The job's environment reaches the vulkan renderer as `vastray render --environment FILE
// --environment-scale S --environment-rotate R` gives it: the same bytes; and a constant map
// makes a miss-only image's mean the texel times the scale.
TEST_F(EnvironmentTest, VulkanJobIsLitAsTheCliLightsIt) {
    startServer();
    const std::string sceneId = uploadSphere()["id"];
    const std::string environmentId = uploadConstantSky();
    json body = smallJob(sceneId);
    body["environment"] = {{"id", environmentId}, {"scale", 0.5}, {"rotation_degrees", 30}};
    const std::string lit = render(body);
    ASSERT_FALSE(lit.empty());
    const std::string flags = "--resolution 32x32 --spp 2";
    EXPECT_EQ(lit, cliRenderWith("vulkan", sceneId,
                                 flags + " --environment " + skyPath().string() +
                                     " --environment-scale 0.5 --environment-rotate 30"));
    EXPECT_NE(lit, cliRender(sceneId, flags)) << "the environment changes nothing";
    checkMeanOfAMissOnlyImage(sceneId, environmentId);
}

TEST_F(EnvironmentTest, EmbreeJobIsLitAsTheCliLightsIt) {
    startServer({"--backend", "embree"});
    const std::string sceneId = uploadSphere()["id"];
    const std::string environmentId = uploadConstantSky();
    json body = smallJob(sceneId);
    body["environment"] = {{"id", environmentId}, {"rotation_degrees", -90}};
    body["sun"] = {{"direction", {0, 1, 0}}, {"intensity", 2}};
    const std::string lit = render(body);
    ASSERT_FALSE(lit.empty());
    const std::string flags = "--resolution 32x32 --spp 2 --sun 0,1,0,2";
    EXPECT_EQ(lit, cliRenderWith("embree", sceneId, flags + " --environment " + skyPath().string() +
                                                          " --environment-rotate -90"));
    EXPECT_NE(lit, cliRenderWith("embree", sceneId, flags)) << "the environment changes nothing";
    checkMeanOfAMissOnlyImage(sceneId, environmentId);
}

// The fields are checked with the CLI's ranges and stored with their defaults; an unknown map is
// NOT_FOUND; a map a queued job uses cannot be deleted.
TEST_F(EnvironmentTest, JobFieldsAreCheckedStoredAndKeepTheirMap) {
    startServer({"--paused"});
    const std::string sceneId = uploadSphere()["id"];
    const std::string environmentId = uploadConstantSky();
    const std::vector<std::pair<json, std::string>> bad{
        {{{"scale", 2}}, "environment.id: required"},
        {{{"id", "abc"}}, "environment.id: expected 64 lowercase hex digits"},
        {{{"id", environmentId}, {"scale", -1}}, "environment.scale: -1.000000 is outside [0, 1e18]"},
        {{{"id", environmentId}, {"scale", 2e18}}, "environment.scale"},
        {{{"id", environmentId}, {"rotation_degrees", 400}},
         "environment.rotation_degrees: 400.000000 is outside [-360, 360]"},
        {{{"id", environmentId}, {"rotation_degrees", "NaN"}}, "environment.rotation_degrees"},
    };
    for (const auto& [environment, message] : bad) {
        json body = smallJob(sceneId);
        body["environment"] = environment;
        auto res = submit(body);
        ASSERT_TRUE(res);
        EXPECT_EQ(res->status, 400) << environment.dump() << ": " << res->body;
        EXPECT_NE(res->body.find(message), std::string::npos) << res->body;
    }
    json ao = smallJob(sceneId);
    ao["integrator"] = "ao";
    ao["environment"] = {{"id", environmentId}};
    auto aoRes = submit(ao);
    ASSERT_TRUE(aoRes);
    EXPECT_EQ(aoRes->status, 400);
    EXPECT_NE(aoRes->body.find("integrator ao has no lights"), std::string::npos) << aoRes->body;
    json unknown = smallJob(sceneId);
    unknown["environment"] = {{"id", std::string(64, 'e')}};
    auto unknownRes = submit(unknown);
    ASSERT_TRUE(unknownRes);
    EXPECT_EQ(unknownRes->status, 404);
    EXPECT_NE(unknownRes->body.find("environment.id: no environment eeee"), std::string::npos) << unknownRes->body;

    json body = smallJob(sceneId);
    body["environment"] = {{"id", environmentId}};
    auto res = submit(body);
    ASSERT_TRUE(res && res->status == 202) << (res ? res->body : "");
    const json stored = json::parse(res->body)["request"]["environment"];
    EXPECT_EQ(stored["id"], environmentId);
    EXPECT_EQ(stored["scale"], 1) << "absent scale is 1";
    auto refused = http().Delete(("/v1/environments/" + environmentId).c_str());
    ASSERT_TRUE(refused);
    EXPECT_EQ(refused->status, 409) << refused->body;
    EXPECT_NE(refused->body.find("is used by job-"), std::string::npos) << refused->body;
}

// A queued job's environment survives a restart: the next start renders it lit by its map.
TEST_F(EnvironmentTest, AQueuedJobRendersWithItsMapAfterARestart) {
    startServer({"--paused"});
    const std::string sceneId = uploadSphere()["id"];
    const std::string environmentId = uploadConstantSky();
    json body = smallJob(sceneId);
    body["environment"] = {{"id", environmentId}, {"scale", 4}};
    auto res = submit(body);
    ASSERT_TRUE(res && res->status == 202) << (res ? res->body : "");
    const std::string jobId = json::parse(res->body)["id"];
    server_.kill(SIGKILL);
    startServer();
    const json job = waitForState(jobId, "JOB_STATE_SUCCEEDED");
    EXPECT_EQ(job["request"]["environment"]["scale"], 4);
    EXPECT_EQ(result(jobId), cliRender(sceneId, "--resolution 32x32 --spp 2 --environment " + skyPath().string() +
                                                    " --environment-scale 4"));
}

// The map's device bytes are kept from the job's budget (vulkan): a job whose budget cannot hold
// the map beside the scene's smallest pool fails at its first attempt (the same map would not fit
// again: not retried, though --max-attempts allows 3), naming the map, its device bytes and the
// budget; the same job without the map renders in that budget, and a job with a small map stays
// within it. A budget below the scene's own minimum fails at once too, naming the job's field.
TEST_F(EnvironmentTest, TheMapCountsAgainstTheJobsMemoryBudget) {
    startServer({"--max-attempts", "3"});
    const std::string sceneId = uploadSphere()["id"];
    writeExr(dir_ / "large.exr", 2048, 1024, kTexel);  // 2M texels: about 42 MB on the device
    const json large = uploadEnvironment("large.exr", readBytes(dir_ / "large.exr"));
    const std::string mapBytes = large["device_bytes"];
    ASSERT_GT(std::stoull(mapBytes), 40ull << 20);
    json body = smallJob(sceneId);
    body["memory_budget_bytes"] = std::to_string(32ull << 20);
    ASSERT_FALSE(render(body).empty()) << "the sphere renders in 32 MiB";
    body["environment"] = {{"id", large["id"]}};
    auto res = submit(body);
    ASSERT_TRUE(res && res->status == 202) << (res ? res->body : "");
    const json failed = waitForState(json::parse(res->body)["id"], "JOB_STATE_FAILED");
    EXPECT_EQ(failed["attempts"], 1) << "a map over the budget is not retried: " << failed.dump();
    EXPECT_EQ(failed["attempt_errors"].size(), 1u) << failed.dump();
    const std::string error = failed.value("error", "");
    for (const std::string& part : {"environment map " + std::string(large["id"]) + " (large.exr)",
                                    " = " + mapBytes + " bytes of device memory",
                                    std::string("memory_budget_bytes of 32.0 MiB = 33554432 bytes")})
        EXPECT_NE(error.find(part), std::string::npos) << "missing '" << part << "' in " << error;

    body["environment"] = {{"id", uploadConstantSky()}};
    auto small = submit(body);
    ASSERT_TRUE(small && small->status == 202);
    const json done = waitForState(json::parse(small->body)["id"], "JOB_STATE_SUCCEEDED");
    const uint64_t peak = std::stoull(std::string(done["stats"]["peak_device_bytes"]));
    EXPECT_GT(peak, 0u);
    EXPECT_LE(peak, 32ull << 20);

    body.erase("environment");
    body["memory_budget_bytes"] = "65536";
    auto tiny = submit(body);
    ASSERT_TRUE(tiny && tiny->status == 202) << (tiny ? tiny->body : "");
    const json refused = waitForState(json::parse(tiny->body)["id"], "JOB_STATE_FAILED");
    EXPECT_EQ(refused["attempts"], 1) << "a budget below the minimum is not retried: " << refused.dump();
    const std::string below = "memory_budget_bytes 64.0 KiB is below this scene's minimum of ";
    EXPECT_NE(refused.value("error", "").find(below), std::string::npos) << refused.dump();
}

// One open pool per scene (vulkan): a job whose map needs more than the scene's open pool kept
// replaces that pool (closed, not left beside the new one until least recently used), and a job
// refused because its map does not fit its budget leaves the open pool as it was: the next job
// with a map that fits loads no chunk. /metrics vastray_device_scenes_open counts the open pools.
TEST_F(EnvironmentTest, ALargerMapReplacesTheScenesPoolAndARefusedOneKeepsIt) {
    startServer();
    const std::string sceneId = uploadSphere()["id"];
    const std::string smallId = uploadConstantSky();  // 16x8: about 3 KB on the device
    writeExr(dir_ / "medium.exr", 256, 128, kTexel);  // about 640 KB
    const std::string mediumId = uploadEnvironment("medium.exr", readBytes(dir_ / "medium.exr"))["id"];
    writeExr(dir_ / "large.exr", 2048, 1024, kTexel);  // about 40 MB: over the 32 MiB budget
    const std::string largeId = uploadEnvironment("large.exr", readBytes(dir_ / "large.exr"))["id"];
    auto run = [&](const std::string& environmentId, const std::string& state) {
        json body = smallJob(sceneId);
        body["memory_budget_bytes"] = std::to_string(32ull << 20);
        body["environment"] = {{"id", environmentId}};
        auto res = submit(body);
        EXPECT_TRUE(res && res->status == 202) << (res ? res->body : "no response");
        return res && res->status == 202 ? waitForState(json::parse(res->body)["id"], state) : json();
    };
    auto loads = [](const json& job) {
        return std::stoull(job.value("stats", json::object()).value("chunk_loads", std::string("0")));
    };
    auto scenesOpen = [&] {
        auto metrics = http().Get("/metrics");
        const std::string name = "\nvastray_device_scenes_open ";
        const size_t at = metrics ? metrics->body.find(name) : std::string::npos;
        return at == std::string::npos ? -1.0 : std::stod(metrics->body.substr(at + name.size()));
    };
    EXPECT_GT(loads(run(smallId, "JOB_STATE_SUCCEEDED")), 0u);
    EXPECT_EQ(scenesOpen(), 1);
    EXPECT_GT(loads(run(mediumId, "JOB_STATE_SUCCEEDED")), 0u) << "the open pool kept too little for the map";
    EXPECT_EQ(scenesOpen(), 1) << "the scene's first pool should be closed, not kept beside the second";
    EXPECT_EQ(run(largeId, "JOB_STATE_FAILED")["attempts"], 1);
    EXPECT_EQ(scenesOpen(), 1);
    EXPECT_EQ(loads(run(mediumId, "JOB_STATE_SUCCEEDED")), 0u) << "the refused job closed the open pool";
    EXPECT_EQ(loads(run(smallId, "JOB_STATE_SUCCEEDED")), 0u) << "the pool keeps enough for a smaller map";
    EXPECT_EQ(scenesOpen(), 1);
}

// gRPC: UploadEnvironment as a client stream, GetEnvironment, ListEnvironments, a job with the
// map, DeleteEnvironment.
TEST_F(EnvironmentTest, GrpcUploadListSubmitAndDelete) {
    startServer();
    const std::string sceneId = uploadSphere()["id"];
    const std::string exr = writeExr(skyPath(), 16, 8, kTexel);
    auto channel = grpc::CreateChannel(server_.grpcAddress(), grpc::InsecureChannelCredentials());
    auto scenes = v1::SceneService::NewStub(channel);
    v1::UploadEnvironmentResponse uploaded;
    {
        grpc::ClientContext context;
        auto writer = scenes->UploadEnvironment(&context, &uploaded);
        v1::UploadEnvironmentRequest message;
        message.set_name("sky.exr");
        for (size_t at = 0; at < exr.size(); at += 100) {
            message.set_data(exr.substr(at, 100));
            ASSERT_TRUE(writer->Write(message));
            message.clear_name();
        }
        writer->WritesDone();
        const grpc::Status status = writer->Finish();
        ASSERT_TRUE(status.ok()) << status.error_message();
    }
    EXPECT_EQ(uploaded.environment().id(), server::sha256Hex(exr.data(), exr.size()));
    EXPECT_EQ(uploaded.environment().width(), 16u);
    {
        grpc::ClientContext context;
        v1::ListEnvironmentsResponse list;
        ASSERT_TRUE(scenes->ListEnvironments(&context, v1::ListEnvironmentsRequest(), &list).ok());
        ASSERT_EQ(list.environments_size(), 1);
        EXPECT_EQ(list.environments(0).name(), "sky.exr");
    }
    {
        grpc::ClientContext context;
        v1::GetEnvironmentRequest get;
        get.set_id(std::string(64, 'f'));
        v1::GetEnvironmentResponse got;
        EXPECT_EQ(scenes->GetEnvironment(&context, get, &got).error_code(), grpc::StatusCode::NOT_FOUND);
    }
    {
        grpc::ClientContext context;
        v1::UploadEnvironmentResponse refused;
        auto writer = scenes->UploadEnvironment(&context, &refused);
        v1::UploadEnvironmentRequest message;
        message.set_name("garbage.hdr");
        message.set_data("#?RADIANCE\nnonsense");
        ASSERT_TRUE(writer->Write(message));
        writer->WritesDone();
        const grpc::Status status = writer->Finish();
        EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
        EXPECT_NE(status.error_message().find("garbage.hdr"), std::string::npos) << status.error_message();
    }
    auto renders = v1::RenderService::NewStub(channel);
    v1::SubmitJobRequest request;
    request.set_scene_id(sceneId);
    request.set_width(32);
    request.set_height(32);
    request.set_spp(2);
    request.mutable_environment()->set_id(uploaded.environment().id());
    request.mutable_environment()->set_scale(0.5f);
    v1::SubmitJobResponse submitted;
    {
        grpc::ClientContext context;
        const grpc::Status status = renders->SubmitJob(&context, request, &submitted);
        ASSERT_TRUE(status.ok()) << status.error_message();
    }
    waitForState(submitted.job().id(), "JOB_STATE_SUCCEEDED");
    EXPECT_EQ(result(submitted.job().id()),
              cliRender(sceneId, "--resolution 32x32 --spp 2 --environment " + skyPath().string() +
                                     " --environment-scale 0.5"));
    grpc::ClientContext context;
    v1::DeleteEnvironmentRequest remove;
    remove.set_id(uploaded.environment().id());
    v1::DeleteEnvironmentResponse removed;
    const grpc::Status status = scenes->DeleteEnvironment(&context, remove, &removed);
    EXPECT_TRUE(status.ok()) << status.error_message();
}

}  // namespace
}  // namespace vastray::test
