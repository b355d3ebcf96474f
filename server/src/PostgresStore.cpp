// SceneCatalog, EnvironmentCatalog and JobStore in PostgreSQL through libpq: the records and the behaviour of
// SqliteStore.cpp (serialized proto messages, with columns only to look them up and order
// them). One connection, one statement at a time behind a mutex, as SqliteStore; a connection
// lost between statements is re-opened once before the next statement.
//
// One server per database: open() takes a session advisory lock that a second `vastray serve`
// on the same database cannot take (its queue lives in memory and would run the first's
// jobs). PostgreSQL drops the lock with the connection, so a killed server frees it.
#include <libpq-fe.h>

#include <chrono>
#include <memory>
#include <mutex>
#include <thread>

#include "JobRequest.h"
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
    // 2: tasks, the tiles of jobs that replicas lease (tile -1: assembling the result). state 0
    // waiting, 1 leased (by owner until lease_until), 2 done. attempts: leases so far;
    // failures: attempts that failed or lost their lease.
    "CREATE TABLE tasks ("
    " job_id TEXT NOT NULL REFERENCES jobs(id) ON DELETE CASCADE,"
    " tile INTEGER NOT NULL,"
    " priority INTEGER NOT NULL,"
    " job_position BIGINT NOT NULL,"
    " state INTEGER NOT NULL DEFAULT 0,"
    " owner TEXT,"
    " lease_until TIMESTAMPTZ,"
    " attempts INTEGER NOT NULL DEFAULT 0,"
    " failures INTEGER NOT NULL DEFAULT 0,"
    " PRIMARY KEY (job_id, tile));"
    "CREATE INDEX tasks_to_lease ON tasks(state, priority DESC, job_position, tile);",
    // 3: environments (SceneService.UploadEnvironment), as SQLite's version 2.
    "CREATE TABLE environments ("
    " position BIGINT GENERATED ALWAYS AS IDENTITY PRIMARY KEY,"
    " id TEXT NOT NULL UNIQUE,"
    " record BYTEA NOT NULL);",
};
static_assert(std::size(kMigrations) == size_t(kPostgresSchemaVersion));

// Advisory lock keys (any 64-bit values; "vastray" in ASCII, then 1 and 2).
constexpr const char* kMigrationLock = "SELECT pg_advisory_xact_lock(32496010093605121)";
// One server takes it exclusively; replicas share it: a single server and replicas never run
// on one database together.
constexpr const char* kServerLock = "SELECT pg_try_advisory_lock(32496010093605122)";
constexpr const char* kReplicaLock = "SELECT pg_try_advisory_lock_shared(32496010093605122)";
// A server that has just closed its connection holds the lock until its backend process has
// ended, which PostgreSQL does after the client has gone: a server restarted at once (or a
// test that reopens the database) asks again for this long before it is refused.
constexpr auto kServerLockWait = std::chrono::seconds(2);
constexpr auto kServerLockRetry = std::chrono::milliseconds(25);

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

constexpr int kWaiting = 0, kLeased = 1, kDone = 2;

class PostgresStore final : public SceneCatalog, public EnvironmentCatalog, public JobStore, public TaskStore {
public:
    PostgresStore(PGconn* conn, std::string display, bool replicas)
        : conn_(conn), display_(std::move(display)), replicas_(replicas) {}
    ~PostgresStore() override { PQfinish(conn_); }

