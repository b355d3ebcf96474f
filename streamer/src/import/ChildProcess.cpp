#include "import/ChildProcess.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <new>

#include "import/ImportCommon.h"

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#include <sanitizer/allocator_interface.h>
#include <sanitizer/asan_interface.h>
#endif
#elif defined(__SANITIZE_ADDRESS__)
#include <sanitizer/allocator_interface.h>
#include <sanitizer/asan_interface.h>
#endif

namespace vastray::import {
namespace {

// One read or write moves at most this much (a pipe takes far less at a time anyway).
constexpr uint64_t kMaxTransfer = uint64_t(1) << 30;

// AddressSanitizer (make test-asan, the fuzzers): its shadow and allocator regions are reserved
// at start-up, so RLIMIT_AS over what the child inherits still bounds new mappings (a large
// block's), but a failed mapping ends the process with a report instead of std::bad_alloc, and
// blocks up to 128 KiB come from the reserved region without a new mapping. The child then also
// counts its heap through the allocator's hooks, and either way ends with kOutOfMemoryExit
// (limitMemory). MemorySanitizer and ThreadSanitizer: no limit.
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define VASTRAY_ASAN_HEAP 1
#elif __has_feature(memory_sanitizer) || __has_feature(thread_sanitizer)
#define VASTRAY_SANITIZER_SHADOW 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) && !defined(VASTRAY_ASAN_HEAP)
#define VASTRAY_ASAN_HEAP 1
#endif
#if defined(__SANITIZE_THREAD__) && !defined(VASTRAY_SANITIZER_SHADOW)
#define VASTRAY_SANITIZER_SHADOW 1
#endif

// The child's exit status when its parent was gone before it could ask to die with it.
constexpr int kParentGoneExit = 5;
// The child's exit status when it crossed its memory limit where no std::bad_alloc can be thrown
// (AddressSanitizer's allocator hooks, or its out-of-memory report): the parent words it
// (outOfMemoryText).
constexpr int kOutOfMemoryExit = 4;

// Set in the child by the new-handler once an allocation failed.
volatile sig_atomic_t ranOutOfMemory = 0;
// In the child: the limit's allowance once it is set (limitMemory, allowMoreChildMemory).
uint64_t memoryAllowance = 0;
// In the child: a page shared with the parent (runInChildProcess) where the allowance is kept,
// so that the parent can name the limit of a child that ended with kOutOfMemoryExit.
std::atomic<uint64_t>* sharedAllowance = nullptr;

void setAllowance(uint64_t bytes) {
    memoryAllowance = bytes;
    if (sharedAllowance) sharedAllowance->store(bytes, std::memory_order_relaxed);
}

void noteOutOfMemory() {
    ranOutOfMemory = 1;
    throw std::bad_alloc();
}

// The address space this process has mapped (/proc/self/statm's first field); 0 if unknown.
uint64_t mappedBytes() {
    const int fd = ::open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
    if (fd < 0) return 0;
    char text[64] = {};
    const ssize_t n = ::read(fd, text, sizeof text - 1);
    ::close(fd);
    if (n <= 0) return 0;
    unsigned long long pages = 0;
    if (std::sscanf(text, "%llu", &pages) != 1) return 0;
    return uint64_t(pages) * uint64_t(::sysconf(_SC_PAGESIZE));
}

#ifdef VASTRAY_ASAN_HEAP
// In the child under AddressSanitizer: heap bytes allocated since the fork less those freed
// (blocks of the parent's freed here count against it too), for the small blocks that RLIMIT_AS
// does not see. Past the allowance the child ends at once (the hook runs after the allocation,
// under callers that may be C code, through which no exception may pass).
std::atomic<int64_t> heapGrowth{0};
void countAllocation(const volatile void*, size_t size) {
    const int64_t now = heapGrowth.fetch_add(int64_t(size), std::memory_order_relaxed) + int64_t(size);
    if (memoryAllowance != 0 && now > int64_t(std::min<uint64_t>(memoryAllowance, INT64_MAX)))
        ::_exit(kOutOfMemoryExit);
}
void countFree(const volatile void* p) {
    const size_t size = __sanitizer_get_allocated_size(const_cast<const void*>(p));
    heapGrowth.fetch_sub(int64_t(size), std::memory_order_relaxed);
}

// In the child under AddressSanitizer: its report of an allocation that failed (a mapping past
// RLIMIT_AS, or a size beyond the allocator's) ends the child as the limit does.
void endOnOutOfMemoryReport(const char* report) {
    if (std::strstr(report, "out-of-memory") || std::strstr(report, "allocation-size-too-big"))
        ::_exit(kOutOfMemoryExit);
}
#endif

// In the child: at most `bytes` more address space than it inherited (see ChildReader).
void limitMemory(uint64_t bytes) {
    std::set_new_handler(noteOutOfMemory);
#ifndef VASTRAY_SANITIZER_SHADOW
    if (bytes == 0) return;
    const uint64_t inherited = mappedBytes();
    rlimit limit{};
    if (inherited == 0 || ::getrlimit(RLIMIT_AS, &limit) != 0) return;
    const uint64_t wanted = inherited + bytes;
    if (limit.rlim_cur != RLIM_INFINITY && uint64_t(limit.rlim_cur) <= wanted) return;  // a lower ulimit -v stays
    limit.rlim_cur = rlim_t(wanted);
    // Lowering one's own soft limit needs no privilege.
    if (::setrlimit(RLIMIT_AS, &limit) != 0) return;
    setAllowance(bytes);
#ifdef VASTRAY_ASAN_HEAP
    __asan_set_error_report_callback(endOnOutOfMemoryReport);
    __sanitizer_install_malloc_and_free_hooks(countAllocation, countFree);
#endif
#else
    (void)bytes;
#endif
}

// Runs in the child: `child` writes the answer, then the child ends without the parent's
// destructors or atexit handlers.
[[noreturn]] void runChild(int fd, pid_t parent, uint64_t memoryLimitBytes, const std::function<void(int)>& child) {
    // The child dies with its parent: a `vastray import` or `vastray serve` killed by SIGKILL (no
    // handler runs that could end the child) would leave its reader running until it finished
    // (its answer then meets a closed pipe) or, in a reader that hangs, for ever: the time limit
    // is the parent's to enforce. The signal comes when the thread that forked ends; that thread
    // waits for this child in runInChildProcess. A parent gone between the fork and the prctl
    // shows as another parent (init or a subreaper).
    if (::prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || ::getppid() != parent) ::_exit(kParentGoneExit);
    // A fault ends the child by its signal, whatever handlers the parent installed (the
    // sanitizers' own would turn it into an exit status).
    for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGPIPE}) ::signal(sig, SIG_DFL);
    // The kernel's OOM killer takes this process before any other (raising one's own score
    // needs no privilege).
    if (const int score = ::open("/proc/self/oom_score_adj", O_WRONLY | O_CLOEXEC); score >= 0) {
        const ssize_t written = ::write(score, "1000", 4);
        (void)written;  // without it the child is only as likely a choice as its size makes it
        ::close(score);
    }
    limitMemory(memoryLimitBytes);
    try {
        child(fd);
    } catch (...) {
        ::_exit(3);  // never unwind into the parent's code
    }
    ::_exit(0);
}

