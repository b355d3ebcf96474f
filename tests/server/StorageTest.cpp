// The storage pieces in process: SHA-256 and the SQLite job store (its behaviour, shared with
// the PostgreSQL store's tests, and its schema migrations).
#include <gtest/gtest.h>

#include <sqlite3.h>

#include "StoreBehaviour.h"
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

std::filesystem::path freshDir(const std::string& name) {
    const auto dir = testTmpDir("server") / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

TEST(SqliteStore, JobsPersistAcrossReopenWithIdempotencyAndPaging) {
    const auto dir = freshDir("sqlite");
    checkStoreBehaviour([&] { return server::openSqliteStores(dir / "jobs.db"); });
}

// Runs SQL on a database file directly (the tests' own connection, not the store's).
void runSql(const std::filesystem::path& path, const std::string& sql) {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    char* message = nullptr;
    const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &message);
    EXPECT_EQ(rc, SQLITE_OK) << (message ? message : "");
    sqlite3_free(message);
    sqlite3_close(db);
}

int64_t schemaVersion(const std::filesystem::path& path) {
    sqlite3* db = nullptr;
    EXPECT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    sqlite3_stmt* query = nullptr;
    sqlite3_prepare_v2(db, "SELECT version FROM schema_version", -1, &query, nullptr);
    const int64_t version = query && sqlite3_step(query) == SQLITE_ROW ? sqlite3_column_int64(query, 0) : -1;
    sqlite3_finalize(query);
    sqlite3_close(db);
    return version;
}

TEST(SqliteStore, EmptyDatabaseGetsTheCurrentSchemaVersion) {
    const auto path = freshDir("sqlite-empty") / "jobs.db";
    ASSERT_TRUE(server::openSqliteStores(path).isOk());
    EXPECT_EQ(schemaVersion(path), server::kSqliteSchemaVersion);
    ASSERT_TRUE(server::openSqliteStores(path).isOk()) << "a second open finds nothing to migrate";
    EXPECT_EQ(schemaVersion(path), server::kSqliteSchemaVersion);
}

// The previous version: the tables the servers before schema_version wrote (verbatim), with a
// job in them. Opening migrates it and keeps the job.
TEST(SqliteStore, DatabaseOfThePreviousVersionIsMigratedKeepingItsJobs) {
    const auto path = freshDir("sqlite-previous") / "jobs.db";
    runSql(path, R"sql(
CREATE TABLE IF NOT EXISTS scenes (
  position INTEGER PRIMARY KEY AUTOINCREMENT,
  id TEXT NOT NULL UNIQUE,
  record BLOB NOT NULL);
CREATE TABLE IF NOT EXISTS jobs (
  position INTEGER PRIMARY KEY AUTOINCREMENT,
  id TEXT NOT NULL UNIQUE,
  request_id TEXT UNIQUE,
  scene_id TEXT NOT NULL,
  state INTEGER NOT NULL,
  record BLOB NOT NULL);
CREATE INDEX IF NOT EXISTS jobs_by_state ON jobs(state, position);
CREATE INDEX IF NOT EXISTS jobs_by_scene ON jobs(scene_id, state);
)sql");
    {
        // The previous server's rows, written through its statements.
        const v1::Job job = makeJob("job-old", v1::JOB_STATE_QUEUED, "old-key");
        sqlite3* db = nullptr;
        ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
        sqlite3_stmt* insert = nullptr;
        sqlite3_prepare_v2(db, "INSERT INTO jobs(id, request_id, scene_id, state, record) VALUES(?, ?, ?, ?, ?)",
                           -1, &insert, nullptr);
        const std::string record = job.SerializeAsString();
        sqlite3_bind_text(insert, 1, "job-old", -1, SQLITE_STATIC);
        sqlite3_bind_text(insert, 2, "old-key", -1, SQLITE_STATIC);
        sqlite3_bind_text(insert, 3, job.request().scene_id().c_str(), -1, SQLITE_TRANSIENT);
        sqlite3_bind_int64(insert, 4, v1::JOB_STATE_QUEUED);
        sqlite3_bind_blob(insert, 5, record.data(), int(record.size()), SQLITE_TRANSIENT);
        EXPECT_EQ(sqlite3_step(insert), SQLITE_DONE);
        sqlite3_finalize(insert);
        sqlite3_close(db);
    }
    auto stores = server::openSqliteStores(path);
    ASSERT_TRUE(stores.isOk()) << stores.message();
    EXPECT_EQ(schemaVersion(path), server::kSqliteSchemaVersion);
    auto unfinished = stores->jobs->unfinishedJobs();
    ASSERT_TRUE(unfinished.isOk());
    ASSERT_EQ(unfinished->size(), 1u);
    EXPECT_EQ((*unfinished)[0].id(), "job-old");
    auto again = stores->jobs->insertJob(makeJob("job-new", v1::JOB_STATE_QUEUED, "old-key"));
    ASSERT_TRUE(again.isOk());
    EXPECT_FALSE(again->created) << "the old request id still maps to its job";
}

// Version 1 (before environments), as a server of that version left it, with a job: opening
// migrates it to the current version keeping the job, and environments are stored.
TEST(SqliteStore, DatabaseOfVersionOneGetsTheEnvironmentsTable) {
    const auto path = freshDir("sqlite-version-one") / "jobs.db";
    {
        auto stores = server::openSqliteStores(path);
        ASSERT_TRUE(stores.isOk()) << stores.message();
        ASSERT_TRUE(stores->jobs->insertJob(makeJob("job-one", v1::JOB_STATE_QUEUED, "one-key")).isOk());
    }
    runSql(path, "DROP TABLE environments; UPDATE schema_version SET version = 1");
    ASSERT_EQ(schemaVersion(path), 1);
    auto stores = server::openSqliteStores(path);
    ASSERT_TRUE(stores.isOk()) << stores.message();
    EXPECT_EQ(schemaVersion(path), server::kSqliteSchemaVersion);
    auto kept = stores->jobs->getJob("job-one");
    ASSERT_TRUE(kept.isOk() && *kept) << "the job survives the migration";
    v1::Environment environment;
    environment.set_id(std::string(64, 'e'));
    environment.set_name("sky.exr");
    ASSERT_TRUE(stores->environments->insertEnvironment(environment).isOk());
    auto stored = stores->environments->getEnvironment(environment.id());
    ASSERT_TRUE(stored.isOk() && *stored) << stored.message();
    EXPECT_EQ((*stored)->name(), "sky.exr");
}

TEST(SqliteStore, NewerSchemaVersionIsRefusedNamingBoth) {
    const auto path = freshDir("sqlite-newer") / "jobs.db";
    ASSERT_TRUE(server::openSqliteStores(path).isOk());
    runSql(path, "UPDATE schema_version SET version = 99");
    auto stores = server::openSqliteStores(path);
    ASSERT_FALSE(stores.isOk());
    EXPECT_NE(stores.message().find(path.string() + ": the database has schema version 99; this vastray knows "
                                                    "versions up to " +
                                    std::to_string(server::kSqliteSchemaVersion)),
              std::string::npos)
        << stores.message();
    EXPECT_EQ(schemaVersion(path), 99) << "nothing was changed";
}

}  // namespace
}  // namespace vastray::test