    // Migrates the schema to kPostgresSchemaVersion (one transaction), then takes the server
    // lock (exclusive for one server, shared among replicas).
    Status prepare() {
        VASTRAY_TRY(migrate());
        return takeServerLock("");
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

    Result<v1::Environment> insertEnvironment(const v1::Environment& environment) override {
        std::lock_guard<std::mutex> lock(mutex_);
        VASTRAY_TRY(run("INSERT INTO environments(id, record) VALUES($1, $2) ON CONFLICT (id) DO NOTHING",
                        Params().text(environment.id()).bytes(environment.SerializeAsString())));
        auto stored = getEnvironmentLocked(environment.id());
        if (!stored) return stored.status();
        if (!*stored) return Status::error(display_ + ": environment " + environment.id() + " vanished after insert");
        return **stored;
    }

    Result<std::optional<v1::Environment>> getEnvironment(const std::string& id) override {
        std::lock_guard<std::mutex> lock(mutex_);
        return getEnvironmentLocked(id);
    }

    Result<EnvironmentPage> listEnvironments(uint64_t after, uint32_t limit) override {
        std::lock_guard<std::mutex> lock(mutex_);
        auto rows = run("SELECT position, record FROM environments WHERE position > $1 ORDER BY position LIMIT $2",
                        Params().integer(int64_t(after)).integer(int64_t(limit) + 1));
        if (!rows) return rows.status();
        EnvironmentPage page;
        for (int row = 0; row < PQntuples(rows->get()); ++row) {
            if (page.environments.size() == limit) {
                page.more = true;
                break;
            }
            auto environment = parseRecord<v1::Environment>(byteaValue(rows->get(), row, 1), display_);
            if (!environment) return environment.status();
            page.environments.push_back(std::move(*environment));
            page.last = uint64_t(integerValue(rows->get(), row, 0));
        }
        return page;
    }

    Status deleteEnvironment(const std::string& id) override {
        std::lock_guard<std::mutex> lock(mutex_);
        return run("DELETE FROM environments WHERE id = $1", Params().text(id)).status();
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
        auto updated =
            run("UPDATE jobs SET state = $1, record = $2 WHERE id = $3",
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
                        Params().integer(v1::JOB_STATE_QUEUED).integer(v1::JOB_STATE_RUNNING));
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
                        Params().text(sceneId).integer(v1::JOB_STATE_QUEUED).integer(v1::JOB_STATE_RUNNING));
        if (!rows) return rows.status();
        return PQntuples(rows->get()) > 0;
    }

    Result<Insert> insertJobWithTasks(const v1::Job& job, uint32_t tiles) override {
        std::lock_guard<std::mutex> lock(mutex_);
        const std::string& requestId = job.request().request_id();
        VASTRAY_TRY(run("BEGIN", Params()));
        Params params;
        params.text(job.id());
        requestId.empty() ? params.null() : params.text(requestId);
        params.text(job.request().scene_id()).integer(int64_t(job.state())).bytes(job.SerializeAsString());
        auto inserted = run(
            "INSERT INTO jobs(id, request_id, scene_id, state, record) VALUES($1, $2, $3, $4, $5) "
            "ON CONFLICT (request_id) DO NOTHING RETURNING position",
            params);
        if (inserted && PQntuples(inserted->get()) == 1) {
            auto tasks = run(
                "INSERT INTO tasks(job_id, tile, priority, job_position) SELECT $1, g, $2, $3 FROM "
                "generate_series(-1, $4 - 1) AS g",
                Params()
                    .text(job.id())
                    .integer(job.request().priority())
                    .integer(integerValue(inserted->get(), 0, 0))
                    .integer(tiles));
            if (!tasks) return rollback(tasks.status());
            VASTRAY_TRY(run("COMMIT", Params()));
            return Insert{job, true};
        }
        Status failed = inserted ? Status::ok() : inserted.status();
        VASTRAY_TRY(run("ROLLBACK", Params()));
        if (!failed) return failed;
        auto existing = findOne("SELECT record FROM jobs WHERE request_id = $1", requestId);
        if (!existing) return existing.status();
        if (!*existing) return Status::error(display_ + ": job with request_id " + requestId + " vanished");
        return Insert{**existing, false};
    }

