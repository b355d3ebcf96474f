#pragma once
// Readers that may crash, hang or take all memory on a hostile file (assimp, OpenVDB) run in a
// child process (fork) that sends its answer back through a pipe: a crash, a kill by the OOM
// killer or a read past the time limit then fails the import by the file's name, not the CLI or
// the server that called it. Private to streamer/src/import.
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

#include "vastray/core/Result.h"

namespace vastray::import {

// In the child: writes all of `size` bytes to the parent, or ends the child (exit status 2).
void writeToParent(int fd, const void* data, uint64_t size);

// The parent's end of the pipe: reads until a deadline; false (with error() set) when the
// child closed its end early, the deadline passed or the read failed.
class ChildAnswer {
public:
    ChildAnswer(int fd, std::chrono::steady_clock::time_point deadline) : fd_(fd), deadline_(deadline) {}

    // Exactly `size` bytes.
    bool read(void* data, uint64_t size);

    template <typename T>
    bool value(T& out) {
        static_assert(std::is_trivially_copyable_v<T>);
        return read(&out, sizeof out);
    }

    // A uint64 count, then that many elements, at most `max`.
    template <typename T>
    bool vector(std::vector<T>& out, uint64_t max) {
        static_assert(std::is_trivially_copyable_v<T>);
        uint64_t count = 0;
        if (!value(count)) return false;
        if (count > max) return fail(false, "the answer holds " + std::to_string(count) + " elements, above " + std::to_string(max));
        out.resize(count);
        return read(out.data(), count * sizeof(T));
    }

    // Every byte until the child closes its end.
    bool readToEnd(std::vector<uint8_t>& out);

    bool timedOut() const { return timedOut_; }
    // Whether the child closed its end (it ended, by itself or by a signal).
    bool sawEnd() const { return sawEnd_; }
    const std::string& error() const { return error_; }

private:
    // Waits for bytes until the deadline; false (with the error set) when none can come.
    bool waitForBytes();
    bool fail(bool timedOut, std::string error) {
        timedOut_ = timedOut, error_ = std::move(error);
        return false;
    }

    int fd_;
    std::chrono::steady_clock::time_point deadline_;
    bool timedOut_ = false, sawEnd_ = false;
    std::string error_;
};

// How a child's failures are worded, after the file's name: "<library> did not finish reading
// the file within N s; refused", "<process> crashed reading the file (signal 11, Segmentation
// fault); refused" ("was killed ...; out of memory?" for SIGKILL), "the <library> reader process
// failed (exit status N)".
struct ChildReader {
    std::string library;  // "assimp", "OpenVDB"
    std::string process;  // what crashes: "assimp", "the OpenVDB reader process"
    int secondsLimit;     // past this the child is killed and the file refused
    // Address space the child may map beyond what it inherits from the parent (RLIMIT_AS, set
    // in the child after the fork: the parent's own mappings, a GPU driver's reservations
    // included, do not count against it); 0: no limit. An allocation past it fails at once
    // (std::bad_alloc; childRanOutOfMemory() tells) instead of paging the machine full. A lower
    // `ulimit -v` the parent runs under is kept. Under AddressSanitizer (whose allocator dies
    // instead of failing, and serves small blocks from regions reserved at start-up) the child
    // also counts its heap, and ends past the limit; the import fails all the same, naming the
    // limit (outOfMemoryText). None under MemorySanitizer or ThreadSanitizer.
    uint64_t memoryLimitBytes = 0;
    // How the limit is computed, for messages: "4 GiB + 64 x the file's size".
    std::string memoryRule;
};

// In the child: whether an allocation (operator new) failed since the fork, which with a
// memory limit means the limit was reached. A reader that catches std::bad_alloc itself (assimp
// turns it into an error string) still fails with an error that says so.
bool childRanOutOfMemory();

// In the child: raises its memory limit by `bytes` (files a reader holds whose size only
// reading the model tells, such as texture images: they are on disk, not claimed by a header).
// Nothing without a limit.
void allowMoreChildMemory(uint64_t bytes);
// In the child: its memory limit with what allowMoreChildMemory added; 0: none.
uint64_t childMemoryLimit();

// "<library> ran out of its 4.5 GiB memory limit (<memoryRule>) reading the file; refused", or
// without a limit of its own (0) "<library> ran out of memory reading the file; refused": after
// the file's name, in the child (once childRanOutOfMemory()) and in the parent (a child the
// sanitizer's allocator ended).
std::string outOfMemoryText(const ChildReader& reader, uint64_t limit);

// "4 GiB", "1.5 GiB", "300 MiB": a memory limit in messages.
std::string memoryLimitText(uint64_t bytes);

// Forks a child that runs `child(fd)`, which writes its answer to `fd`, then ends without the
// parent's destructors or atexit handlers. A fault ends the child by its signal, whatever
// handlers the parent installed, the kernel's OOM killer takes the child before any other
// process, and the child is sent SIGKILL when the calling thread ends (its process killed, even
// by SIGKILL, included). Here `parent(answer)` reads the answer; when it fails, the child (stuck
// or still writing) is killed. The child is always reaped. Errors name `fileName`: the time limit, a
// child that died by a signal or exited non-zero before its answer was whole, or else what
// `parent` returned.
Status runInChildProcess(const std::string& fileName, const ChildReader& reader,
                         const std::function<void(int fd)>& child,
                         const std::function<Status(ChildAnswer& answer)>& parent);

}  // namespace vastray::import
