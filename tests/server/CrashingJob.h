#pragma once
// A job that crashes its server every time a worker starts it (a real SIGABRT of `vastray
// serve`, through the test-only hook VASTRAY_TEST_CRASH_ON_JOB=REQUEST_ID): each start after a
// crash finds it RUNNING and counts a failed attempt; after --max-attempts it is FAILED with
// every attempt's reason, and the jobs queued behind it and new ones run. Shared by the SQLite
// (AttemptsTest.cpp) and PostgreSQL (postgres/) tests: `flags` choose the store.
#include <string>
#include <vector>

#include "ServerTestSupport.h"

namespace vastray::test {

class CrashingJobTest : public ServerTest {
protected:
    void crashingJobFailsAfterMaxAttempts(std::vector<std::string> flags, int maxAttempts) {
        if (maxAttempts != 3) flags.insert(flags.end(), {"--max-attempts", std::to_string(maxAttempts)});
        server_.setEnvironment("VASTRAY_TEST_CRASH_ON_JOB", "crash-me");
        std::vector<std::string> paused = flags;
        paused.push_back("--paused");
        startServer(paused);
        const std::string sceneId = uploadSphere()["id"];
        json crashing = smallJob(sceneId);
        crashing["request_id"] = "crash-me";
        crashing["priority"] = 90;  // started first at every start
        auto res = submit(crashing);
        ASSERT_EQ(res->status, 202) << res->body;
        const std::string crashId = json::parse(res->body)["id"];
        json behind = smallJob(sceneId);
        behind["seed"] = 7;
        res = submit(behind);
        ASSERT_EQ(res->status, 202) << res->body;
        const std::string behindId = json::parse(res->body)["id"];
        server_.kill(SIGKILL);

        for (int attempt = 1; attempt <= maxAttempts; ++attempt) {
            SCOPED_TRACE("start " + std::to_string(attempt));
            // The worker may start the job (and crash) before or after the "ready" line.
            server_.start(dataDir(), flags);
            const int status = server_.waitExit(std::chrono::seconds(60));
            ASSERT_TRUE(status != -1 && WIFSIGNALED(status) && WTERMSIG(status) == SIGABRT)
                << "status " << status << "\n"
                << server_.log();
            EXPECT_NE(server_.log().find("VASTRAY_TEST_CRASH_ON_JOB: aborting on job " + crashId),
                      std::string::npos)
                << server_.log();
        }
        // The next start fails the job instead of starting it (the hook is still set).
        startServer(flags);
        const json failed = waitForState(crashId, "JOB_STATE_FAILED");
        EXPECT_EQ(failed["attempts"], maxAttempts) << failed.dump();
        ASSERT_EQ(failed["attempt_errors"].size(), size_t(maxAttempts)) << failed.dump();
        const std::string error = failed.value("error", "");
        EXPECT_EQ(error.find("failed " + std::to_string(maxAttempts) + " times (--max-attempts " +
                             std::to_string(maxAttempts) + "); not run again: attempt 1 (started "),
                  0u)
            << error;
        for (int attempt = 1; attempt <= maxAttempts; ++attempt) {
            const std::string reason = failed["attempt_errors"][attempt - 1];
            EXPECT_EQ(reason.find("attempt " + std::to_string(attempt) + " (started "), 0u) << reason;
            EXPECT_NE(reason.find("the server stopped while rendering it"), std::string::npos) << reason;
            EXPECT_NE(error.find(reason), std::string::npos) << "the error lists attempt " << attempt;
        }
        EXPECT_EQ(server_.log().find("aborting"), std::string::npos) << server_.log();
        // The job queued behind it, and a new one, run as usual.
        EXPECT_EQ(waitForState(behindId, "JOB_STATE_SUCCEEDED")["attempts"], 1);
        EXPECT_EQ(result(behindId), cliRender(sceneId, "--resolution 32x32 --spp 2 --seed 7"));
        res = submit(smallJob(sceneId));
        ASSERT_EQ(res->status, 202) << res->body;
        waitForState(json::parse(res->body)["id"], "JOB_STATE_SUCCEEDED");
        EXPECT_EQ(getJob(crashId)["state"], "JOB_STATE_FAILED") << "never run again";
    }
};

}  // namespace vastray::test