    Result<std::optional<Lease>> leaseTask(const std::string& owner, double seconds, uint32_t maxAttempts) override {
        std::lock_guard<std::mutex> lock(mutex_);
        // Each round leases a task, or fails one whose lease expired too often and looks again.
        for (int round = 0; round < 64; ++round) {
            VASTRAY_TRY(run("BEGIN", Params()));
            auto found = run(
                "SELECT t.job_id, t.tile, t.state, coalesce(t.owner, ''), t.attempts, t.failures "
                "FROM tasks t JOIN jobs j ON j.id = t.job_id "
                "WHERE j.state IN ($1, $2) AND (t.state = $3 OR (t.state = $4 AND t.lease_until < now())) "
                "AND (t.tile >= 0 OR NOT EXISTS (SELECT 1 FROM tasks u WHERE u.job_id = t.job_id "
                "AND u.tile >= 0 AND u.state <> $5)) "
                "ORDER BY t.priority DESC, t.job_position, t.tile LIMIT 1 FOR UPDATE OF t SKIP LOCKED",
                Params().integer(v1::JOB_STATE_QUEUED).integer(v1::JOB_STATE_RUNNING).integer(kWaiting).integer(kLeased).integer(kDone));
            if (!found) return rollback(found.status());
            if (PQntuples(found->get()) == 0) {
                VASTRAY_TRY(run("COMMIT", Params()));
                return std::optional<Lease>();
            }
            Lease lease;
            lease.jobId = PQgetvalue(found->get(), 0, 0);
            lease.tile = int32_t(integerValue(found->get(), 0, 1));
            const bool expired = integerValue(found->get(), 0, 2) == kLeased;
            const std::string previousOwner = PQgetvalue(found->get(), 0, 3);
            const int64_t attempts = integerValue(found->get(), 0, 4);
            int64_t failures = integerValue(found->get(), 0, 5);
            auto job = lockJob(lease.jobId);
            if (!job) return rollback(job.status());
            if (expired) {
                ++failures;
                job->add_attempt_errors(taskName(lease.tile) + " attempt " + std::to_string(attempts) + " (replica " +
                                        previousOwner +
                                        "): its lease expired (the replica stopped renewing it: crashed, killed or "
                                        "cut off)");
            }
            if (expired && uint64_t(failures) >= maxAttempts) {
                VASTRAY_TRY(failJobLocked(*job, lease, failures, maxAttempts));
                continue;
            }
            auto leased = run(
                "UPDATE tasks SET state = $3, owner = $4, lease_until = now() + make_interval(secs => $5), "
                "attempts = attempts + 1, failures = $6 WHERE job_id = $1 AND tile = $2 RETURNING attempts",
                Params()
                    .text(lease.jobId)
                    .integer(lease.tile)
                    .integer(kLeased)
                    .text(owner)
                    .text(std::to_string(seconds))
                    .integer(failures));
            if (!leased) return rollback(leased.status());
            lease.attempt = uint32_t(integerValue(leased->get(), 0, 0));
            if (job->state() == v1::JOB_STATE_QUEUED) {
                job->set_state(v1::JOB_STATE_RUNNING);
                *job->mutable_start_time() = nowTimestamp();
            }
            job->set_attempts(std::max(job->attempts(), lease.attempt));
            if (Status stored = storeJobLocked(*job); !stored) return rollback(stored);
            VASTRAY_TRY(run("COMMIT", Params()));
            lease.job = *job;
            return std::optional<Lease>(std::move(lease));
        }
        return std::optional<Lease>();
    }

    Result<bool> renewLease(const Lease& lease, const std::string& owner, double seconds) override {
        std::lock_guard<std::mutex> lock(mutex_);
        auto renewed = run(
            "UPDATE tasks t SET lease_until = now() + make_interval(secs => $5) FROM jobs j "
            "WHERE t.job_id = $1 AND t.tile = $2 AND t.owner = $3 AND t.attempts = $4 AND t.state = $6 "
            "AND j.id = t.job_id AND j.state IN ($7, $8)",
            Params()
                .text(lease.jobId)
                .integer(lease.tile)
                .text(owner)
                .integer(lease.attempt)
                .text(std::to_string(seconds))
                .integer(kLeased)
                .integer(v1::JOB_STATE_QUEUED)
                .integer(v1::JOB_STATE_RUNNING));
        if (!renewed) return renewed.status();
        return std::string(PQcmdTuples(renewed->get())) == "1";
    }

    Result<Completion> completeTile(const Lease& lease, const std::string& owner, double seconds) override {
        std::lock_guard<std::mutex> lock(mutex_);
        VASTRAY_TRY(run("BEGIN", Params()));
        auto held = markDoneLocked(lease, owner);
        if (!held) return rollback(held.status());
        auto job = *held ? lockJob(lease.jobId) : Result<v1::Job>(Status::error(""));
        if (!*held || (job && isFinal(job->state()))) {
            VASTRAY_TRY(run("ROLLBACK", Params()));
            return Completion{};
        }
        if (!job) return rollback(job.status());
        // Serialized by the job row's lock: of two replicas finishing the last two tiles, the
        // second sees the first's tile done, and only it leases the assemble task.
        auto counts = run(
            "SELECT count(*) FILTER (WHERE state = $2), count(*) FROM tasks WHERE job_id = $1 AND tile >= 0",
            Params().text(lease.jobId).integer(kDone));
        if (!counts) return rollback(counts.status());
        const int64_t done = integerValue(counts->get(), 0, 0), total = integerValue(counts->get(), 0, 1);
        job->set_progress(total ? 100.0 * double(done) / double(total) : 0);
        if (Status stored = storeJobLocked(*job); !stored) return rollback(stored);
        Completion completion{true, std::nullopt};
        if (done == total) {
            auto assemble = run(
                "UPDATE tasks SET state = $3, owner = $4, lease_until = now() + make_interval(secs => $5), "
                "attempts = attempts + 1 WHERE job_id = $1 AND tile = $2 AND state = $6 RETURNING attempts",
                Params()
                    .text(lease.jobId)
                    .integer(kAssembleTile)
                    .integer(kLeased)
                    .text(owner)
                    .text(std::to_string(seconds))
                    .integer(kWaiting));
            if (!assemble) return rollback(assemble.status());
            if (PQntuples(assemble->get()) == 1)
                completion.assemble = Lease{lease.jobId, kAssembleTile,
                                            uint32_t(integerValue(assemble->get(), 0, 0)), *job};
        }
        VASTRAY_TRY(run("COMMIT", Params()));
        return completion;
    }

