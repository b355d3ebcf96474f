// SceneCatalog, EnvironmentCatalog and JobStore in one SQLite database. Records are the serialized proto
// messages; the columns beside them exist only to look records up and order them.
#include <sqlite3.h>

#include <iterator>
#include <mutex>
#include <vector>

#include "vastray/server/Storage.h"

namespace vastray::server {
namespace {

// schema_version.version N means kMigrations[0..N-1] have run, each in the transaction that
// set N. New versions are appended, never edited. Version 1 is the schema of the servers that
// wrote no schema_version (IF NOT EXISTS: their databases migrate from 0 keeping every row).
const char* const kMigrations[] = {
    R"sql(
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
)sql",
    R"sql(
CREATE TABLE environments (
  position INTEGER PRIMARY KEY AUTOINCREMENT,
  id TEXT NOT NULL UNIQUE,
  record BLOB NOT NULL);
)sql",
};
static_assert(std::size(kMigrations) == size_t(kSqliteSchemaVersion));

// One prepared statement, finalized on scope exit.
class Statement {
public:
    Statement(sqlite3* db, const char* sql) : db_(db), sql_(sql) {
        sqlite3_prepare_v2(db, sql, -1, &stmt_, nullptr);
    }
    ~Statement() { sqlite3_finalize(stmt_); }
    Statement(const Statement&) = delete;
    Statement& operator=(const Statement&) = delete;

    bool valid() const { return stmt_ != nullptr; }
    void bind(int i, const std::string& text) {
        sqlite3_bind_text(stmt_, i, text.data(), int(text.size()), SQLITE_TRANSIENT);
    }
    void bindBlob(int i, const std::string& bytes) {
        sqlite3_bind_blob(stmt_, i, bytes.data(), int(bytes.size()), SQLITE_TRANSIENT);
    }
    void bind(int i, int64_t value) { sqlite3_bind_int64(stmt_, i, value); }
    void bindNull(int i) { sqlite3_bind_null(stmt_, i); }
    // SQLITE_ROW, SQLITE_DONE or an error code.
    int step() { return sqlite3_step(stmt_); }
    int64_t integer(int column) const { return sqlite3_column_int64(stmt_, column); }
    std::string blob(int column) const {
        const void* data = sqlite3_column_blob(stmt_, column);
        return data ? std::string(static_cast<const char*>(data), size_t(sqlite3_column_bytes(stmt_, column)))
                    : "";
    }
    std::string error() const { return sqlite3_errmsg(db_); }
    const char* sql() const { return sql_; }

private:
    sqlite3* db_;
    const char* sql_;
    sqlite3_stmt* stmt_ = nullptr;
};

template <typename Message>
Result<Message> parseRecord(const std::string& bytes) {
    Message message;
    if (!message.ParseFromString(bytes)) return Status::error("job store: a stored record does not parse");
    return message;
}

class SqliteStore final : public SceneCatalog, public EnvironmentCatalog, public JobStore {
public:
    explicit SqliteStore(sqlite3* db, std::string path) : db_(db), path_(std::move(path)) {}
    ~SqliteStore() override { sqlite3_close(db_); }

    Result<v1::Scene> insertScene(const v1::Scene& scene) override {
        std::lock_guard<std::mutex> lock(mutex_);
        Statement insert(db_, "INSERT OR IGNORE INTO scenes(id, record) VALUES(?, ?)");
        insert.bind(1, scene.id());
        insert.bindBlob(2, scene.SerializeAsString());
        if (insert.step() != SQLITE_DONE) return failure(insert);
        auto stored = getSceneLocked(scene.id());
        if (!stored) return stored.status();
        if (!*stored) return Status::error(path_ + ": scene " + scene.id() + " vanished after insert");
        return **stored;
    }

    Result<std::optional<v1::Scene>> getScene(const std::string& id) override {
        std::lock_guard<std::mutex> lock(mutex_);
        return getSceneLocked(id);
    }

