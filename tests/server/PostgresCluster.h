#pragma once
// A throw-away PostgreSQL 15 cluster for one test process (Debian's `postgresql`, whose
// initdb and pg_ctl live in /usr/lib/postgresql/15/bin): a fresh /tmp/vastray-pg-XXXXXX
// folder, listening only on a unix socket in that folder (no TCP port: parallel tests cannot
// collide), trust authentication for the superuser `vastray`, fsync off (test data need not
// survive a power loss). PostgreSQL refuses to run as root; as root (CI) the cluster runs as
// `nobody` through runuser. Every step is bounded in time. The destructor stops it
// (pg_ctl stop -m immediate) and deletes the folder, also when the test failed; a test process
// killed before its destructor ran leaves a folder whose owner pid is gone, and the next
// start() stops and deletes those.
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "CommandRunner.h"

namespace vastray::test {

class PostgresCluster {
public:
    static constexpr const char* kBin = "/usr/lib/postgresql/15/bin";

    PostgresCluster() = default;
    PostgresCluster(const PostgresCluster&) = delete;
    PostgresCluster& operator=(const PostgresCluster&) = delete;
    ~PostgresCluster() { stop(); }

    // initdb, start, CREATE DATABASE vastray; "" on success, else what failed with its output.
    std::string start() {
        removeStaleClusters();
        char pattern[] = "/tmp/vastray-pg-XXXXXX";
        if (!::mkdtemp(pattern)) return "mkdtemp failed";
        dir_ = pattern;
        std::ofstream(dir_ / "owner-pid") << ::getpid();
        if (::geteuid() == 0) {
            const CommandResult own = runShell("chown nobody " + dir_.string());
            if (own.exitCode != 0) return "chown nobody: " + own.output;
        }
        const CommandResult init = asOwner("timeout 60 " + std::string(kBin) + "/initdb -D " + data() +
                                           " -U vastray -A trust -E UTF8 --no-sync");
        if (init.exitCode != 0) return "initdb: " + init.output;
        const std::string options = "-c listen_addresses='' -k " + dir_.string() + " -c fsync=off";
        const CommandResult started = asOwner(std::string(kBin) + "/pg_ctl -D " + data() + " -o \"" + options +
                                              "\" -l " + (dir_ / "server.log").string() + " -w -t 30 start");
        if (started.exitCode != 0) return "pg_ctl start: " + started.output + "\n" + serverLog();
        running_ = true;
        const CommandResult created = psql("postgres", "CREATE DATABASE vastray");
        if (created.exitCode != 0) return "CREATE DATABASE: " + created.output;
        return "";
    }

    void stop() {
        if (dir_.empty()) return;
        if (running_) asOwner(std::string(kBin) + "/pg_ctl -D " + data() + " -m immediate -w -t 30 stop");
        running_ = false;
        std::error_code error;
        std::filesystem::remove_all(dir_, error);
        dir_.clear();
    }

    // The libpq URL of `database` (through the socket folder).
    std::string url(const std::string& database = "vastray") const {
        return "postgresql://vastray@/" + database + "?host=" + dir_.string();
    }

    // Runs SQL through psql (bounded); its exit code and output.
    CommandResult psql(const std::string& database, const std::string& sql) const {
        return runShell("timeout 30 " + std::string(kBin) + "/psql -X -q -A -t -v ON_ERROR_STOP=1 '" +
                        url(database) + "' -c \"" + sql + "\"");
    }

    std::string serverLog() const {
        std::ifstream in(dir_ / "server.log");
        return std::string(std::istreambuf_iterator<char>(in), {});
    }

private:
    std::string data() const { return (dir_ / "data").string(); }

    static CommandResult asOwner(const std::string& command) {
        return runShell(::geteuid() == 0 ? "runuser -u nobody -- " + command : command);
    }

    // Clusters of test processes that died before their destructor ran.
    static void removeStaleClusters() {
        std::error_code error;
        for (const auto& entry : std::filesystem::directory_iterator("/tmp", error)) {
            const std::string name = entry.path().filename().string();
            if (name.rfind("vastray-pg-", 0) != 0) continue;
            pid_t owner = 0;
            std::ifstream(entry.path() / "owner-pid") >> owner;
            if (owner <= 0 || ::kill(owner, 0) == 0 || errno != ESRCH) continue;
            asOwner(std::string(kBin) + "/pg_ctl -D " + (entry.path() / "data").string() +
                    " -m immediate -w -t 30 stop");
            std::filesystem::remove_all(entry.path(), error);
        }
    }

    std::filesystem::path dir_;
    bool running_ = false;
};

}  // namespace vastray::test
