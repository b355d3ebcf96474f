// The storage pieces in process: SHA-256 and the SQLite job store.
#include <gtest/gtest.h>

#include "TestTmp.h"
#include "vastray/server/Sha256.h"
#include "vastray/server/Storage.h"

namespace vastray::test {
namespace {

TEST(Sha256, MatchesTheFips180TestVectors) {
    EXPECT_EQ(server::sha256Hex("abc", 3),
              "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    EXPECT_EQ(server::sha256Hex("", 0), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    server::Sha256 split;
    split.update("a", 1);
    split.update("bc", 2);
    EXPECT_EQ(split.finishHex(), server::sha256Hex("abc", 3)) << "incremental updates hash the concatenation";
    EXPECT_TRUE(server::isSha256Hex(std::string(64, 'f')));
    EXPECT_FALSE(server::isSha256Hex(std::string(64, 'F')));
    EXPECT_FALSE(server::isSha256Hex(std::string(63, 'f')));
}

v1::Job makeJob(const std::string& id, v1::JobState state, const std::string& requestId = "") {
    v1::Job job;
    job.set_id(id);
    job.set_state(state);
    job.mutable_request()->set_scene_id(std::string(64, 'a'));
    job.mutable_request()->set_request_id(requestId);
    return job;
}

TEST(SqliteStore, JobsPersistAcrossReopenWithIdempotencyAndPaging) {
    const auto dir = testTmpDir("server") / "sqlite";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    {
        auto stores = server::openSqliteStores(dir / "jobs.db");
        ASSERT_TRUE(stores.isOk()) << stores.message();
        auto& jobs = *stores->jobs;
        for (int i = 0; i < 5; ++i)
            ASSERT_TRUE(jobs.insertJob(makeJob("job-" + std::to_string(i), v1::QUEUED)).isOk());
        auto first = jobs.insertJob(makeJob("job-x", v1::QUEUED, "key"));
        ASSERT_TRUE(first.isOk() && first->created);
        auto again = jobs.insertJob(makeJob("job-y", v1::QUEUED, "key"));
        ASSERT_TRUE(again.isOk());
        EXPECT_FALSE(again->created);
        EXPECT_EQ(again->job.id(), "job-x") << "a request id maps to its first job";
        v1::Job running = makeJob("job-1", v1::RUNNING);
        ASSERT_TRUE(jobs.updateJob(running).isOk());
        EXPECT_FALSE(jobs.updateJob(makeJob("job-missing", v1::FAILED)).isOk()) << "update of an unknown job";
        ASSERT_TRUE(jobs.updateJob(makeJob("job-2", v1::SUCCEEDED)).isOk());
    }
    auto stores = server::openSqliteStores(dir / "jobs.db");
    ASSERT_TRUE(stores.isOk());
    auto& jobs = *stores->jobs;
    auto unfinished = jobs.unfinishedJobs();
    ASSERT_TRUE(unfinished.isOk());
    ASSERT_EQ(unfinished->size(), 5u) << "job-2 finished; the others are QUEUED or RUNNING";
    EXPECT_EQ((*unfinished)[1].id(), "job-1");
    EXPECT_EQ((*unfinished)[1].state(), v1::RUNNING);

    std::vector<std::string> seen;
    uint64_t before = 0;
    for (bool more = true; more;) {
        auto page = jobs.listJobs(v1::JOB_STATE_UNSPECIFIED, before, 2);
        ASSERT_TRUE(page.isOk());
        for (const auto& job : page->jobs) seen.push_back(job.id());
        before = page->last;
        more = page->more;
    }
    EXPECT_EQ(seen, (std::vector<std::string>{"job-x", "job-4", "job-3", "job-2", "job-1", "job-0"}))
        << "newest first";
    auto succeeded = jobs.listJobs(v1::SUCCEEDED, 0, 10);
    ASSERT_TRUE(succeeded.isOk());
    ASSERT_EQ(succeeded->jobs.size(), 1u);
    EXPECT_EQ(succeeded->jobs[0].id(), "job-2");
    auto inUse = jobs.sceneInUse(std::string(64, 'a'));
    ASSERT_TRUE(inUse.isOk());
    EXPECT_TRUE(*inUse);
}

}  // namespace
}  // namespace vastray::test