    Result<ScenePage> listScenes(uint64_t after, uint32_t limit) override {
        std::lock_guard<std::mutex> lock(mutex_);
        Statement query(db_,
                        "SELECT position, record FROM scenes WHERE position > ? ORDER BY position LIMIT ?");
        query.bind(1, int64_t(after));
        query.bind(2, int64_t(limit) + 1);
        ScenePage page;
        int rc;
        while ((rc = query.step()) == SQLITE_ROW) {
            if (page.scenes.size() == limit) {
                page.more = true;
                break;
            }
            auto scene = parseRecord<v1::Scene>(query.blob(1));
            if (!scene) return scene.status();
            page.scenes.push_back(std::move(*scene));
            page.last = uint64_t(query.integer(0));
        }
        if (rc != SQLITE_ROW && rc != SQLITE_DONE) return failure(query);
        return page;
    }

    Status deleteScene(const std::string& id) override {
        std::lock_guard<std::mutex> lock(mutex_);
        Statement remove(db_, "DELETE FROM scenes WHERE id = ?");
        remove.bind(1, id);
        if (remove.step() != SQLITE_DONE) return failure(remove);
        return Status::ok();
    }

    Result<v1::Environment> insertEnvironment(const v1::Environment& environment) override {
        std::lock_guard<std::mutex> lock(mutex_);
        Statement insert(db_, "INSERT OR IGNORE INTO environments(id, record) VALUES(?, ?)");
        insert.bind(1, environment.id());
        insert.bindBlob(2, environment.SerializeAsString());
        if (insert.step() != SQLITE_DONE) return failure(insert);
        auto stored = getRecordLocked<v1::Environment>("SELECT record FROM environments WHERE id = ?", environment.id());
        if (!stored) return stored.status();
        if (!*stored) return Status::error(path_ + ": environment " + environment.id() + " vanished after insert");
        return **stored;
    }

    Result<std::optional<v1::Environment>> getEnvironment(const std::string& id) override {
        std::lock_guard<std::mutex> lock(mutex_);
        return getRecordLocked<v1::Environment>("SELECT record FROM environments WHERE id = ?", id);
    }

    Result<EnvironmentPage> listEnvironments(uint64_t after, uint32_t limit) override {
        std::lock_guard<std::mutex> lock(mutex_);
        Statement query(db_, "SELECT position, record FROM environments WHERE position > ? ORDER BY position LIMIT ?");
        query.bind(1, int64_t(after));
        query.bind(2, int64_t(limit) + 1);
        EnvironmentPage page;
        int rc;
        while ((rc = query.step()) == SQLITE_ROW) {
            if (page.environments.size() == limit) {
                page.more = true;
                break;
            }
            auto environment = parseRecord<v1::Environment>(query.blob(1));
            if (!environment) return environment.status();
            page.environments.push_back(std::move(*environment));
            page.last = uint64_t(query.integer(0));
        }
        if (rc != SQLITE_ROW && rc != SQLITE_DONE) return failure(query);
        return page;
    }

    Status deleteEnvironment(const std::string& id) override {
        std::lock_guard<std::mutex> lock(mutex_);
        Statement remove(db_, "DELETE FROM environments WHERE id = ?");
        remove.bind(1, id);
        if (remove.step() != SQLITE_DONE) return failure(remove);
        return Status::ok();
    }

    Result<Insert> insertJob(const v1::Job& job) override {
        std::lock_guard<std::mutex> lock(mutex_);
        const std::string& requestId = job.request().request_id();
        if (!requestId.empty()) {
            auto existing = findOne("SELECT record FROM jobs WHERE request_id = ?", requestId);
            if (!existing) return existing.status();
            if (*existing) return Insert{**existing, false};
        }
        Statement insert(db_,
                         "INSERT INTO jobs(id, request_id, scene_id, state, record) VALUES(?, ?, ?, ?, ?)");
        insert.bind(1, job.id());
        if (requestId.empty())
            insert.bindNull(2);
        else
            insert.bind(2, requestId);
        insert.bind(3, job.request().scene_id());
        insert.bind(4, int64_t(job.state()));
        insert.bindBlob(5, job.SerializeAsString());
        if (insert.step() != SQLITE_DONE) return failure(insert);
        return Insert{job, true};
    }

    Result<std::optional<v1::Job>> getJob(const std::string& id) override {
        std::lock_guard<std::mutex> lock(mutex_);
        return findOne("SELECT record FROM jobs WHERE id = ?", id);
    }

