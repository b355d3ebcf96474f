#pragma once
// The service's persistent state behind three narrow interfaces, so that a deployment of
// several replicas can put them on a shared database and an object store:
//  - ObjectStore: scene packages and result images, as immutable objects by key;
//  - SceneCatalog: one record per stored scene;
//  - JobStore: one record per job, the source of truth for its state.
// The single-machine defaults are files under --data-dir and one SQLite database (WAL).
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vastray/core/Result.h"
#include "vastray/v1/render_service.pb.h"
#include "vastray/v1/scene_service.pb.h"

namespace vastray::server {

class ObjectStore {
public:
    virtual ~ObjectStore() = default;
    // A folder for files that become objects (uploads, renders in progress); same file
    // system as the store, so that put() can rename.
    virtual std::filesystem::path scratchDir() const = 0;
    // Moves a finished local file in under `key`, atomically: readers see the whole object or
    // none. Replaces an object of the same key.
    virtual Status put(const std::string& key, const std::filesystem::path& file) = 0;
    // A local path to read the object from; an error when absent.
    virtual Result<std::filesystem::path> localPath(const std::string& key) const = 0;
    virtual Status remove(const std::string& key) = 0;
    // Bytes free for new objects.
    virtual uint64_t availableBytes() const = 0;
};

// Objects as files dataDir/KEY; scratch in dataDir/tmp (emptied on open: a crash leaves
// only partial uploads and renders there, never a partial object).
Result<std::unique_ptr<ObjectStore>> openFileObjectStore(const std::filesystem::path& dataDir);
// The same on a folder that several replicas share (`serve --storage`, NFS and the like):
// scratch in dir/tmp/REPLICA, this replica's own (a replica never empties another's).
Result<std::unique_ptr<ObjectStore>> openSharedFileObjectStore(const std::filesystem::path& dir,
                                                               const std::string& replica);

class SceneCatalog {
public:
    virtual ~SceneCatalog() = default;
    // Inserts unless a scene of that id exists; returns the stored record either way.
    virtual Result<v1::Scene> insertScene(const v1::Scene& scene) = 0;
    virtual Result<std::optional<v1::Scene>> getScene(const std::string& id) = 0;
    // Oldest first, after the scene at position `after` (0: from the start).
    struct ScenePage {
        std::vector<v1::Scene> scenes;
        uint64_t last = 0;  // position of the last scene returned
        bool more = false;
    };
    virtual Result<ScenePage> listScenes(uint64_t after, uint32_t limit) = 0;
    virtual Status deleteScene(const std::string& id) = 0;
};

// One record per stored environment map (SceneService.UploadEnvironment), as SceneCatalog's
// scenes.
class EnvironmentCatalog {
public:
    virtual ~EnvironmentCatalog() = default;
    // Inserts unless an environment of that id exists; returns the stored record either way.
    virtual Result<v1::Environment> insertEnvironment(const v1::Environment& environment) = 0;
    virtual Result<std::optional<v1::Environment>> getEnvironment(const std::string& id) = 0;
    // Oldest first, after the environment at position `after` (0: from the start).
    struct EnvironmentPage {
        std::vector<v1::Environment> environments;
        uint64_t last = 0;  // position of the last environment returned
        bool more = false;
    };
    virtual Result<EnvironmentPage> listEnvironments(uint64_t after, uint32_t limit) = 0;
    virtual Status deleteEnvironment(const std::string& id) = 0;
};

class JobStore {
public:
    virtual ~JobStore() = default;
    // Stores a new job; when job.request().request_id() is set and already used, stores
    // nothing and returns the job that id created (`created` false).
    struct Insert {
        v1::Job job;
        bool created = false;
    };
    virtual Result<Insert> insertJob(const v1::Job& job) = 0;
    virtual Result<std::optional<v1::Job>> getJob(const std::string& id) = 0;
    virtual Result<std::optional<v1::Job>> findJobByRequestId(const std::string& requestId) = 0;
    // Replaces the stored record of job.id() (durable when it returns).
    virtual Status updateJob(const v1::Job& job) = 0;
    // Newest first, before position `before` (0: from the newest); `state` unspecified: all.
    struct JobPage {
        std::vector<v1::Job> jobs;
        uint64_t last = 0;
        bool more = false;
    };
    virtual Result<JobPage> listJobs(v1::JobState state, uint64_t before, uint32_t limit) = 0;
    // QUEUED and RUNNING jobs, oldest first: what a restart must run.
    virtual Result<std::vector<v1::Job>> unfinishedJobs() = 0;
    // Whether a QUEUED or RUNNING job renders this scene.
    virtual Result<bool> sceneInUse(const std::string& sceneId) = 0;
};

// The tiles of render jobs as task rows that the replicas of a `serve --storage` deployment
// lease (PostgreSQL only: SELECT ... FOR UPDATE SKIP LOCKED). A job has one task per tile and
// one assemble task (tile kAssembleTile) that can be leased once every tile is done. A lease
// lasts `seconds` unless renewed; one that expired is a failed attempt of its task, and the
// next replica takes the task over. Every call is one transaction.
class TaskStore {
public:
    static constexpr int32_t kAssembleTile = -1;
    virtual ~TaskStore() = default;
    // Stores a new job and its tasks (`tiles` tiles and the assemble task) together; a
    // request id already used stores nothing, as JobStore::insertJob.
    virtual Result<JobStore::Insert> insertJobWithTasks(const v1::Job& job, uint32_t tiles) = 0;
    struct Lease {
        std::string jobId;
        int32_t tile = 0;
        uint32_t attempt = 0;  // 1 for the task's first lease
        v1::Job job;           // the job's record when leased
    };
    // Leases the next task nobody holds (or whose lease expired) for `owner`: highest priority
    // first, then the oldest job, then the lowest tile. A task whose lease expired counts a failed
    // attempt in its job's attempt_errors; when that makes `maxAttempts` failed attempts of the
    // task, the job is FAILED and the next task is looked for. The job goes RUNNING with its
    // first lease. None: nothing to do now.
    virtual Result<std::optional<Lease>> leaseTask(const std::string& owner, double seconds,
                                                   uint32_t maxAttempts) = 0;
    // Extends the lease; false when `owner` lost it (expired and taken over, or its job was
    // cancelled or failed meanwhile).
    virtual Result<bool> renewLease(const Lease& lease, const std::string& owner, double seconds) = 0;
    // Marks a tile done (the job's progress follows). When it was the job's last, the assemble
    // task is leased to `owner` in the same transaction and returned: exactly one replica
    // assembles. `held` false: the lease was lost, nothing changed.
    struct Completion {
        bool held = false;
        std::optional<Lease> assemble;
    };
    virtual Result<Completion> completeTile(const Lease& lease, const std::string& owner, double seconds) = 0;
    // Marks the assemble task done and stores `finished` (the job SUCCEEDED) together; false
    // when the lease was lost.
    virtual Result<bool> completeJob(const Lease& lease, const std::string& owner,
                                     const v1::Job& finished) = 0;
    // A failed attempt of a held task: `reason` is appended to the job's attempt_errors and the
    // task is free again, or, at `maxAttempts` failed attempts of the task, the job is FAILED.
    // `permanent`: the attempt failed as any attempt would (an error of the request: its budget,
    // its scene gone), so the job is FAILED now with `reason` as its error.
    virtual Status failTask(const Lease& lease, const std::string& owner, const std::string& reason,
                            uint32_t maxAttempts, bool permanent) = 0;
    // The tiles a replica could lease now, over every job in the store: waiting, or leased with
    // an expired lease, of QUEUED and RUNNING jobs. Assemble tasks are not counted (they wait
    // for tiles, not for a replica). The queue depth that autoscaling reads (vastray_tasks_waiting).
    virtual Result<uint64_t> countWaitingTiles() = 0;
};

struct MetadataStores {
    std::shared_ptr<SceneCatalog> scenes;
    std::shared_ptr<JobStore> jobs;
    std::shared_ptr<TaskStore> tasks;  // PostgreSQL opened for replicas only
    std::shared_ptr<EnvironmentCatalog> environments;
};

// The schema versions the stores write, in a one-row table schema_version. Opening a store
// runs the migrations from the version it finds (0: an empty database) up to its version, in
// one transaction; a database of a newer version is an error. SQLite databases written before
// schema_version existed hold version 1's tables and are migrated as version 0.
// SQLite 1: scenes, jobs; 2: environments. PostgreSQL 1: scenes, jobs; 2: tasks (the tiles
// replicas lease); 3: environments.
constexpr int kSqliteSchemaVersion = 2;
constexpr int kPostgresSchemaVersion = 3;

// One SQLite database (WAL, synchronous=FULL) implementing both catalogs.
Result<MetadataStores> openSqliteStores(const std::filesystem::path& databasePath);

// One PostgreSQL database (libpq; `url` postgresql://[USER[:PASSWORD]@]HOST[:PORT]/DATABASE[?…])
// implementing both catalogs, with SQLite's behaviour. Without `replicas`, one server per
// database: a second one is refused. With `replicas` (`serve --storage`) any number of servers
// share it, and the TaskStore is open too. Errors name the URL without its password, and the
// failing statement.
Result<MetadataStores> openPostgresStores(const std::string& url, bool replicas = false);

// `url` without a password (in the user info or a password= parameter), for messages.
std::string redactDatabaseUrl(const std::string& url);

}  // namespace vastray::server
