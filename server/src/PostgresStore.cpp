// SceneCatalog and JobStore in PostgreSQL through libpq: the records and the behaviour of
// SqliteStore.cpp (serialized proto messages, with columns only to look them up and order
// them). One connection, one statement at a time behind a mutex, as SqliteStore; a connection
// lost between statements is re-opened once before the next statement.
//
// One server per database: open() takes a session advisory lock that a second `vastray serve`
// on the same database cannot take (its queue lives in memory and would run the first's
// jobs). PostgreSQL drops the lock with the connection, so a killed server frees it.
#include <libpq-fe.h>

#include <memory>
#include <mutex>

#include "vastray/server/Storage.h"

namespace vastray::server {
namespace {

// schema_version.version N means kMigrations[0..N-1] have run, each in the transaction that
// set N. New versions are appended, never edited.
const char* const kMigrations[] = {
    // 1: scenes and jobs, as SQLite's version 1.
    "CREATE TABLE scenes ("
    " position BIGINT GENERATED ALWAYS AS IDENTITY PRIMARY KEY,"
    " id TEXT NOT NULL UNIQUE,"
    " record BYTEA NOT NULL);"
    "CREATE TABLE jobs ("
    " position BIGINT GENERATED ALWAYS AS IDENTITY PRIMARY KEY,"
    " id TEXT NOT NULL UNIQUE,"
    " request_id TEXT UNIQUE,"
    " scene_id TEXT NOT NULL,"
    " state INTEGER NOT NULL,"
    " record BYTEA NOT NULL);"
    "CREATE INDEX jobs_by_state ON jobs(state, position);"
    "CREATE INDEX jobs_by_scene ON jobs(scene_id, state);",
};
static_assert(std::size(kMigrations) == size_t(kSchemaVersion));

// Advisory lock keys (any 64-bit values; "vastray" in ASCII, then 1 and 2).
constexpr const char* kMigrationLock = "SELECT pg_advisory_xact_lock(32496010093605121)";
constexpr const char* kServerLock = "SELECT pg_try_advisory_lock(32496010093605122)";

using ResultPtr = std::unique_ptr<PGresult, decltype(&PQclear)>;

// Parameters of one statement, all sent as text except records (binary bytea).
class Params {
public:
    Params& text(const std::string& value) { return add(value, 0, false); }
    Params& integer(int64_t value) { return add(std::to_string(value), 0, false); }
    Params& bytes(const std::string& value) { return add(value, 1, false); }
    Params& null() { return add("", 0, true); }

    int count() const { return int(values_.size()); }
    std::vector<const char*> pointers() const {
        std::vector<const char*> out;
        for (size_t i = 0; i < values_.size(); ++i) out.push_back(nulls_[i] ? nullptr : values_[i].data());
        return out;
    }
    std::vector<int> lengths() const {
        std::vector<int> out;
        for (const auto& v : values_) out.push_back(int(v.size()));
        return out;
    }
    const std::vector<int>& formats() const { return formats_; }

private:
    Params& add(std::string value, int format, bool isNull) {
        values_.push_back(std::move(value));
        formats_.push_back(format);
        nulls_.push_back(isNull);
        return *this;
    }
    std::vector<std::string> values_;
    std::vector<int> formats_;
    std::vector<bool> nulls_;
};

std::string trimmed(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    return text;
}

// A bytea column of a text-format result.
std::string byteaValue(const PGresult* result, int row, int column) {
    size_t length = 0;
    unsigned char* raw =
        PQunescapeBytea(reinterpret_cast<const unsigned char*>(PQgetvalue(result, row, column)), &length);
    if (!raw) return "";
    std::string bytes(reinterpret_cast<const char*>(raw), length);
    PQfreemem(raw);
    return bytes;
}

int64_t integerValue(const PGresult* result, int row, int column) {
    return std::stoll(PQgetvalue(result, row, column));
}

template <typename Message>
Result<Message> parseRecord(const std::string& bytes, const std::string& where) {
    Message message;
    if (!message.ParseFromString(bytes)) return Status::error(where + ": a stored record does not parse");
    return message;
}

class PostgresStore final : public SceneCatalog, public JobStore {
public:
    PostgresStore(PGconn* conn, std::string display) : conn_(conn), display_(std::move(display)) {}
    ~PostgresStore() override { PQfinish(conn_); }

    // Migrates the schema to kSchemaVersion (one transaction), then takes the server lock.
    Status prepare() {
        VASTRAY_TRY(migrate());
        auto locked = run(kServerLock, Params());
        if (!locked) return locked.status();
        if (std::string(PQgetvalue(locked->get(), 0, 0)) != "t")
            return Status::error(display_ +
                                 ": another `vastray serve` uses this database (one server per database)");
        return Status::ok();
    }