    Result<std::optional<v1::Job>> findJobByRequestId(const std::string& requestId) override {
        std::lock_guard<std::mutex> lock(mutex_);
        return findOne("SELECT record FROM jobs WHERE request_id = ?", requestId);
    }

    Status updateJob(const v1::Job& job) override {
        std::lock_guard<std::mutex> lock(mutex_);
        Statement update(db_, "UPDATE jobs SET state = ?, record = ? WHERE id = ?");
        update.bind(1, int64_t(job.state()));
        update.bindBlob(2, job.SerializeAsString());
        update.bind(3, job.id());
        if (update.step() != SQLITE_DONE) return failure(update);
        if (sqlite3_changes(db_) != 1) return Status::error(path_ + ": job " + job.id() + " is not stored");
        return Status::ok();
    }

    Result<JobPage> listJobs(v1::JobState state, uint64_t before, uint32_t limit) override {
        std::lock_guard<std::mutex> lock(mutex_);
        Statement query(
            db_,
            "SELECT position, record FROM jobs WHERE (? = 0 OR state = ?) AND (? = 0 OR position < ?) "
            "ORDER BY position DESC LIMIT ?");
        query.bind(1, int64_t(state));
        query.bind(2, int64_t(state));
        query.bind(3, int64_t(before));
        query.bind(4, int64_t(before));
        query.bind(5, int64_t(limit) + 1);
        JobPage page;
        int rc;
        while ((rc = query.step()) == SQLITE_ROW) {
            if (page.jobs.size() == limit) {
                page.more = true;
                break;
            }
            auto job = parseRecord<v1::Job>(query.blob(1));
            if (!job) return job.status();
            page.jobs.push_back(std::move(*job));
            page.last = uint64_t(query.integer(0));
        }
        if (rc != SQLITE_ROW && rc != SQLITE_DONE) return failure(query);
        return page;
    }

    Result<std::vector<v1::Job>> unfinishedJobs() override {
        std::lock_guard<std::mutex> lock(mutex_);
        Statement query(db_, "SELECT record FROM jobs WHERE state IN (?, ?) ORDER BY position");
        query.bind(1, int64_t(v1::JOB_STATE_QUEUED));
        query.bind(2, int64_t(v1::JOB_STATE_RUNNING));
        std::vector<v1::Job> jobs;
        int rc;
        while ((rc = query.step()) == SQLITE_ROW) {
            auto job = parseRecord<v1::Job>(query.blob(0));
            if (!job) return job.status();
            jobs.push_back(std::move(*job));
        }
        if (rc != SQLITE_DONE) return failure(query);
        return jobs;
    }

    Result<bool> sceneInUse(const std::string& sceneId) override {
        std::lock_guard<std::mutex> lock(mutex_);
        Statement query(db_, "SELECT 1 FROM jobs WHERE scene_id = ? AND state IN (?, ?) LIMIT 1");
        query.bind(1, sceneId);
        query.bind(2, int64_t(v1::JOB_STATE_QUEUED));
        query.bind(3, int64_t(v1::JOB_STATE_RUNNING));
        const int rc = query.step();
        if (rc != SQLITE_ROW && rc != SQLITE_DONE) return failure(query);
        return rc == SQLITE_ROW;
    }

private:
    Status failure(const Statement& statement) const {
        return Status::error(path_ + ": " + statement.sql() + ": " + statement.error());
    }

    Result<std::optional<v1::Scene>> getSceneLocked(const std::string& id) {
        Statement query(db_, "SELECT record FROM scenes WHERE id = ?");
        query.bind(1, id);
        const int rc = query.step();
        if (rc == SQLITE_DONE) return std::optional<v1::Scene>();
        if (rc != SQLITE_ROW) return failure(query);
        auto scene = parseRecord<v1::Scene>(query.blob(0));
        if (!scene) return scene.status();
        return std::optional<v1::Scene>(std::move(*scene));
    }