    Result<bool> completeJob(const Lease& lease, const std::string& owner, const v1::Job& finished) override {
        std::lock_guard<std::mutex> lock(mutex_);
        VASTRAY_TRY(run("BEGIN", Params()));
        auto held = markDoneLocked(lease, owner);
        if (!held) return rollback(held.status());
        auto job = *held ? lockJob(lease.jobId) : Result<v1::Job>(Status::error(""));
        if (!*held || (job && isFinal(job->state()))) {
            VASTRAY_TRY(run("ROLLBACK", Params()));
            return false;
        }
        if (!job) return rollback(job.status());
        // The stored record (attempt errors other replicas added) with the result's fields.
        job->set_state(finished.state());
        job->set_progress(finished.progress());
        job->set_error(finished.error());
        *job->mutable_end_time() = finished.end_time();
        job->set_result_bytes(finished.result_bytes());
        *job->mutable_stats() = finished.stats();
        if (Status stored = storeJobLocked(*job); !stored) return rollback(stored);
        VASTRAY_TRY(run("COMMIT", Params()));
        return true;
    }

    Status failTask(const Lease& lease, const std::string& owner, const std::string& reason,
                    uint32_t maxAttempts, bool permanent) override {
        std::lock_guard<std::mutex> lock(mutex_);
        VASTRAY_TRY(run("BEGIN", Params()));
        auto freed = run(
            "UPDATE tasks SET state = $5, owner = NULL, lease_until = NULL, failures = failures + 1 "
            "WHERE job_id = $1 AND tile = $2 AND owner = $3 AND attempts = $4 AND state = $6 RETURNING failures",
            Params()
                .text(lease.jobId)
                .integer(lease.tile)
                .text(owner)
                .integer(lease.attempt)
                .integer(kWaiting)
                .integer(kLeased));
        if (!freed) return rollback(freed.status()).status();
        if (PQntuples(freed->get()) == 0) return run("ROLLBACK", Params()).status();  // lost meanwhile
        const int64_t failures = integerValue(freed->get(), 0, 0);
        auto job = lockJob(lease.jobId);
        if (!job) return rollback(job.status()).status();
        if (isFinal(job->state())) return run("ROLLBACK", Params()).status();
        job->add_attempt_errors(reason);
        if (permanent || uint64_t(failures) >= maxAttempts) {
            if (Status failed = failJobLocked(*job, lease, failures, maxAttempts, permanent ? reason : "");
                !failed)
                return failed;
            return Status::ok();
        }
        if (Status stored = storeJobLocked(*job); !stored) return rollback(stored).status();
        return run("COMMIT", Params()).status();
    }

    // The leaseable tiles leaseTask chooses among (its WHERE clause without the assemble task),
    // counted; docs/DEPLOY.md describes the figure.
    Result<uint64_t> countWaitingTiles() override {
        std::lock_guard<std::mutex> lock(mutex_);
        auto rows = run(
            "SELECT count(*) FROM tasks t JOIN jobs j ON j.id = t.job_id "
            "WHERE j.state IN ($1, $2) AND t.tile >= 0 AND (t.state = $3 OR (t.state = $4 AND t.lease_until < now()))",
            Params().integer(v1::JOB_STATE_QUEUED).integer(v1::JOB_STATE_RUNNING).integer(kWaiting).integer(kLeased));
        if (!rows) return rows.status();
        return uint64_t(integerValue(rows->get(), 0, 0));
    }

private:
    static std::string taskName(int32_t tile) {
        return tile == kAssembleTile ? std::string("assembling") : "tile " + std::to_string(tile);
    }

    // Ends the open transaction with ROLLBACK and returns `why`.
    Status rollback(const Status& why) {
        run("ROLLBACK", Params());
        return why;
    }

    Result<v1::Job> lockJob(const std::string& id) {
        auto rows = run("SELECT record FROM jobs WHERE id = $1 FOR UPDATE", Params().text(id));
        if (!rows) return rows.status();
        if (PQntuples(rows->get()) == 0) return Status::error(display_ + ": job " + id + " is not stored");
        return parseRecord<v1::Job>(byteaValue(rows->get(), 0, 0), display_);
    }