    Result<v1::Scene> insertScene(const v1::Scene& scene) override {
        std::lock_guard<std::mutex> lock(mutex_);
        VASTRAY_TRY(run("INSERT INTO scenes(id, record) VALUES($1, $2) ON CONFLICT (id) DO NOTHING",
                        Params().text(scene.id()).bytes(scene.SerializeAsString())));
        auto stored = getSceneLocked(scene.id());
        if (!stored) return stored.status();
        if (!*stored) return Status::error(display_ + ": scene " + scene.id() + " vanished after insert");
        return **stored;
    }

    Result<std::optional<v1::Scene>> getScene(const std::string& id) override {
        std::lock_guard<std::mutex> lock(mutex_);
        return getSceneLocked(id);
    }

    Result<ScenePage> listScenes(uint64_t after, uint32_t limit) override {
        std::lock_guard<std::mutex> lock(mutex_);
        auto rows = run("SELECT position, record FROM scenes WHERE position > $1 ORDER BY position LIMIT $2",
                        Params().integer(int64_t(after)).integer(int64_t(limit) + 1));
        if (!rows) return rows.status();
        ScenePage page;
        for (int row = 0; row < PQntuples(rows->get()); ++row) {
            if (page.scenes.size() == limit) {
                page.more = true;
                break;
            }
            auto scene = parseRecord<v1::Scene>(byteaValue(rows->get(), row, 1), display_);
            if (!scene) return scene.status();
            page.scenes.push_back(std::move(*scene));
            page.last = uint64_t(integerValue(rows->get(), row, 0));
        }
        return page;
    }

    Status deleteScene(const std::string& id) override {
        std::lock_guard<std::mutex> lock(mutex_);
        return run("DELETE FROM scenes WHERE id = $1", Params().text(id)).status();
    }

    Result<Insert> insertJob(const v1::Job& job) override {
        std::lock_guard<std::mutex> lock(mutex_);
        const std::string& requestId = job.request().request_id();
        Params params;
        params.text(job.id());
        requestId.empty() ? params.null() : params.text(requestId);
        params.text(job.request().scene_id()).integer(int64_t(job.state())).bytes(job.SerializeAsString());
        // A request id already used inserts nothing; the job it made is returned instead.
        auto inserted = run(
            "INSERT INTO jobs(id, request_id, scene_id, state, record) VALUES($1, $2, $3, $4, $5) "
            "ON CONFLICT (request_id) DO NOTHING",
            params);
        if (!inserted) return inserted.status();
        if (std::string(PQcmdTuples(inserted->get())) == "1") return Insert{job, true};
        auto existing = findOne("SELECT record FROM jobs WHERE request_id = $1", requestId);
        if (!existing) return existing.status();
        if (!*existing) return Status::error(display_ + ": job with request_id " + requestId + " vanished");
        return Insert{**existing, false};
    }

    Result<std::optional<v1::Job>> getJob(const std::string& id) override {
        std::lock_guard<std::mutex> lock(mutex_);
        return findOne("SELECT record FROM jobs WHERE id = $1", id);
    }

    Result<std::optional<v1::Job>> findJobByRequestId(const std::string& requestId) override {
        std::lock_guard<std::mutex> lock(mutex_);
        return findOne("SELECT record FROM jobs WHERE request_id = $1", requestId);
    }

    Status updateJob(const v1::Job& job) override {
        std::lock_guard<std::mutex> lock(mutex_);
        auto updated = run("UPDATE jobs SET state = $1, record = $2 WHERE id = $3",
                           Params().integer(int64_t(job.state())).bytes(job.SerializeAsString()).text(job.id()));
        if (!updated) return updated.status();
        if (std::string(PQcmdTuples(updated->get())) != "1")
            return Status::error(display_ + ": job " + job.id() + " is not stored");
        return Status::ok();
    }

    Result<JobPage> listJobs(v1::JobState state, uint64_t before, uint32_t limit) override {
        std::lock_guard<std::mutex> lock(mutex_);
        auto rows = run(
            "SELECT position, record FROM jobs WHERE ($1 = 0 OR state = $1) AND ($2 = 0 OR position < $2) "
            "ORDER BY position DESC LIMIT $3",
            Params().integer(int64_t(state)).integer(int64_t(before)).integer(int64_t(limit) + 1));
        if (!rows) return rows.status();
        JobPage page;
        for (int row = 0; row < PQntuples(rows->get()); ++row) {
            if (page.jobs.size() == limit) {
                page.more = true;
                break;
            }
            auto job = parseRecord<v1::Job>(byteaValue(rows->get(), row, 1), display_);
            if (!job) return job.status();
            page.jobs.push_back(std::move(*job));
            page.last = uint64_t(integerValue(rows->get(), row, 0));
        }
        return page;
    }