    template <typename Message>
    Result<std::optional<Message>> getRecordLocked(const char* sql, const std::string& key) {
        Statement query(db_, sql);
        query.bind(1, key);
        const int rc = query.step();
        if (rc == SQLITE_DONE) return std::optional<Message>();
        if (rc != SQLITE_ROW) return failure(query);
        auto record = parseRecord<Message>(query.blob(0));
        if (!record) return record.status();
        return std::optional<Message>(std::move(*record));
    }

    Result<std::optional<v1::Job>> findOne(const char* sql, const std::string& key) {
        Statement query(db_, sql);
        query.bind(1, key);
        const int rc = query.step();
        if (rc == SQLITE_DONE) return std::optional<v1::Job>();
        if (rc != SQLITE_ROW) return failure(query);
        auto job = parseRecord<v1::Job>(query.blob(0));
        if (!job) return job.status();
        return std::optional<v1::Job>(std::move(*job));
    }

    std::mutex mutex_;
    sqlite3* db_;
    std::string path_;
};

Status execute(sqlite3* db, const std::string& path, const char* sql) {
    char* message = nullptr;
    if (sqlite3_exec(db, sql, nullptr, nullptr, &message) == SQLITE_OK) return Status::ok();
    std::string text = path + ": " + sql + ": " + (message ? message : "unknown SQLite error");
    sqlite3_free(message);
    return Status::error(text);
}

// The migrations from the stored version to kSqliteSchemaVersion, in one transaction (IMMEDIATE:
// two servers opening one file at once migrate one after the other).
Status migrateInTransaction(sqlite3* db, const std::string& path) {
    VASTRAY_TRY(execute(db, path, "CREATE TABLE IF NOT EXISTS schema_version (version INTEGER NOT NULL)"));
    std::vector<int64_t> versions;
    {
        Statement query(db, "SELECT version FROM schema_version");
        int rc;
        while ((rc = query.step()) == SQLITE_ROW) versions.push_back(query.integer(0));
        if (rc != SQLITE_DONE) return Status::error(path + ": " + query.sql() + ": " + query.error());
    }
    if (versions.size() > 1)
        return Status::error(path + ": schema_version holds " + std::to_string(versions.size()) +
                             " rows; expected one");
    if (versions.empty()) VASTRAY_TRY(execute(db, path, "INSERT INTO schema_version(version) VALUES(0)"));
    const int64_t version = versions.empty() ? 0 : versions[0];
    if (version > kSqliteSchemaVersion || version < 0)
        return Status::error(path + ": the database has schema version " + std::to_string(version) +
                             "; this vastray knows versions up to " + std::to_string(kSqliteSchemaVersion) +
                             " (a newer vastray wrote it: run that one)");
    for (int64_t next = version + 1; next <= kSqliteSchemaVersion; ++next) {
        Status step = execute(db, path, kMigrations[next - 1]);
        if (!step) return step.withContext("migration to schema version " + std::to_string(next) + ": ");
        const std::string set = "UPDATE schema_version SET version = " + std::to_string(next);
        VASTRAY_TRY(execute(db, path, set.c_str()));
    }
    return Status::ok();
}

Status migrate(sqlite3* db, const std::string& path) {
    VASTRAY_TRY(execute(db, path, "BEGIN IMMEDIATE"));
    const Status migrated = migrateInTransaction(db, path);
    VASTRAY_TRY(execute(db, path, migrated ? "COMMIT" : "ROLLBACK"));
    return migrated;
}

}  // namespace

Result<MetadataStores> openSqliteStores(const std::filesystem::path& databasePath) {
    const std::string path = databasePath.string();
    sqlite3* db = nullptr;
    if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX,
                        nullptr) != SQLITE_OK) {
        std::string message = path + ": " + (db ? sqlite3_errmsg(db) : "cannot open");
        sqlite3_close(db);
        return Status::error(message);
    }
    auto store = std::make_shared<SqliteStore>(db, path);
    sqlite3_busy_timeout(db, 5000);
    // WAL: readers never block the writer; synchronous=FULL: a commit that returned survives
    // a power loss, not only a crash of the process.
    VASTRAY_TRY(execute(db, path, "PRAGMA journal_mode=WAL; PRAGMA synchronous=FULL;"));
    VASTRAY_TRY(migrate(db, path));
    return MetadataStores{store, store, nullptr, store};
}

}  // namespace vastray::server
