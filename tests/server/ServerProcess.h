#pragma once
// Runs the real `vastray serve` on loopback ports chosen by the kernel (port 0), as a child
// process whose output goes to a log file, and parses the ports it prints.
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "TestTmp.h"

namespace vastray::test {

class ServerProcess {
public:
    ServerProcess() = default;
    ServerProcess(const ServerProcess&) = delete;
    ServerProcess& operator=(const ServerProcess&) = delete;
    ~ServerProcess() { kill(SIGKILL); }

    // Starts `vastray serve --data-dir DIR --grpc 127.0.0.1:0 --http 127.0.0.1:0 EXTRA...`
    // and waits for its "ready" line; false (with the log in `log()`) when it does not come.
    bool start(const std::filesystem::path& dataDir, const std::vector<std::string>& extra = {}) {
        std::vector<std::string> args = {"--data-dir", dataDir.string()};
        args.insert(args.end(), extra.begin(), extra.end());
        return startLogged(dataDir.parent_path() /
                               (dataDir.filename().string() + "-serve-" + std::to_string(starts_ + 1) + ".log"),
                           args);
    }

    // Starts `vastray serve --grpc 127.0.0.1:0 --http 127.0.0.1:0 FLAGS...` with its output in
    // `logPath`, as start() does.
    bool startLogged(const std::filesystem::path& logPath, const std::vector<std::string>& flags) {
        ++starts_;
        logPath_ = logPath;
        std::vector<std::string> args = {VASTRAY_BINARY, "serve", "--grpc", "127.0.0.1:0", "--http", "127.0.0.1:0"};
        args.insert(args.end(), flags.begin(), flags.end());
        // The child's environment, built before fork (setenv after fork is not safe in a
        // process with threads).
        std::vector<std::string> environment;
        for (char** e = environ; *e; ++e) environment.emplace_back(*e);
        for (const auto& [name, value] : environment_) environment.push_back(name + "=" + value);
        grpcPort_ = httpPort_ = 0;
        const pid_t parent = ::getpid();
        pid_ = ::fork();
        if (pid_ == 0) {
            // The server dies with the test (a crashed or killed test leaves no server behind
            // holding its ports and files); the check covers a parent gone before the prctl.
            ::prctl(PR_SET_PDEATHSIG, SIGKILL);
            if (::getppid() != parent) std::_Exit(127);
            if (addressSpaceLimit_ > 0) {
                const rlimit limit{addressSpaceLimit_, addressSpaceLimit_};
                ::setrlimit(RLIMIT_AS, &limit);
            }
            FILE* log = std::fopen(logPath_.c_str(), "w");
            ::dup2(::fileno(log), 1);
            ::dup2(::fileno(log), 2);
            std::vector<char*> argv;
            for (auto& a : args) argv.push_back(a.data());
            argv.push_back(nullptr);
            std::vector<char*> envp;
            for (auto& e : environment) envp.push_back(e.data());
            envp.push_back(nullptr);
            ::execve(argv[0], argv.data(), envp.data());
            std::_Exit(127);
        }
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
        const std::regex grpcLine(R"(gRPC on 127\.0\.0\.1:(\d+))"), httpLine(R"(HTTP on 127\.0\.0\.1:(\d+))");
        while (std::chrono::steady_clock::now() < deadline) {
            const std::string text = log();
            std::smatch m;
            if (text.find("vastray serve: ready") != std::string::npos) {
                if (std::regex_search(text, m, grpcLine)) grpcPort_ = std::stoi(m[1]);
                if (std::regex_search(text, m, httpLine)) httpPort_ = std::stoi(m[1]);
                return grpcPort_ > 0 && httpPort_ > 0;
            }
            int status = 0;
            if (::waitpid(pid_, &status, WNOHANG) == pid_) {
                pid_ = -1;
                exitStatus_ = status;
                return false;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        return false;
    }

    // Later starts have NAME=VALUE in their environment, besides this process's.
    void setEnvironment(const std::string& name, const std::string& value) {
        environment_.emplace_back(name, value);
    }

    // Waits up to `timeout` for the process to end by itself; its wait status, or -1 when it
    // still runs (or none was started). A process that ended during start() counts.
    int waitExit(std::chrono::seconds timeout) {
        if (pid_ <= 0) return starts_ > 0 ? exitStatus_ : -1;
        const auto deadline = std::chrono::steady_clock::now() + timeout;
        while (std::chrono::steady_clock::now() < deadline) {
            int status = 0;
            if (::waitpid(pid_, &status, WNOHANG) == pid_) {
                pid_ = -1;
                exitStatus_ = status;
                return status;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        return -1;
    }

    // The next start runs under this address-space limit (ulimit -v), in bytes; 0: none.
    void setAddressSpaceLimit(uint64_t bytes) { addressSpaceLimit_ = bytes; }

    // Sends `signal` without waiting (SIGSTOP, SIGCONT).
    void signal(int signal) {
        if (pid_ > 0) ::kill(pid_, signal);
    }

    // Sends `signal` and waits for the process; its wait status (-1 when none ran).
    int kill(int signal) {
        if (pid_ <= 0) return -1;
        ::kill(pid_, signal);
        int status = 0;
        ::waitpid(pid_, &status, 0);
        pid_ = -1;
        exitStatus_ = status;
        return status;
    }

    std::string log() const {
        std::ifstream in(logPath_);
        return std::string(std::istreambuf_iterator<char>(in), {});
    }
    int httpPort() const { return httpPort_; }
    std::string grpcAddress() const { return "127.0.0.1:" + std::to_string(grpcPort_); }

private:
    pid_t pid_ = -1;
    int exitStatus_ = 0, starts_ = 0, grpcPort_ = 0, httpPort_ = 0;
    std::filesystem::path logPath_;
    rlim_t addressSpaceLimit_ = 0;
    std::vector<std::pair<std::string, std::string>> environment_;
};

inline std::string readBytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace vastray::test