    Result<std::vector<v1::Job>> unfinishedJobs() override {
        std::lock_guard<std::mutex> lock(mutex_);
        auto rows = run("SELECT record FROM jobs WHERE state IN ($1, $2) ORDER BY position",
                        Params().integer(v1::QUEUED).integer(v1::RUNNING));
        if (!rows) return rows.status();
        std::vector<v1::Job> jobs;
        for (int row = 0; row < PQntuples(rows->get()); ++row) {
            auto job = parseRecord<v1::Job>(byteaValue(rows->get(), row, 0), display_);
            if (!job) return job.status();
            jobs.push_back(std::move(*job));
        }
        return jobs;
    }

    Result<bool> sceneInUse(const std::string& sceneId) override {
        std::lock_guard<std::mutex> lock(mutex_);
        auto rows = run("SELECT 1 FROM jobs WHERE scene_id = $1 AND state IN ($2, $3) LIMIT 1",
                        Params().text(sceneId).integer(v1::QUEUED).integer(v1::RUNNING));
        if (!rows) return rows.status();
        return PQntuples(rows->get()) > 0;
    }

private:
    // Runs one statement; an error names the database (no password) and the statement.
    Result<ResultPtr> run(const char* sql, const Params& params) {
        if (PQstatus(conn_) != CONNECTION_OK) VASTRAY_TRY(reconnect());
        const auto values = params.pointers();
        const auto lengths = params.lengths();
        // PQexec for statements without parameters: a migration holds several.
        ResultPtr result(params.count() == 0
                             ? PQexec(conn_, sql)
                             : PQexecParams(conn_, sql, params.count(), nullptr, values.data(), lengths.data(),
                                            params.formats().data(), 0),
                         &PQclear);
        const ExecStatusType status = result ? PQresultStatus(result.get()) : PGRES_FATAL_ERROR;
        if (status == PGRES_COMMAND_OK || status == PGRES_TUPLES_OK) return result;
        const std::string why = result ? PQresultErrorMessage(result.get()) : PQerrorMessage(conn_);
        return Status::error(display_ + ": " + sql + ": " + trimmed(why));
    }

    // After a lost connection: a new one must take the server lock again (another server may
    // have started on the database meanwhile).
    Status reconnect() {
        PQreset(conn_);
        if (PQstatus(conn_) != CONNECTION_OK)
            return Status::error(display_ + ": connection lost: " + trimmed(PQerrorMessage(conn_)));
        auto locked = run(kServerLock, Params());
        if (!locked) return locked.status();
        if (std::string(PQgetvalue(locked->get(), 0, 0)) != "t")
            return Status::error(display_ + ": reconnected, but another `vastray serve` uses this database now");
        return Status::ok();
    }

    Status migrate() {
        VASTRAY_TRY(run("BEGIN", Params()));
        Status migrated = migrateInTransaction();
        VASTRAY_TRY(run(migrated ? "COMMIT" : "ROLLBACK", Params()));
        return migrated;
    }

    Status migrateInTransaction() {
        // Two servers opening an empty database at once: the second waits, then finds it migrated.
        VASTRAY_TRY(run(kMigrationLock, Params()));
        VASTRAY_TRY(run("CREATE TABLE IF NOT EXISTS schema_version (version INTEGER NOT NULL)", Params()));
        auto rows = run("SELECT version FROM schema_version", Params());
        if (!rows) return rows.status();
        if (PQntuples(rows->get()) > 1)
            return Status::error(display_ + ": schema_version holds " + std::to_string(PQntuples(rows->get())) +
                                 " rows; expected one");
        int64_t version = 0;
        if (PQntuples(rows->get()) == 1) {
            version = integerValue(rows->get(), 0, 0);
        } else {
            VASTRAY_TRY(run("INSERT INTO schema_version(version) VALUES(0)", Params()));
        }
        if (version > kSchemaVersion || version < 0)
            return Status::error(display_ + ": the database has schema version " + std::to_string(version) +
                                 "; this vastray knows versions up to " + std::to_string(kSchemaVersion) +
                                 " (a newer vastray wrote it: run that one)");
        for (int64_t next = version + 1; next <= kSchemaVersion; ++next) {
            Status step = run(kMigrations[next - 1], Params()).status();
            if (!step) return step.withContext("migration to schema version " + std::to_string(next) + ": ");
            VASTRAY_TRY(run("UPDATE schema_version SET version = $1", Params().integer(next)));
        }
        return Status::ok();
    }