int reap(pid_t child) {
    int status = 0;
    while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
    }
    return status;
}

// Why the child failed, when it ended before its answer was whole; empty when it did not.
std::string childFailure(const ChildReader& reader, const ChildAnswer& answer, int status, uint64_t allowance) {
    if (answer.timedOut())
        return reader.library + " did not finish reading the file within " + std::to_string(reader.secondsLimit) +
               " s; refused";
    if (!answer.sawEnd()) return "";  // a whole answer, or one `parent` refused before the end
    // By its own fault, or killed from outside (the OOM killer sends SIGKILL).
    if (WIFSIGNALED(status)) {
        const int sig = WTERMSIG(status);
        return reader.process + (sig == SIGKILL ? " was killed" : " crashed") + " reading the file (signal " +
               std::to_string(sig) + ", " + std::string(::strsignal(sig)) + (sig == SIGKILL ? "; out of memory?" : "") +
               "); refused";
    }
    if (WIFEXITED(status) && WEXITSTATUS(status) == kOutOfMemoryExit) return outOfMemoryText(reader, allowance);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return "the " + reader.library + " reader process failed (exit status " + std::to_string(WEXITSTATUS(status)) +
               ")";
    return "";
}

}  // namespace

bool childRanOutOfMemory() { return ranOutOfMemory != 0; }

std::string outOfMemoryText(const ChildReader& reader, uint64_t limit) {
    if (limit == 0)  // a lower `ulimit -v` of the caller's, or no limit at all
        return reader.library + " ran out of memory reading the file; refused";
    return reader.library + " ran out of its " + memoryLimitText(limit) + " memory limit (" + reader.memoryRule +
           ") reading the file; refused";
}

