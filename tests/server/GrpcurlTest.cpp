// The gRPC front end through `grpcurl`, the generic client operators reach for, with no .proto
// files: everything it knows of the API comes from server reflection. grpcurl is a Go tool that
// scripts/install-deps.sh builds into /usr/local/bin; without it these tests FAIL (never skip).
// The binary is $GRPCURL when set, else `grpcurl` on PATH, else /usr/local/bin/grpcurl.
#include <grpcpp/support/status_code_enum.h>
#include <unistd.h>

#include <cstdlib>
#include <sstream>

#include "ServerTestSupport.h"

namespace vastray::test {
namespace {

std::string findGrpcurl() {
    if (const char* env = std::getenv("GRPCURL"); env && *env) return ::access(env, X_OK) == 0 ? env : "";
    std::string path = std::getenv("PATH") ? std::getenv("PATH") : "";
    path += ":/usr/local/bin";  // where scripts/install-deps.sh installs it
    std::stringstream dirs(path);
    for (std::string dir; std::getline(dirs, dir, ':');) {
        if (dir.empty()) continue;
        const std::string candidate = dir + "/grpcurl";
        if (::access(candidate.c_str(), X_OK) == 0) return candidate;
    }
    return "";
}

// 'text' for /bin/sh.
std::string shellQuote(const std::string& text) {
    std::string quoted = "'";
    for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

std::string base64(const std::string& bytes) {
    static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16 | uint32_t(uint8_t(bytes[i + 1])) << 8 | uint8_t(bytes[i + 2]);
        for (int shift : {18, 12, 6, 0}) out += digits[(v >> shift) & 63];
    }
    if (i + 1 == bytes.size()) {
        const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
        out += std::string{digits[(v >> 18) & 63], digits[(v >> 12) & 63], '=', '='};
    } else if (i + 2 == bytes.size()) {
        const uint32_t v = uint32_t(uint8_t(bytes[i])) << 16 | uint32_t(uint8_t(bytes[i + 1])) << 8;
        out += std::string{digits[(v >> 18) & 63], digits[(v >> 12) & 63], digits[(v >> 6) & 63], '='};
    }
    return out;
}

std::string unbase64(const std::string& text) {
    std::string out;
    uint32_t bits = 0;
    int count = 0;
    for (char c : text) {
        int v = -1;
        if (c >= 'A' && c <= 'Z') v = c - 'A';
        else if (c >= 'a' && c <= 'z') v = c - 'a' + 26;
        else if (c >= '0' && c <= '9') v = c - '0' + 52;
        else if (c == '+' || c == '-') v = 62;
        else if (c == '/' || c == '_') v = 63;
        if (v < 0) continue;  // padding
        bits = bits << 6 | uint32_t(v);
        if ((count += 6) >= 8) {
            count -= 8;
            out += char((bits >> count) & 0xff);
        }
    }
    return out;
}

// The JSON messages grpcurl printed, one after the other (a stream gives several).
std::vector<json> messages(const std::string& output) {
    std::vector<json> out;
    std::istringstream in(output);
    while (in >> std::ws && in.peek() == '{') {
        json message;
        try {
            in >> message;
        } catch (const json::exception&) {
            break;
        }
        out.push_back(std::move(message));
    }
    return out;
}

using GrpcurlRun = CommandResult;

class GrpcurlTest : public ServerTest {
protected:
    void SetUp() override {
        ServerTest::SetUp();
        grpcurl_ = findGrpcurl();
        const char* env = std::getenv("GRPCURL");
        ASSERT_FALSE(grpcurl_.empty())
            << (env && *env ? "$GRPCURL=" + std::string(env) + " is not an executable"
                            : std::string("grpcurl not found on PATH or in /usr/local/bin"))
            << ": run scripts/install-deps.sh, which builds grpcurl from the Go module proxy into /usr/local/bin";
    }

    // grpcurl -plaintext [-H authorization] FLAGS... ADDRESS ARGS... [< stdinFile]
    GrpcurlRun grpcurl(const std::vector<std::string>& flags, const std::vector<std::string>& args,
                       const std::string& stdinFile = "") {
        std::string command = shellQuote(grpcurl_) + " -plaintext -max-time 60";
        if (!header_.empty()) command += " -H " + shellQuote(header_);
        for (const auto& f : flags) command += " " + shellQuote(f);
        command += " " + server_.grpcAddress();
        for (const auto& a : args) command += " " + shellQuote(a);
        command += stdinFile.empty() ? " < /dev/null" : " < " + shellQuote(stdinFile);
        return runShell(command);
    }

    // A unary call with a JSON request; its one reply (checked OK).
    json call(const std::string& method, const json& request) {
        const GrpcurlRun run = grpcurl({"-d", request.dump()}, {method});
        EXPECT_EQ(run.exitCode, 0) << method << ": " << run.output;
        const auto replies = messages(run.output);
        EXPECT_EQ(replies.size(), 1u) << method << ": " << run.output;
        return replies.empty() ? json() : replies.front();
    }

