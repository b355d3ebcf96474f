// --max-attempts with the SQLite store: a job that crashes its server is failed after N
// attempts with every reason, the server goes on serving the others; bad values are refused.
#include <fstream>

#include "CrashingJob.h"

namespace vastray::test {
namespace {

TEST_F(CrashingJobTest, JobThatCrashesTheServerFailsAfterTheDefaultThreeAttempts) {
    crashingJobFailsAfterMaxAttempts({}, 3);
}

TEST_F(CrashingJobTest, MaxAttemptsOneFailsAtTheFirstCrash) { crashingJobFailsAfterMaxAttempts({}, 1); }

// An internal render error (here: the stored package damaged after its upload, which the
// renderer reports naming the file) is retried until --max-attempts attempts failed, then the
// job is FAILED with each attempt's reason; the server goes on.
TEST_F(ServerTest, InternalRenderErrorsAreRetriedUntilMaxAttempts) {
    startServer({"--max-attempts", "2"});
    const std::string sceneId = uploadSphere()["id"];
    const auto package = dataDir() / "scenes" / (sceneId + ".vast");
    std::string bytes = readBytes(package);
    ASSERT_GT(bytes.size(), 64u);
    bytes.resize(bytes.size() / 2);
    std::ofstream(package, std::ios::binary | std::ios::trunc) << bytes;
    auto res = submit(smallJob(sceneId));
    ASSERT_EQ(res->status, 202) << res->body;
    const std::string id = json::parse(res->body)["id"];
    const json failed = waitForState(id, "JOB_STATE_FAILED");
    EXPECT_EQ(failed["attempts"], 2) << failed.dump();
    ASSERT_EQ(failed["attempt_errors"].size(), 2u) << failed.dump();
    const std::string error = failed.value("error", "");
    EXPECT_EQ(error.find("failed 2 times (--max-attempts 2); not run again: attempt 1 (started "), 0u) << error;
    for (int attempt = 1; attempt <= 2; ++attempt) {
        const std::string reason = failed["attempt_errors"][attempt - 1];
        EXPECT_EQ(reason.find("attempt " + std::to_string(attempt) + " (started "), 0u) << reason;
        EXPECT_NE(reason.find(sceneId), std::string::npos) << "the reason names the package: " << reason;
        EXPECT_NE(error.find(reason), std::string::npos);
    }
    EXPECT_EQ(http().Get("/healthz")->status, 200);
}

TEST_F(ServerTest, MaxAttemptsZeroOrNotANumberIsRefused) {
    const std::string start = "timeout 60 " + std::string(VASTRAY_BINARY) + " serve --data-dir " +
                              (dir_ / "bad").string() + " --grpc 127.0.0.1:0 --http 127.0.0.1:0 --max-attempts ";
    const CommandResult zero = runShell(start + "0");
    EXPECT_EQ(zero.exitCode, 2) << zero.output;
    EXPECT_NE(zero.output.find("--max-attempts must be at least 1"), std::string::npos) << zero.output;
    const CommandResult text = runShell(start + "many");
    EXPECT_NE(text.exitCode, 0) << text.output;
    EXPECT_NE(text.output.find("--max-attempts"), std::string::npos) << text.output;
    EXPECT_EQ(text.output.find("ready"), std::string::npos) << text.output;
}

}  // namespace
}  // namespace vastray::test
