#pragma once
// What every SceneCatalog + JobStore must do, whichever database holds it (SqliteStore,
// PostgresStore): records survive a reopen, a request id maps to its first job, paging and
// filters order as documented, scenes and environments insert once and delete, a job's
// environment fields come back as stored.
#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "vastray/server/Storage.h"

namespace vastray::test {

inline v1::Job makeJob(const std::string& id, v1::JobState state, const std::string& requestId = "") {
    v1::Job job;
    job.set_id(id);
    job.set_state(state);
    job.mutable_request()->set_scene_id(std::string(64, 'a'));
    job.mutable_request()->set_request_id(requestId);
    return job;
}

// `open` opens the same (initially empty) database each time it is called.
inline void checkStoreBehaviour(const std::function<Result<server::MetadataStores>()>& open) {
    {
        auto stores = open();
        ASSERT_TRUE(stores.isOk()) << stores.message();
        auto& jobs = *stores->jobs;
        for (int i = 0; i < 5; ++i)
            ASSERT_TRUE(jobs.insertJob(makeJob("job-" + std::to_string(i), v1::JOB_STATE_QUEUED)).isOk());
        auto first = jobs.insertJob(makeJob("job-x", v1::JOB_STATE_QUEUED, "key"));
        ASSERT_TRUE(first.isOk() && first->created) << first.message();
        auto again = jobs.insertJob(makeJob("job-y", v1::JOB_STATE_QUEUED, "key"));
        ASSERT_TRUE(again.isOk()) << again.message();
        EXPECT_FALSE(again->created);
        EXPECT_EQ(again->job.id(), "job-x") << "a request id maps to its first job";
        auto byRequest = jobs.findJobByRequestId("key");
        ASSERT_TRUE(byRequest.isOk() && *byRequest);
        EXPECT_EQ((*byRequest)->id(), "job-x");
        v1::Job running = makeJob("job-1", v1::JOB_STATE_RUNNING);
        running.set_attempts(2);
        running.add_attempt_errors("attempt 1: why");
        ASSERT_TRUE(jobs.updateJob(running).isOk());
        EXPECT_FALSE(jobs.updateJob(makeJob("job-missing", v1::JOB_STATE_FAILED)).isOk())
            << "update of an unknown job";
        ASSERT_TRUE(jobs.updateJob(makeJob("job-2", v1::JOB_STATE_SUCCEEDED)).isOk());

        auto& scenes = *stores->scenes;
        for (const char* id : {"scene-a", "scene-b", "scene-c"}) {
            v1::Scene scene;
            scene.set_id(id);
            scene.set_name(std::string(id) + ".ply");
            ASSERT_TRUE(scenes.insertScene(scene).isOk());
        }
        v1::Scene renamed;
        renamed.set_id("scene-a");
        renamed.set_name("other.ply");
        auto kept = scenes.insertScene(renamed);
        ASSERT_TRUE(kept.isOk());
        EXPECT_EQ(kept->name(), "scene-a.ply") << "a scene id inserts once; the stored record is returned";
        ASSERT_TRUE(scenes.deleteScene("scene-b").isOk());

        auto& environments = *stores->environments;
        for (const char* id : {"env-a", "env-b", "env-c"}) {
            v1::Environment environment;
            environment.set_id(id);
            environment.set_name(std::string(id) + ".exr");
            environment.set_format("exr");
            environment.set_width(16);
            environment.set_height(8);
            environment.set_device_bytes(2580);
            ASSERT_TRUE(environments.insertEnvironment(environment).isOk());
        }
        v1::Environment renamedEnvironment;
        renamedEnvironment.set_id("env-a");
        renamedEnvironment.set_name("other.hdr");
        auto keptEnvironment = environments.insertEnvironment(renamedEnvironment);
        ASSERT_TRUE(keptEnvironment.isOk()) << keptEnvironment.message();
        EXPECT_EQ(keptEnvironment->name(), "env-a.exr") << "an environment id inserts once";
        ASSERT_TRUE(environments.deleteEnvironment("env-b").isOk());

        v1::Job lit = makeJob("job-lit", v1::JOB_STATE_SUCCEEDED);
        v1::JobEnvironment& e = *lit.mutable_request()->mutable_environment();
        e.set_id("env-a");
        e.set_scale(0);  // present and zero: a map scaled to black, not the default 1
        e.set_rotation_degrees(-90.5f);
        ASSERT_TRUE(jobs.insertJob(lit).isOk());
    }
    auto stores = open();
    ASSERT_TRUE(stores.isOk()) << stores.message();
    auto& jobs = *stores->jobs;
    auto unfinished = jobs.unfinishedJobs();
    ASSERT_TRUE(unfinished.isOk());
    ASSERT_EQ(unfinished->size(), 5u) << "job-2 finished; the others are QUEUED or RUNNING";
    EXPECT_EQ((*unfinished)[1].id(), "job-1");
    EXPECT_EQ((*unfinished)[1].state(), v1::JOB_STATE_RUNNING);
    EXPECT_EQ((*unfinished)[1].attempts(), 2u);
    ASSERT_EQ((*unfinished)[1].attempt_errors_size(), 1);
    EXPECT_EQ((*unfinished)[1].attempt_errors(0), "attempt 1: why");

    std::vector<std::string> seen;
    uint64_t before = 0;
    for (bool more = true; more;) {
        auto page = jobs.listJobs(v1::JOB_STATE_UNSPECIFIED, before, 2);
        ASSERT_TRUE(page.isOk());
        for (const auto& job : page->jobs) seen.push_back(job.id());
        before = page->last;
        more = page->more;
    }
    EXPECT_EQ(seen, (std::vector<std::string>{"job-lit", "job-x", "job-4", "job-3", "job-2", "job-1", "job-0"}))
        << "newest first";
    auto succeeded = jobs.listJobs(v1::JOB_STATE_SUCCEEDED, 0, 10);
    ASSERT_TRUE(succeeded.isOk());
    ASSERT_EQ(succeeded->jobs.size(), 2u);
    EXPECT_EQ(succeeded->jobs[0].id(), "job-lit");
    EXPECT_EQ(succeeded->jobs[1].id(), "job-2");
    auto inUse = jobs.sceneInUse(std::string(64, 'a'));
    ASSERT_TRUE(inUse.isOk());
    EXPECT_TRUE(*inUse);
    auto unused = jobs.sceneInUse(std::string(64, 'b'));
    ASSERT_TRUE(unused.isOk());
    EXPECT_FALSE(*unused);
    auto missing = jobs.getJob("job-none");
    ASSERT_TRUE(missing.isOk());
    EXPECT_FALSE(*missing);

    auto& scenes = *stores->scenes;
    std::vector<std::string> sceneIds;
    uint64_t after = 0;
    for (bool more = true; more;) {
        auto page = scenes.listScenes(after, 1);
        ASSERT_TRUE(page.isOk());
        for (const auto& scene : page->scenes) sceneIds.push_back(scene.id());
        after = page->last;
        more = page->more;
    }
    EXPECT_EQ(sceneIds, (std::vector<std::string>{"scene-a", "scene-c"})) << "oldest first, scene-b deleted";

    auto lit = jobs.getJob("job-lit");
    ASSERT_TRUE(lit.isOk() && *lit) << lit.message();
    ASSERT_TRUE((*lit)->request().has_environment());
    EXPECT_EQ((*lit)->request().environment().id(), "env-a");
    EXPECT_TRUE((*lit)->request().environment().has_scale()) << "a scale of 0 is kept as given";
    EXPECT_EQ((*lit)->request().environment().scale(), 0.0f);
    EXPECT_EQ((*lit)->request().environment().rotation_degrees(), -90.5f);

    auto& environments = *stores->environments;
    std::vector<std::string> environmentIds;
    after = 0;
    for (bool more = true; more;) {
        auto page = environments.listEnvironments(after, 1);
        ASSERT_TRUE(page.isOk()) << page.message();
        for (const auto& environment : page->environments) environmentIds.push_back(environment.id());
        after = page->last;
        more = page->more;
    }
    EXPECT_EQ(environmentIds, (std::vector<std::string>{"env-a", "env-c"})) << "oldest first, env-b deleted";
    auto environment = environments.getEnvironment("env-c");
    ASSERT_TRUE(environment.isOk() && *environment);
    EXPECT_EQ((*environment)->width(), 16u);
    EXPECT_EQ((*environment)->device_bytes(), 2580u);
    auto goneEnvironment = environments.getEnvironment("env-b");
    ASSERT_TRUE(goneEnvironment.isOk());
    EXPECT_FALSE(*goneEnvironment);
    auto gone = scenes.getScene("scene-b");
    ASSERT_TRUE(gone.isOk());
    EXPECT_FALSE(*gone);
}

}  // namespace vastray::test
