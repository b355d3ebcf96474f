// The PostgreSQL job store against a real PostgreSQL 15 that each test starts for itself
// (PostgresCluster.h): the store's behaviour (the SQLite store's, StoreBehaviour.h), its
// schema migrations, one server per database, `vastray serve --database` end to end (jobs
// survive kill -9, a crashing job fails after --max-attempts) and hostile URLs.
#include "CrashingJob.h"
#include "PostgresCluster.h"
#include "StoreBehaviour.h"

namespace vastray::test {
namespace {

class PostgresStoreTest : public ::testing::Test {
protected:
    void SetUp() override {
        const std::string failed = cluster_.start();
        ASSERT_EQ(failed, "") << failed;
    }
    std::string scalar(const std::string& sql) {
        const CommandResult run = cluster_.psql("vastray", sql);
        EXPECT_EQ(run.exitCode, 0) << run.output;
        std::string out = run.output;
        while (!out.empty() && out.back() == '\n') out.pop_back();
        return out;
    }
    PostgresCluster cluster_;
};

TEST_F(PostgresStoreTest, BehavesAsTheSqliteStore) {
    checkStoreBehaviour([&] { return server::openPostgresStores(cluster_.url()); });
}

TEST_F(PostgresStoreTest, EmptyDatabaseIsMigratedOnceToTheCurrentVersion) {
    {
        auto stores = server::openPostgresStores(cluster_.url());
        ASSERT_TRUE(stores.isOk()) << stores.message();
        ASSERT_TRUE(stores->jobs->insertJob(makeJob("job-kept", v1::JOB_STATE_QUEUED)).isOk());
    }
    EXPECT_EQ(scalar("SELECT version FROM schema_version"), std::to_string(server::kPostgresSchemaVersion));
    EXPECT_EQ(scalar("SELECT string_agg(tablename, ',' ORDER BY tablename) FROM pg_tables WHERE schemaname = "
                     "'public'"),
              "environments,jobs,scenes,schema_version,tasks");
    auto stores = server::openPostgresStores(cluster_.url());
    ASSERT_TRUE(stores.isOk()) << stores.message();
    EXPECT_EQ(scalar("SELECT count(*) FROM schema_version"), "1") << "a second open finds nothing to migrate";
    auto kept = stores->jobs->getJob("job-kept");
    ASSERT_TRUE(kept.isOk() && *kept) << "the rows survive a reopen";
}

// Version 1 (before tasks): the current database without the tasks and environments tables, at
// version 1, with a job. Opening migrates it to the current version and keeps the job.
TEST_F(PostgresStoreTest, DatabaseOfThePreviousVersionIsMigratedKeepingItsJobs) {
    {
        auto stores = server::openPostgresStores(cluster_.url());
        ASSERT_TRUE(stores.isOk()) << stores.message();
        ASSERT_TRUE(stores->jobs->insertJob(makeJob("job-old", v1::JOB_STATE_QUEUED, "old-key")).isOk());
    }
    scalar("DROP TABLE tasks; DROP TABLE environments; UPDATE schema_version SET version = 1");
    auto stores = server::openPostgresStores(cluster_.url(), true);
    ASSERT_TRUE(stores.isOk()) << stores.message();
    EXPECT_EQ(scalar("SELECT version FROM schema_version"), std::to_string(server::kPostgresSchemaVersion));
    auto unfinished = stores->jobs->unfinishedJobs();
    ASSERT_TRUE(unfinished.isOk());
    ASSERT_EQ(unfinished->size(), 1u);
    EXPECT_EQ((*unfinished)[0].id(), "job-old");
    // The new table works: a tiled job's tasks are stored and leased.
    v1::Job tiled = makeJob("job-tiled", v1::JOB_STATE_QUEUED);
    tiled.mutable_request()->add_tiles(2);
    tiled.mutable_request()->add_tiles(1);
    ASSERT_TRUE(stores->tasks->insertJobWithTasks(tiled, 2).isOk());
    EXPECT_EQ(scalar("SELECT string_agg(tile::text, ',' ORDER BY tile) FROM tasks WHERE job_id = 'job-tiled'"),
              "-1,0,1");
}

// Version 2 (before environments): the current database without the environments table, at
// version 2, with a job. Opening migrates it to the current version, keeps the job, and
// environments are stored.
TEST_F(PostgresStoreTest, DatabaseOfVersionTwoGetsTheEnvironmentsTable) {
    {
        auto stores = server::openPostgresStores(cluster_.url());
        ASSERT_TRUE(stores.isOk()) << stores.message();
        ASSERT_TRUE(stores->jobs->insertJob(makeJob("job-two", v1::JOB_STATE_QUEUED, "two-key")).isOk());
    }
    scalar("DROP TABLE environments; UPDATE schema_version SET version = 2");
    auto stores = server::openPostgresStores(cluster_.url());
    ASSERT_TRUE(stores.isOk()) << stores.message();
    EXPECT_EQ(scalar("SELECT version FROM schema_version"), std::to_string(server::kPostgresSchemaVersion));
    auto kept = stores->jobs->getJob("job-two");
    ASSERT_TRUE(kept.isOk() && *kept) << "the job survives the migration";
    v1::Environment environment;
    environment.set_id(std::string(64, 'e'));
    environment.set_name("sky.exr");
    ASSERT_TRUE(stores->environments->insertEnvironment(environment).isOk());
    auto stored = stores->environments->getEnvironment(environment.id());
    ASSERT_TRUE(stored.isOk() && *stored) << stored.message();
    EXPECT_EQ((*stored)->name(), "sky.exr");
}

TEST_F(PostgresStoreTest, NewerSchemaVersionIsRefusedNamingBoth) {
    ASSERT_TRUE(server::openPostgresStores(cluster_.url()).isOk());
    scalar("UPDATE schema_version SET version = 99");
    auto stores = server::openPostgresStores(cluster_.url());
    ASSERT_FALSE(stores.isOk());
    EXPECT_NE(stores.message().find(cluster_.url() + ": the database has schema version 99; this vastray knows "
                                                     "versions up to " +
                                    std::to_string(server::kPostgresSchemaVersion)),
              std::string::npos)
        << stores.message();
    EXPECT_EQ(scalar("SELECT version FROM schema_version"), "99") << "nothing was changed";
}

// A migration that fails leaves the database as it was (one transaction): here a table `jobs`
// that is not ours blocks version 1.
TEST_F(PostgresStoreTest, FailedMigrationNamesItsVersionAndChangesNothing) {
    scalar("CREATE TABLE jobs (something INTEGER)");
    auto stores = server::openPostgresStores(cluster_.url());
    ASSERT_FALSE(stores.isOk());
    EXPECT_NE(stores.message().find("migration to schema version 1: " + cluster_.url() + ": CREATE TABLE scenes"),
              std::string::npos)
        << stores.message();
    EXPECT_NE(stores.message().find("relation \"jobs\" already exists"), std::string::npos) << stores.message();
    EXPECT_EQ(scalar("SELECT count(*) FROM pg_tables WHERE tablename IN ('scenes', 'schema_version')"), "0")
        << "rolled back";
}

TEST_F(PostgresStoreTest, SecondServerOnOneDatabaseIsRefusedUntilTheFirstCloses) {
    auto first = server::openPostgresStores(cluster_.url());
    ASSERT_TRUE(first.isOk()) << first.message();
    auto second = server::openPostgresStores(cluster_.url());
    ASSERT_FALSE(second.isOk());
    EXPECT_EQ(second.message(),
              cluster_.url() + ": another `vastray serve` uses this database (one server per database)");
    first = Status::error("closed");
    EXPECT_TRUE(server::openPostgresStores(cluster_.url()).isOk()) << "the lock goes with the connection";
}

TEST_F(PostgresStoreTest, StatementErrorsNameTheDatabaseAndTheStatement) {
    auto stores = server::openPostgresStores(cluster_.url());
    ASSERT_TRUE(stores.isOk()) << stores.message();
    scalar("DROP TABLE jobs CASCADE");
    auto job = stores->jobs->getJob("job-1");
    ASSERT_FALSE(job.isOk());
    EXPECT_EQ(job.message().find(cluster_.url() + ": SELECT record FROM jobs WHERE id = $1: ERROR:  relation "
                                                  "\"jobs\" does not exist"),
              0u)
        << job.message();
}

TEST(PostgresUrl, PasswordsAreLeftOutOfMessages) {
    EXPECT_EQ(server::redactDatabaseUrl("postgresql://render:s3cret@db.example:5432/jobs"),
              "postgresql://render@db.example:5432/jobs");
    EXPECT_EQ(server::redactDatabaseUrl("postgresql://render@db/jobs?password=s3cret&sslmode=require"),
              "postgresql://render@db/jobs?sslmode=require");
    EXPECT_EQ(server::redactDatabaseUrl("postgres://db/jobs?password=x"), "postgres://db/jobs");
    EXPECT_EQ(server::redactDatabaseUrl("postgresql://a:b@[::1]:5432/j"), "postgresql://a@[::1]:5432/j");
}

// `vastray serve --database` end to end, with the fixtures of the SQLite tests.
class PostgresServeTest : public CrashingJobTest {
protected:
    void SetUp() override {
        CrashingJobTest::SetUp();
        const std::string failed = cluster_.start();
        ASSERT_EQ(failed, "") << failed;
    }
    std::vector<std::string> database() const { return {"--database", cluster_.url()}; }
    PostgresCluster cluster_;
};

TEST_F(PostgresServeTest, JobsSurviveKillAndRestart) {
    startServer(database());
    EXPECT_NE(server_.log().find("job store " + cluster_.url() + "\n"), std::string::npos) << server_.log();
    const std::string sceneId = uploadSphere()["id"];
    auto res = submit(slowJob(sceneId));
    ASSERT_EQ(res->status, 202) << res->body;
    const std::string running = json::parse(res->body)["id"];
    json queued = smallJob(sceneId);
    queued["request_id"] = "render-7";
    res = submit(queued);
    ASSERT_EQ(res->status, 202) << res->body;
    const std::string queuedId = json::parse(res->body)["id"];
    waitForState(running, "JOB_STATE_RUNNING");
    server_.kill(SIGKILL);
    EXPECT_FALSE(std::filesystem::exists(dataDir() / "jobs.db")) << "no SQLite database beside PostgreSQL";

    startServer(database());
    const json job = waitForState(running, "JOB_STATE_SUCCEEDED");
    EXPECT_EQ(job["attempts"], 2) << "the interrupted render ran again";
    EXPECT_EQ(result(running), cliRender(sceneId, kSlowJobFlags));
    EXPECT_EQ(waitForState(queuedId, "JOB_STATE_SUCCEEDED")["attempts"], 1);
    res = submit(queued);
    ASSERT_EQ(res->status, 200) << "the request id is known after the restart: " << res->body;
    EXPECT_EQ(json::parse(res->body)["id"], queuedId);
    auto list = http().Get("/v1/jobs");
    EXPECT_EQ(json::parse(list->body)["jobs"].size(), 2u) << "no job lost or duplicated";
}

TEST_F(PostgresServeTest, JobThatCrashesTheServerFailsAfterMaxAttempts) {
    crashingJobFailsAfterMaxAttempts(database(), 2);
}

TEST_F(PostgresServeTest, SecondServerOnTheDatabaseIsRefusedAtStart) {
    startServer(database());
    const CommandResult second =
        runShell("timeout 60 " + std::string(VASTRAY_BINARY) + " serve --data-dir " + (dir_ / "second").string() +
                 " --grpc 127.0.0.1:0 --http 127.0.0.1:0 --database '" + cluster_.url() + "'");
    EXPECT_EQ(second.exitCode, 1) << second.output;
    EXPECT_NE(second.output.find("another `vastray serve` uses this database"), std::string::npos) << second.output;
    EXPECT_EQ(http().Get("/healthz")->status, 200) << "the first server goes on";
}

// Hostile --database values stop the start with a named error: no crash, no "ready", no password.
TEST_F(PostgresServeTest, BadDatabaseUrlsAreNamedErrorsAtStart) {
    cluster_.psql("vastray", "CREATE TABLE schema_version (version INTEGER NOT NULL); "
                             "INSERT INTO schema_version VALUES (7)");
    struct Case {
        std::string url, expected;
    };
    const std::vector<Case> cases = {
        {"mysql://render:s3cret@localhost/jobs",
         "--database 'mysql://render@localhost/jobs': expected a URL postgresql://"},
        {"postgresql://render:s3cret@127.0.0.1:1/jobs",
         "postgresql://render@127.0.0.1:1/jobs: cannot connect: connection to server at \"127.0.0.1\", port 1 failed"},
        {"postgresql://render:s3cret@[::1/jobs", "--database 'postgresql://render@[::1/jobs': "},
        {"postgresql:///nosuchdb?host=" + cluster_.url().substr(cluster_.url().find("host=") + 5) +
             "&user=vastray&password=s3cret",
         "cannot connect: "},
        {cluster_.url(), cluster_.url() + ": the database has schema version 7; this vastray knows versions up to"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.url);
        const CommandResult run =
            runShell("timeout 60 " + std::string(VASTRAY_BINARY) + " serve --data-dir " + (dir_ / "bad").string() +
                     " --grpc 127.0.0.1:0 --http 127.0.0.1:0 --database '" + c.url + "'");
        EXPECT_GE(run.exitCode, 1) << run.output;
        EXPECT_LE(run.exitCode, 2) << "an error exit, not a crash or a timeout: " << run.output;
        EXPECT_NE(run.output.find(c.expected), std::string::npos) << run.output;
        EXPECT_EQ(run.output.find("s3cret"), std::string::npos) << run.output;
        EXPECT_EQ(run.output.find("vastray serve: ready"), std::string::npos) << run.output;
    }
}

}  // namespace
}  // namespace vastray::test
