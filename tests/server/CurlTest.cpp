// The HTTP API through `curl`, the client most pipelines script with: upload, submit with an
// Idempotency-Key, Server-Sent Events, a ranged download.
#include "ServerTestSupport.h"

namespace vastray::test {
namespace {

// Runs a shell command and returns its stdout.
std::string run(const std::string& command) {
    std::string out;
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return out;
    char buffer[4096];
    size_t n;
    while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) out.append(buffer, n);
    pclose(pipe);
    return out;
}

TEST_F(ServerTest, CurlDrivesTheHttpApi) {
    startServer();
    const std::string base = "http://127.0.0.1:" + std::to_string(server_.httpPort());
    const json scene = json::parse(run("curl -sS -X PUT --data-binary @" + spherePath_.string() + " '" +
                                       base + "/v1/scenes?name=sphere.ply'"),
                                   nullptr, false);
    ASSERT_TRUE(scene.is_object() && scene.contains("id")) << scene.dump();

    const std::string body = smallJob(scene["id"]).dump();
    const std::string headers = run("curl -sS -o /dev/null -D - -X POST -H 'Idempotency-Key: curl-1' -d '" +
                                    body + "' " + base + "/v1/jobs");
    EXPECT_NE(headers.find("HTTP/1.1 202"), std::string::npos) << headers;
    const size_t location = headers.find("Location: /v1/jobs/");
    ASSERT_NE(location, std::string::npos) << headers;
    const std::string id = headers.substr(location + 19, 36);

    const std::string events = run("curl -sS -N " + base + "/v1/jobs/" + id + "/events");
    EXPECT_NE(events.find("event: KIND_SNAPSHOT"), std::string::npos) << events;
    EXPECT_NE(events.find("\"state\":\"JOB_STATE_SUCCEEDED\""), std::string::npos) << events;

    const std::string again =
        run("curl -sS -X POST -H 'Idempotency-Key: curl-1' -d '" + body + "' " + base + "/v1/jobs");
    EXPECT_EQ(json::parse(again, nullptr, false).value("id", ""), id);

    const std::string head = run("curl -sS -r 0-7 " + base + "/v1/jobs/" + id + "/result");
    EXPECT_EQ(head, std::string("\x89PNG\r\n\x1a\n", 8));
    const std::string missing =
        run("curl -sS -o /dev/null -w '%{http_code}' " + base + "/v1/jobs/job-0/result");
    EXPECT_EQ(missing, "404");

    // A cancel with no body: plain `curl -X POST` sends no Content-Length. It is answered at
    // once (here 409: the job has finished), not after the server's 5 s read timeout.
    const std::string cancel =
        run("curl -sS -o /dev/null -w '%{http_code} %{time_total}' -X POST " + base + "/v1/jobs/" + id + ":cancel");
    EXPECT_EQ(cancel.substr(0, 3), "409") << cancel;
    EXPECT_LT(std::stod(cancel.substr(4)), 2.0) << cancel;
}

}  // namespace
}  // namespace vastray::test