    Status storeJobLocked(const v1::Job& job) {
        return run("UPDATE jobs SET state = $1, record = $2 WHERE id = $3",
                   Params().integer(int64_t(job.state())).bytes(job.SerializeAsString()).text(job.id()))
            .status();
    }

    // The held task (owner, attempt, still leased) marked done; false when not held.
    Result<bool> markDoneLocked(const Lease& lease, const std::string& owner) {
        auto done = run(
            "UPDATE tasks SET state = $5, lease_until = NULL WHERE job_id = $1 AND tile = $2 AND owner = $3 "
            "AND attempts = $4 AND state = $6",
            Params()
                .text(lease.jobId)
                .integer(lease.tile)
                .text(owner)
                .integer(lease.attempt)
                .integer(kDone)
                .integer(kLeased));
        if (!done) return done.status();
        return std::string(PQcmdTuples(done->get())) == "1";
    }

    // In the open transaction: the job FAILED after `failures` failed attempts of one task (its
    // task freed, so that nothing leases it: the job is final), committed.
    // `error`: the job's error; empty: the attempts that failed (failedAttemptsMessage).
    Status failJobLocked(v1::Job& job, const Lease& lease, int64_t failures, uint32_t maxAttempts,
                         const std::string& error = "") {
        job.set_state(v1::JOB_STATE_FAILED);
        job.set_error(!error.empty() ? error
                                     : failedAttemptsMessage(job, maxAttempts) + " (" + taskName(lease.tile) +
                                           " failed " + std::to_string(failures) + " times)");
        *job.mutable_end_time() = nowTimestamp();
        auto freed = run("UPDATE tasks SET state = $3, owner = NULL, lease_until = NULL, failures = $4 "
                         "WHERE job_id = $1 AND tile = $2",
                         Params().text(lease.jobId).integer(lease.tile).integer(kWaiting).integer(failures));
        if (!freed) return rollback(freed.status());
        if (Status stored = storeJobLocked(job); !stored) return rollback(stored);
        return run("COMMIT", Params()).status();
    }

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
        return takeServerLock("reconnected, but ");
    }

    Status takeServerLock(const std::string& context) {
        const auto giveUp = std::chrono::steady_clock::now() + kServerLockWait;
        for (;;) {
            auto locked = run(replicas_ ? kReplicaLock : kServerLock, Params());
            if (!locked) return locked.status();
            if (std::string(PQgetvalue(locked->get(), 0, 0)) == "t") return Status::ok();
            if (std::chrono::steady_clock::now() >= giveUp) break;
            std::this_thread::sleep_for(kServerLockRetry);
        }
        return Status::error(display_ + ": " + context +
                             (replicas_ ? "a `vastray serve` without --storage uses this database (replicas need "
                                          "every server on it to be a replica)"
                                        : "another `vastray serve` uses this database (one server per database)"));
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
        if (version > kPostgresSchemaVersion || version < 0)
            return Status::error(display_ + ": the database has schema version " + std::to_string(version) +
                                 "; this vastray knows versions up to " + std::to_string(kPostgresSchemaVersion) +
                                 " (a newer vastray wrote it: run that one)");
        for (int64_t next = version + 1; next <= kPostgresSchemaVersion; ++next) {
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

    Result<std::optional<v1::Environment>> getEnvironmentLocked(const std::string& id) {
        auto rows = run("SELECT record FROM environments WHERE id = $1", Params().text(id));
        if (!rows) return rows.status();
        if (PQntuples(rows->get()) == 0) return std::optional<v1::Environment>();
        auto environment = parseRecord<v1::Environment>(byteaValue(rows->get(), 0, 0), display_);
        if (!environment) return environment.status();
        return std::optional<v1::Environment>(std::move(*environment));
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
    bool replicas_;
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

Result<MetadataStores> openPostgresStores(const std::string& url, bool replicas) {
    const std::string display = redactDatabaseUrl(url);
    if (!startsWith(url, "postgresql://") && !startsWith(url, "postgres://"))
        return Status::error("--database '" + display +
                             "': expected a URL postgresql://[USER[:PASSWORD]@]HOST[:PORT]/DATABASE");
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
    auto store = std::make_shared<PostgresStore>(conn, display, replicas);
    VASTRAY_TRY(store->prepare());
    return MetadataStores{store, store, replicas ? store : nullptr, store};
}

}  // namespace vastray::server