    Result<std::optional<v1::Scene>> getSceneLocked(const std::string& id) {
        auto rows = run("SELECT record FROM scenes WHERE id = $1", Params().text(id));
        if (!rows) return rows.status();
        if (PQntuples(rows->get()) == 0) return std::optional<v1::Scene>();
        auto scene = parseRecord<v1::Scene>(byteaValue(rows->get(), 0, 0), display_);
        if (!scene) return scene.status();
        return std::optional<v1::Scene>(std::move(*scene));
    }

    Result<std::optional<v1::Job>> findOne(const char* sql, const std::string& key) {
        auto rows = run(sql, Params().text(key));
        if (!rows) return rows.status();
        if (PQntuples(rows->get()) == 0) return std::optional<v1::Job>();
        auto job = parseRecord<v1::Job>(byteaValue(rows->get(), 0, 0), display_);
        if (!job) return job.status();
        return std::optional<v1::Job>(std::move(*job));
    }

    std::mutex mutex_;
    PGconn* conn_;
    std::string display_;
};

bool startsWith(const std::string& text, const std::string& prefix) { return text.rfind(prefix, 0) == 0; }

}  // namespace

std::string redactDatabaseUrl(const std::string& url) {
    std::string out = url;
    // The password of the user info: scheme://user:PASSWORD@host...
    const size_t scheme = out.find("://");
    if (scheme != std::string::npos) {
        const size_t authorityStart = scheme + 3;
        const size_t authorityEnd = std::min(out.find_first_of("/?", authorityStart), out.size());
        const size_t at = out.rfind('@', authorityEnd - 1);
        if (at != std::string::npos && at >= authorityStart) {
            const size_t colon = out.find(':', authorityStart);
            if (colon != std::string::npos && colon < at) out.erase(colon, at - colon);
        }
    }
    // password=... among the query parameters.
    const size_t query = out.find('?');
    if (query != std::string::npos) {
        std::string kept;
        size_t start = query + 1;
        while (start <= out.size()) {
            const size_t end = std::min(out.find('&', start), out.size());
            const std::string item = out.substr(start, end - start);
            if (!item.empty() && !startsWith(item, "password="))
                kept += (kept.empty() ? "" : "&") + item;
            start = end + 1;
        }
        out = out.substr(0, query) + (kept.empty() ? "" : "?" + kept);
    }
    return out;
}

Result<MetadataStores> openPostgresStores(const std::string& url) {
    const std::string display = redactDatabaseUrl(url);
    if (!startsWith(url, "postgresql://") && !startsWith(url, "postgres://"))
        return Status::error("--database '" + display + "': expected a URL postgresql://[USER[:PASSWORD]@]HOST[:PORT]/DATABASE");
    char* parseError = nullptr;
    PQconninfoOption* parsed = PQconninfoParse(url.c_str(), &parseError);
    if (!parsed) {
        // libpq's message quotes the URL, password included.
        std::string why = parseError ? trimmed(parseError) : "not a connection URL";
        PQfreemem(parseError);
        for (size_t at = why.find(url); at != std::string::npos; at = why.find(url, at + display.size()))
            why.replace(at, url.size(), display);
        return Status::error("--database '" + display + "': " + why);
    }
    PQconninfoFree(parsed);
    // A host that never answers must not hang the start: 10 s unless the URL says otherwise
    // (the URL's own connect_timeout comes later and wins).
    const char* keywords[] = {"connect_timeout", "dbname", nullptr};
    const char* values[] = {"10", url.c_str(), nullptr};
    PGconn* conn = PQconnectdbParams(keywords, values, 1);
    if (!conn) return Status::error(display + ": out of memory");
    if (PQstatus(conn) != CONNECTION_OK) {
        const std::string why = trimmed(PQerrorMessage(conn));
        PQfinish(conn);
        return Status::error(display + ": cannot connect: " + why);
    }
    // Notices ("relation ... already exists, skipping") are not errors: not printed.
    PQsetNoticeProcessor(conn, [](void*, const char*) {}, nullptr);
    auto store = std::make_shared<PostgresStore>(conn, display);
    VASTRAY_TRY(store->prepare());
    return MetadataStores{store, store};
}

}  // namespace vastray::server
