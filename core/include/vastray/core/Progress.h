#pragma once
// Progress of long work on stderr: a redrawn bar on a TTY, plain "label: 40% (...)" lines
// otherwise (logs, CI). advance() may be called from any thread.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>

namespace vastray {

class Progress {
public:
    enum class Mode { Auto, Bar, Lines, None };
    // Told the work done after every advance() and once more at finish() (done == total), from
    // the thread that advanced: it must be thread-safe and cheap (a job's progress field).
    using Observer = std::function<void(uint64_t done, uint64_t total)>;

    Progress(std::string label, uint64_t total, Mode mode = Mode::Auto, Observer observer = {});
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    void advance(uint64_t amount);
    // The work is complete: prints 100% once. Destroying an unfinished Progress (an error
    // path) prints how far it got instead.
    void finish();

private:
    void end(bool complete);
    void print(uint64_t done, bool final);

    std::string label_;
    uint64_t total_;
    Mode mode_;
    Observer observer_;
    std::atomic<uint64_t> done_{0};
    std::mutex printMutex_;
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point lastPrint_;
    int lastDecile_ = -1;
    bool finished_ = false;
};

}  // namespace vastray