void allowMoreChildMemory(uint64_t bytes) {
    rlimit limit{};
    if (memoryAllowance == 0 || bytes == 0 || ::getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return;
    const uint64_t room = limit.rlim_max == RLIM_INFINITY ? UINT64_MAX / 2 : uint64_t(limit.rlim_max);
    const uint64_t raised = std::min(room, uint64_t(limit.rlim_cur) + std::min(bytes, room));
    limit.rlim_cur = rlim_t(raised);
    if (::setrlimit(RLIMIT_AS, &limit) == 0) setAllowance(memoryAllowance + bytes);
}

uint64_t childMemoryLimit() { return memoryAllowance; }

std::string memoryLimitText(uint64_t bytes) {
    constexpr uint64_t kMiB = uint64_t(1) << 20, kGiB = uint64_t(1) << 30;
    if (bytes < kGiB) return std::to_string((bytes + kMiB - 1) / kMiB) + " MiB";
    if (bytes % kGiB == 0) return std::to_string(bytes / kGiB) + " GiB";
    char text[32];
    std::snprintf(text, sizeof text, "%.1f GiB", double(bytes) / double(kGiB));
    return text;
}

void writeToParent(int fd, const void* data, uint64_t size) {
    const char* at = static_cast<const char*>(data);
    while (size > 0) {
        const ssize_t n = ::write(fd, at, size_t(std::min(size, kMaxTransfer)));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) ::_exit(2);
        at += n, size -= uint64_t(n);
    }
}

bool ChildAnswer::waitForBytes() {
    for (;;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline_ - std::chrono::steady_clock::now());
        if (left.count() <= 0) return fail(true, "");
        pollfd p{fd_, POLLIN, 0};
        const int ready = ::poll(&p, 1, int(std::min<int64_t>(left.count(), 1000)));
        if (ready < 0 && errno != EINTR) return fail(false, std::string("poll: ") + std::strerror(errno));
        if (ready > 0) return true;
    }
}

bool ChildAnswer::read(void* data, uint64_t size) {
    char* at = static_cast<char*>(data);
    while (size > 0) {
        if (!waitForBytes()) return false;
        const ssize_t n = ::read(fd_, at, size_t(std::min(size, kMaxTransfer)));
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return fail(false, std::string("read: ") + std::strerror(errno));
        if (n == 0) {
            sawEnd_ = true;
            return fail(false, "the answer ends early");
        }
        at += n, size -= uint64_t(n);
    }
    return true;
}

bool ChildAnswer::readToEnd(std::vector<uint8_t>& out) {
    for (;;) {
        if (!waitForBytes()) return false;
        uint8_t block[1 << 16];
        const ssize_t n = ::read(fd_, block, sizeof block);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return fail(false, std::string("read: ") + std::strerror(errno));
        if (n == 0) {
            sawEnd_ = true;
            return true;
        }
        out.insert(out.end(), block, block + n);
    }
}

Status runInChildProcess(const std::string& fileName, const ChildReader& reader,
                         const std::function<void(int fd)>& child,
                         const std::function<Status(ChildAnswer& answer)>& parent) {
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) return errorIn(fileName, std::string("pipe: ") + std::strerror(errno));
    // Where the child keeps its memory limit for the parent to read (kOutOfMemoryExit).
    void* page =
        ::mmap(nullptr, sizeof(std::atomic<uint64_t>), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    auto* allowance = page == MAP_FAILED ? nullptr : new (page) std::atomic<uint64_t>(0);
    const pid_t self = ::getpid();
    const pid_t pid = ::fork();
    if (pid < 0) {
        ::close(fds[0]), ::close(fds[1]);
        if (allowance) ::munmap(page, sizeof *allowance);
        return errorIn(fileName, std::string("fork: ") + std::strerror(errno));
    }
    if (pid == 0) {
        ::close(fds[0]);
        sharedAllowance = allowance;
        runChild(fds[1], self, reader.memoryLimitBytes, child);
    }
    ::close(fds[1]);
    ChildAnswer answer(fds[0], std::chrono::steady_clock::now() + std::chrono::seconds(reader.secondsLimit));
    const Status received = parent(answer);
    ::close(fds[0]);
    if (!received.isOk()) ::kill(pid, SIGKILL);  // a child stuck or still writing ends here
    const int status = reap(pid);
    const uint64_t limit = allowance ? allowance->load(std::memory_order_relaxed) : reader.memoryLimitBytes;
    if (allowance) ::munmap(page, sizeof *allowance);
    const std::string failure = childFailure(reader, answer, status, limit);
    return failure.empty() ? received : errorIn(fileName, failure);
}

}  // namespace vastray::import
