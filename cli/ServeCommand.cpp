#include <signal.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "Commands.h"
#include "vastray/core/ByteSize.h"
#include "vastray/core/ImageFile.h"
#include "vastray/server/FrontEnds.h"
#include "vastray/server/Service.h"
#include "vastray/server/Storage.h"

namespace vastray::cli {
namespace {

struct ServeArgs {
    std::string grpc = "127.0.0.1:50051", http = "127.0.0.1:8080", dataDir;
    std::string memoryBudget = "4GiB", hostCache = "2GiB", maxUpload = "16GiB";
    std::string authTokenFile, tlsCert, tlsKey, backend = "vulkan", database, storage;
    std::string gpuDevices = "-1";
    uint32_t maxQueue = 1000, maxAttempts = 3;
    double shutdownGrace = 30, leaseSeconds = 30;
    bool paused = false;
};

Result<uint64_t> sizeFlag(const char* flag, const std::string& text) {
    auto bytes = parseByteSize(text);
    if (!bytes) return Status::error(std::string(flag) + ": " + bytes.message());
    return *bytes;
}

Result<std::string> readToken(const std::string& path) {
    std::ifstream in(path);
    if (!in) return Status::error("--auth-token-file " + path + ": cannot read");
    std::string token((std::istreambuf_iterator<char>(in)), {});
    while (!token.empty() && std::isspace(static_cast<unsigned char>(token.back()))) token.pop_back();
    if (token.empty()) return Status::error("--auth-token-file " + path + ": the file is empty");
    if (token.find_first_of(" \t\r\n") != std::string::npos)
        return Status::error("--auth-token-file " + path + ": the token must be one line without spaces");
    return token;
}

Result<server::ServiceOptions> serviceOptions(const ServeArgs& args) {
    server::ServiceOptions options;
    if (args.dataDir.empty() == args.storage.empty())
        return Status::error("give one of --data-dir (one server) or --storage (replicas sharing a folder)");
    if (!args.storage.empty() && args.database.empty())
        return Status::error("--storage needs --database (the replicas share a PostgreSQL database)");
    if (!(args.leaseSeconds >= 1)) return Status::error("--lease-seconds must be at least 1");
    options.dataDir = args.storage.empty() ? args.dataDir : args.storage;
    options.sharedStorage = !args.storage.empty();
    options.leaseSeconds = args.leaseSeconds;
    auto budget = sizeFlag("--memory-budget", args.memoryBudget);
    if (!budget) return budget.status();
    auto cache = sizeFlag("--host-cache", args.hostCache);
    if (!cache) return cache.status();
    auto upload = sizeFlag("--max-upload", args.maxUpload);
    if (!upload) return upload.status();
    if (*budget == 0) return Status::error("--memory-budget must be more than 0");
    if (args.maxQueue == 0) return Status::error("--max-queue must be at least 1");
    if (args.maxAttempts == 0) return Status::error("--max-attempts must be at least 1");
    if (!(args.shutdownGrace >= 0)) return Status::error("--shutdown-grace must be >= 0 seconds");
    options.memoryBudgetBytes = *budget;
    options.hostCacheBytes = *cache;
    options.maxUploadBytes = *upload;
    options.maxQueue = args.maxQueue;
    options.maxAttempts = args.maxAttempts;
    options.databaseUrl = args.database;
    options.paused = args.paused;
    return options;
}

Result<server::FrontEndOptions> frontEndOptions(const ServeArgs& args) {
    server::FrontEndOptions options;
    if (args.tlsCert.empty() != args.tlsKey.empty())
        return Status::error("--tls-cert and --tls-key go together");
    options.tlsCertFile = args.tlsCert;
    options.tlsKeyFile = args.tlsKey;
    if (!args.authTokenFile.empty()) {
        auto token = readToken(args.authTokenFile);
        if (!token) return token.status();
        options.authToken = *token;
    }
    return options;
}

// `--gpu-device`: -1 (the default device) or device indices separated by commas, one worker
// each; an index may repeat (several workers on one device).
Result<std::vector<int>> parseGpuDevices(const std::string& text) {
    const std::string expected =
        "expected -1 or device indices separated by commas, one worker each, at most " +
        std::to_string(server::Service::kMaxWorkers);
    auto bad = [&](const std::string& why) {
        return Status::error("--gpu-device '" + text + "': " + why + "; " + expected);
    };
    std::vector<int> devices;
    size_t start = 0;
    while (true) {
        const size_t comma = std::min(text.find(',', start), text.size());
        const std::string item = text.substr(start, comma - start);
        if (item.empty()) return bad("entry " + std::to_string(devices.size() + 1) + " is empty");
        const bool digits = item.find_first_not_of("0123456789", item == "-1" ? 1 : 0) == std::string::npos;
        if (!digits) return bad("'" + item + "' is not -1 or a device index");
        if (item.size() > 10 || std::stoll(item) > INT32_MAX) return bad("'" + item + "' is past 2147483647");
        if (devices.size() == server::Service::kMaxWorkers)
            return bad("more than " + std::to_string(server::Service::kMaxWorkers) + " workers");
        devices.push_back(int(std::stoll(item)));
        if (comma == text.size()) break;
        start = comma + 1;
    }
    return devices;
}

// One streaming renderer per worker, each opening its own device and pool (--memory-budget
// each); the host cache is split evenly between them.
using Renderers = std::vector<std::unique_ptr<server::JobRenderer>>;

Result<Renderers> vulkanRenderers(const server::ServiceOptions& options, const std::vector<int>& devices) {
    Renderers renderers;
    for (int device : devices) {
        auto streaming = server::makeStreamingJobRenderer(options.hostCacheBytes / devices.size(),
                                                          options.memoryBudgetBytes, device);
        if (!streaming) {
            const std::string flag =
                device >= 0 ? "--gpu-device " + std::to_string(device) : "--backend vulkan";
            return Status::error(flag + ": " + streaming.message());
        }
        renderers.push_back(std::move(streaming).value());
    }
    return renderers;
}

int fail(const std::string& message, int code) {
    std::fprintf(stderr, "vastray serve: %s\n", message.c_str());
    return code;
}

int runServe(const ServeArgs& args) {
    // SIGTERM/SIGINT are taken by sigwait below: block them before any thread starts, so that
    // every thread inherits the mask. A peer closing a socket must not kill the server.
    sigset_t stopSignals;
    sigemptyset(&stopSignals);
    sigaddset(&stopSignals, SIGTERM);
    sigaddset(&stopSignals, SIGINT);
    pthread_sigmask(SIG_BLOCK, &stopSignals, nullptr);
    signal(SIGPIPE, SIG_IGN);

    auto options = serviceOptions(args);
    if (!options) return fail(options.message(), 2);
    auto front = frontEndOptions(args);
    if (!front) return fail(front.message(), 2);
    if (args.backend != "vulkan" && args.backend != "embree")
        return fail("--backend '" + args.backend + "': expected vulkan or embree", 2);
    auto devices = parseGpuDevices(args.gpuDevices);
    if (!devices) return fail(devices.message(), 2);
    // An Embree render already uses every core: a second worker would only halve each job's share.
    if (args.backend == "embree" && devices->size() > 1)
        return fail("--gpu-device '" + args.gpuDevices +
                        "': the embree backend runs one worker (a render uses every core); give one value "
                        "or none",
                    2);
    // Results are written through the image module: a broken install stops the start.
    if (Status images = loadImageModule(); !images) return fail(images.message(), 1);
    // The Vulkan devices open now (never for embree): a --gpu-device that does not exist or
    // cannot run the tracer stops the start, naming the devices Vulkan reports.
    Renderers renderers;
    if (args.backend == "vulkan") {
        auto vulkan = vulkanRenderers(*options, *devices);
        if (!vulkan) return fail(vulkan.message(), 1);
        renderers = std::move(vulkan).value();
    } else {
        renderers.push_back(server::makeEmbreeJobRenderer(options->hostCacheBytes));
    }
    std::vector<std::string> deviceNames;
    for (const auto& renderer : renderers) deviceNames.push_back(renderer->deviceDescription());
    auto service = server::Service::open(*options, std::move(renderers));
    if (!service) return fail(service.message(), 1);
    auto grpc = server::GrpcFrontEnd::start(**service, args.grpc, *front);
    if (!grpc) return fail(grpc.message(), 1);
    auto http = server::HttpFrontEnd::start(**service, args.http, *front);
    if (!http) return fail(http.message(), 1);
    auto host = [](const std::string& address) { return server::splitHostPort(address)->first; };
    std::printf("vastray serve: gRPC on %s:%d\n", host(args.grpc).c_str(), (*grpc)->port());
    std::printf("vastray serve: HTTP on %s:%d\n", host(args.http).c_str(), (*http)->port());
    if (deviceNames.size() == 1) {
        const std::string& device = deviceNames[0];
        std::printf("vastray serve: backend %s%s%s\n", args.backend.c_str(), device.empty() ? "" : " on ",
                    device.c_str());
    } else {
        std::printf("vastray serve: backend %s, %zu workers\n", args.backend.c_str(), deviceNames.size());
        for (size_t i = 0; i < deviceNames.size(); ++i)
            std::printf("vastray serve: worker %zu on %s\n", i, deviceNames[i].c_str());
    }
    const std::string jobStore =
        args.database.empty() ? (std::filesystem::path(args.dataDir) / "jobs.db").string()
                              : server::redactDatabaseUrl(args.database);
    std::printf("vastray serve: job store %s\n", jobStore.c_str());
    if (!args.storage.empty())
        std::printf("vastray serve: replica %s, tiles leased for %g s\n", (*service)->replicaId().c_str(),
                    args.leaseSeconds);
    std::printf("vastray serve: ready (data in %s%s)\n", options->dataDir.c_str(),
                args.paused ? ", paused" : "");
    std::fflush(stdout);

    int signal = 0;
    sigwait(&stopSignals, &signal);
    std::printf("vastray serve: %s: shutting down\n", signal == SIGTERM ? "SIGTERM" : "SIGINT");
    std::fflush(stdout);
    (*service)->stopAccepting();
    (*http)->stop();
    (*grpc)->shutdown(std::chrono::seconds(5));
    const auto grace = std::chrono::milliseconds(int64_t(args.shutdownGrace * 1000));
    const bool stopped = (*service)->shutdown(grace);
    for (const std::string& left : (*service)->jobsLeftRunning()) {
        // The job's record says RUNNING: the next start runs it again.
        std::printf(
            "vastray serve: job %s did not finish within --shutdown-grace; it runs again at the next start\n",
            left.c_str());
    }
    std::fflush(stdout);
    // A render that cannot be interrupted must not hold the exit up: its job is safe in the store.
    if (!stopped) std::_Exit(0);
    std::printf("vastray serve: stopped\n");
    return 0;
}

}  // namespace

CommandRun addServeCommand(CLI::App& app) {
    auto args = std::make_shared<ServeArgs>();
    CLI::App* cmd = app.add_subcommand("serve", "Run the render service (gRPC and HTTP; docs/SERVICE.md).");
    cmd->add_option("--grpc", args->grpc, "gRPC address HOST:PORT (port 0: any free port)")
        ->capture_default_str();
    cmd->add_option("--http", args->http, "HTTP address HOST:PORT (port 0: any free port)")
        ->capture_default_str();
    cmd->add_option("--data-dir", args->dataDir,
                    "folder for scenes and results, and for the job database (jobs.db, SQLite) unless "
                    "--database names one (this or --storage is required)");
    cmd->add_option("--storage", args->storage,
                    "instead of --data-dir: a folder every replica mounts (scenes, results, tiles); with "
                    "--database, replicas share the database and lease the tiles of every job (job field "
                    "tiles [nx, ny])");
    cmd->add_option("--lease-seconds", args->leaseSeconds,
                    "with --storage: how long a tile's lease lasts unless renewed (every third of it while "
                    "it renders); a replica that stops renewing loses its tiles to the others")
        ->capture_default_str();
    cmd->add_option("--database", args->database,
                    "job store in PostgreSQL instead of SQLite: postgresql://[USER[:PASSWORD]@]HOST[:PORT]/"
                    "DATABASE[?PARAM=VALUE&...] (libpq URL; the schema is created or migrated at start; one "
                    "server per database, unless --storage makes them replicas)");
    cmd->add_option("--max-attempts", args->maxAttempts,
                    "failed attempts after which a job FAILS with every attempt's reason; an attempt fails "
                    "when the server stops mid-render without handing the job back (crash, kill: found "
                    "RUNNING at the next start) or its render reports an internal error (a lost device, a "
                    "failed write; other errors fail the job at once)")
        ->capture_default_str();
    cmd->add_option("--memory-budget", args->memoryBudget,
                    "device memory pool of the vulkan backend, per worker (each --gpu-device entry has its "
                    "own): the most one job may use, and the sum that worker's open scenes may hold together")
        ->capture_default_str();
    cmd->add_option("--host-cache", args->hostCache,
                    "decoded chunks (vulkan) or scenes (embree) kept in host memory, for all jobs and open "
                    "scenes; split evenly between the workers")
        ->capture_default_str();
    cmd->add_option("--max-queue", args->maxQueue,
                    "queued render jobs, and queued import jobs (async uploads); one more is refused "
                    "(429 / RESOURCE_EXHAUSTED)")
        ->capture_default_str();
    cmd->add_option("--max-upload", args->maxUpload,
                    "largest scene upload; also the most a zip upload may expand to")
        ->capture_default_str();
    cmd->add_option("--auth-token-file", args->authTokenFile,
                    "file holding a bearer token every request must carry (health checks excepted)");
    cmd->add_option("--tls-cert", args->tlsCert, "PEM certificate: serve gRPC and HTTP over TLS");
    cmd->add_option("--tls-key", args->tlsKey, "PEM private key of --tls-cert");
    cmd->add_option("--shutdown-grace", args->shutdownGrace,
                    "seconds SIGTERM waits for the running jobs before leaving them to the next start")
        ->capture_default_str();
    cmd->add_flag("--paused", args->paused, "accept and store jobs but start none");
    cmd->add_option("--backend", args->backend,
                    "vulkan (streaming; the last job's scene stays resident for the next) | embree (CPU reference)")
        ->capture_default_str();
    cmd->add_option("--gpu-device", args->gpuDevices,
                    "vulkan: Vulkan device index (-1: first discrete GPU, else first); a list such as 0,1 "
                    "runs one worker per entry, each with its own --memory-budget, taking jobs from the one "
                    "queue at the same time (an index may repeat: 0,0 runs two workers on device 0); at "
                    "most " +
                        std::to_string(server::Service::kMaxWorkers) +
                        " entries. embree: one worker, one value")
        ->capture_default_str();
    return [args]() { return runServe(*args); };
}

}  // namespace vastray::cli