    // The sphere as a client stream of UploadSceneRequest messages, `chunk` bytes each.
    GrpcurlRun uploadSphere(size_t chunk, size_t* messageCount) {
        const std::string bytes = readBytes(spherePath_);
        const auto file = dir_ / "upload.jsonl";
        std::ofstream out(file);
        *messageCount = 0;
        for (size_t at = 0; at < bytes.size(); at += chunk, ++*messageCount) {
            json message = {{"data", base64(bytes.substr(at, chunk))}};
            if (at == 0) message["name"] = "sphere.ply";
            out << message.dump() << "\n";
        }
        out.close();
        return grpcurl({"-d", "@"}, {"vastray.v1.SceneService/UploadScene"}, file.string());
    }

    std::string grpcurl_, header_;
};

// grpcurl exits with 64 + the gRPC status code when the call fails.
constexpr int kGrpcurlStatusOffset = 64;

TEST_F(GrpcurlTest, DrivesTheServiceThroughReflection) {
    startServer({"--backend", "vulkan"});

    const GrpcurlRun list = grpcurl({}, {"list"});
    ASSERT_EQ(list.exitCode, 0) << list.output;
    for (const char* service : {"vastray.v1.SceneService", "vastray.v1.RenderService", "grpc.health.v1.Health"})
        EXPECT_NE(list.output.find(std::string(service) + "\n"), std::string::npos) << service << ": " << list.output;
    const GrpcurlRun methods = grpcurl({}, {"list", "vastray.v1.RenderService"});
    for (const char* method : {"SubmitJob", "GetJob", "ListJobs", "WatchJob", "CancelJob", "GetResult"})
        EXPECT_NE(methods.output.find(std::string("vastray.v1.RenderService.") + method + "\n"), std::string::npos)
            << method << ": " << methods.output;

    const GrpcurlRun method = grpcurl({}, {"describe", "vastray.v1.RenderService.SubmitJob"});
    EXPECT_EQ(method.exitCode, 0) << method.output;
    EXPECT_NE(method.output.find("vastray.v1.RenderService.SubmitJob is a method:"), std::string::npos)
        << method.output;
    EXPECT_NE(
        method.output.find(
            "rpc SubmitJob ( .vastray.v1.SubmitJobRequest ) returns ( .vastray.v1.SubmitJobResponse );"),
        std::string::npos)
        << method.output;
    // The method's comment from render_service.proto (reflection sends the files with comments).
    EXPECT_NE(method.output.find("// Validates and queues a job."), std::string::npos) << method.output;
    const GrpcurlRun stats = grpcurl({}, {"describe", "vastray.v1.JobStats"});
    EXPECT_NE(stats.output.find("uint64 peak_device_bytes = 6;"), std::string::npos) << stats.output;

    EXPECT_EQ(call("grpc.health.v1.Health/Check", json::object()), json({{"status", "SERVING"}}));
    for (const char* service : {"vastray.v1.SceneService", "vastray.v1.RenderService"})
        EXPECT_EQ(call("grpc.health.v1.Health/Check", json({{"service", service}})), json({{"status", "SERVING"}}))
            << service;

    size_t uploadMessages = 0;
    const GrpcurlRun upload = uploadSphere(16 << 10, &uploadMessages);
    ASSERT_EQ(upload.exitCode, 0) << upload.output;
    EXPECT_GE(uploadMessages, 2u) << "the upload should be a stream of several messages";
    const auto uploaded = messages(upload.output);
    ASSERT_EQ(uploaded.size(), 1u) << upload.output;
    const json scene = uploaded[0].value("scene", json::object());
    const std::string sceneId = scene.value("id", "");
    // Content-addressed: the same bytes over HTTP name the same scene.
    EXPECT_EQ(ServerTest::uploadSphere().value("id", ""), sceneId) << upload.output;
    EXPECT_EQ(scene.value("format", ""), "ply") << uploaded[0].dump();

    const json job =
        call("vastray.v1.RenderService/SubmitJob", smallJob(sceneId)).value("job", json::object());
    const std::string id = job.value("id", "");
    ASSERT_FALSE(id.empty()) << job.dump();
    EXPECT_EQ(job["request"].value("scene_id", ""), sceneId) << job.dump();

    const GrpcurlRun watch = grpcurl({"-d", json{{"id", id}}.dump()}, {"vastray.v1.RenderService/WatchJob"});
    EXPECT_EQ(watch.exitCode, 0) << watch.output;
    std::vector<json> events;
    for (const json& response : messages(watch.output))
        events.push_back(response.value("event", json::object()));
    ASSERT_FALSE(events.empty()) << watch.output;
    EXPECT_EQ(events.front().value("kind", ""), "KIND_SNAPSHOT") << watch.output;
    EXPECT_EQ(events.back().value("state", ""), "JOB_STATE_SUCCEEDED")
        << "the stream ends at the final state: " << watch.output;

    const json done = call("vastray.v1.RenderService/GetJob", {{"id", id}}).value("job", json::object());
    EXPECT_EQ(done.value("state", ""), "JOB_STATE_SUCCEEDED") << done.dump();
    ASSERT_TRUE(done.contains("stats")) << done.dump();
    EXPECT_EQ(done["stats"].value("backend", ""), "vulkan") << done.dump();
    EXPECT_GT(std::stoull(done["stats"].value("peak_device_bytes", "0")), 0u) << done.dump();

    // The result (a server stream of chunks, base64 in JSON): the bytes HTTP serves.
    const GrpcurlRun download =
        grpcurl({"-d", json{{"job_id", id}}.dump()}, {"vastray.v1.RenderService/GetResult"});
    EXPECT_EQ(download.exitCode, 0) << download.output.substr(0, 2000);
    std::string image;
    for (const json& chunk : messages(download.output)) {
        EXPECT_EQ(std::stoull(chunk.value("offset", "0")), image.size()) << chunk.dump();
        EXPECT_EQ(chunk.value("content_type", ""), "image/png");
        image += unbase64(chunk.value("data", ""));
    }
    EXPECT_EQ(image.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    EXPECT_EQ(image, result(id));

    // Error codes: grpcurl prints them and exits with 64 + the code.
    const GrpcurlRun missing = grpcurl({"-d", R"({"id": "job-0"})"}, {"vastray.v1.RenderService/GetJob"});
    EXPECT_EQ(missing.exitCode, kGrpcurlStatusOffset + int(grpc::StatusCode::NOT_FOUND)) << missing.output;
    EXPECT_NE(missing.output.find("Code: NotFound"), std::string::npos) << missing.output;
    json bad = smallJob(sceneId);
    bad["width"] = 0;
    const GrpcurlRun invalid = grpcurl({"-d", bad.dump()}, {"vastray.v1.RenderService/SubmitJob"});
    EXPECT_EQ(invalid.exitCode, kGrpcurlStatusOffset + int(grpc::StatusCode::INVALID_ARGUMENT)) << invalid.output;
    EXPECT_NE(invalid.output.find("Code: InvalidArgument"), std::string::npos) << invalid.output;
    EXPECT_NE(invalid.output.find("Message: width: "), std::string::npos) << "the field comes first: " << invalid.output;
    const GrpcurlRun noResult = grpcurl({"-d", R"({"job_id": "job-0"})"}, {"vastray.v1.RenderService/GetResult"});
    EXPECT_NE(noResult.output.find("Code: NotFound"), std::string::npos) << noResult.output;
}

TEST_F(GrpcurlTest, AuthTokenIsRequiredWhenConfigured) {
    const auto tokenFile = dir_ / "token";
    std::ofstream(tokenFile) << "grpcurl-token\n";
    startServer({"--auth-token-file", tokenFile.string()});
    const int unauthenticated = kGrpcurlStatusOffset + int(grpc::StatusCode::UNAUTHENTICATED);

    // Health and reflection stay open.
    EXPECT_EQ(call("grpc.health.v1.Health/Check", json::object()), json({{"status", "SERVING"}}));
    EXPECT_EQ(grpcurl({}, {"list"}).exitCode, 0);

    const GrpcurlRun none = grpcurl({"-d", "{}"}, {"vastray.v1.RenderService/ListJobs"});
    EXPECT_EQ(none.exitCode, unauthenticated) << none.output;
    EXPECT_NE(none.output.find("Code: Unauthenticated"), std::string::npos) << none.output;
    header_ = "authorization: Bearer not-the-token";
    const GrpcurlRun wrong = grpcurl({"-d", "{}"}, {"vastray.v1.RenderService/ListJobs"});
    EXPECT_EQ(wrong.exitCode, unauthenticated) << wrong.output;
    size_t uploadMessages = 0;
    EXPECT_EQ(uploadSphere(16 << 10, &uploadMessages).exitCode, unauthenticated);

    header_ = "authorization: Bearer grpcurl-token";
    const GrpcurlRun ok = grpcurl({"-d", "{}"}, {"vastray.v1.RenderService/ListJobs"});
    EXPECT_EQ(ok.exitCode, 0) << ok.output;
    const GrpcurlRun upload = uploadSphere(16 << 10, &uploadMessages);
    EXPECT_EQ(upload.exitCode, 0) << upload.output;
    const auto scene = messages(upload.output);
    ASSERT_EQ(scene.size(), 1u) << upload.output;
    EXPECT_EQ(scene[0].value("scene", json::object()).value("id", "").size(), 64u) << upload.output;
}

}  // namespace
}  // namespace vastray::test
