// The volumes of an import (VolumeImport.h): materials checked, each .vdb read in this process
// or in a child process that sends the volume back through a pipe. No OpenVDB here: the child
// calls readVdbVolume (VdbVolume.cpp) like the caller would.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstring>
#include <type_traits>

#include "import/ImportCommon.h"
#include "vastray/streamer/VolumeImport.h"

namespace vastray {
namespace {

// A grid name sent back by the child is at most this long (readVdbVolume's are a file's strings).
constexpr uint64_t kMaxSentNameBytes = 1 << 20;
constexpr const char* kAnswerEndsEarly = "the answer ends early";

std::string colorText(const std::array<float, 3>& c) {
    std::string text;
    for (int i = 0; i < 3; ++i) {
        char digits[32];
        text += (i ? "," : "") + std::string(digits, std::to_chars(digits, digits + sizeof digits, c[i]).ptr);
    }
    return text;
}

bool colorWithin(const std::array<float, 3>& c, float max) {
    for (float x : c)
        if (!(x >= 0.0f && x <= max)) return false;
    return true;
}

// The child's end: writes all of `size` bytes or ends the child (the parent then reports it).
void writeAll(int fd, const void* data, uint64_t size) {
    const char* at = static_cast<const char*>(data);
    while (size > 0) {
        const ssize_t n = ::write(fd, at, size_t(std::min<uint64_t>(size, uint64_t(1) << 30)));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) ::_exit(2);
        at += n, size -= uint64_t(n);
    }
}

template <typename T>
void writeValue(int fd, const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    writeAll(fd, &value, sizeof value);
}

template <typename T>
void writeVector(int fd, const std::vector<T>& values) {
    writeValue(fd, uint64_t(values.size()));
    writeAll(fd, values.data(), values.size() * sizeof(T));
}

// In the child: the answer is a byte 0 and the message, or a byte 1 and the volume less what
// the parent computes again (worldToIndex, majorants, world bounds).
void sendAnswer(int fd, const Result<Volume>& volume) {
    writeValue(fd, uint8_t(volume ? 1 : 0));
    if (!volume) {
        writeValue(fd, uint64_t(volume.message().size()));
        writeAll(fd, volume.message().data(), volume.message().size());
        return;
    }
    const Volume& v = *volume;
    writeValue(fd, uint64_t(v.name.size()));
    writeAll(fd, v.name.data(), v.name.size());
    writeValue(fd, v.indexToWorld), writeValue(fd, v.origin), writeValue(fd, v.brickCells);
    writeValue(fd, v.material);
    writeVector(fd, v.brickOf), writeVector(fd, v.voxels), writeVector(fd, v.emissionVoxels);
}

// The parent's end of the pipe: exact reads until a deadline; false (with `error` set) when the
// child closed early, the deadline passed or the read failed.
class AnswerReader {
public:
    AnswerReader(int fd, std::chrono::steady_clock::time_point deadline) : fd_(fd), deadline_(deadline) {}

    bool read(void* data, uint64_t size) {
        char* at = static_cast<char*>(data);
        while (size > 0) {
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline_ - std::chrono::steady_clock::now());
            if (left.count() <= 0) return fail(true, "");
            pollfd p{fd_, POLLIN, 0};
            const int ready = ::poll(&p, 1, int(std::min<int64_t>(left.count(), 1000)));
            if (ready < 0 && errno != EINTR) return fail(false, std::string("poll: ") + std::strerror(errno));
            if (ready <= 0) continue;
            const ssize_t n = ::read(fd_, at, size_t(std::min<uint64_t>(size, uint64_t(1) << 30)));
            if (n < 0 && errno == EINTR) continue;
            if (n < 0) return fail(false, std::string("read: ") + std::strerror(errno));
            if (n == 0) return fail(false, kAnswerEndsEarly);
            at += n, size -= uint64_t(n);
        }
        return true;
    }

    template <typename T>
    bool value(T& out) {
        return read(&out, sizeof out);
    }

    // A vector of at most `max` elements.
    template <typename T>
    bool vector(std::vector<T>& out, uint64_t max) {
        uint64_t count = 0;
        if (!value(count)) return false;
        if (count > max) return fail(false, "the answer holds " + std::to_string(count) + " elements, above " + std::to_string(max));
        out.resize(count);
        return read(out.data(), count * sizeof(T));
    }

    bool timedOut() const { return timedOut_; }
    const std::string& error() const { return error_; }

private:
    bool fail(bool timedOut, std::string error) {
        timedOut_ = timedOut, error_ = std::move(error);
        return false;
    }

    int fd_;
    std::chrono::steady_clock::time_point deadline_;
    bool timedOut_ = false;
    std::string error_;
};

// The volume (or the child's error) from the pipe; the checks it passed in the child are made
// again here, for a child whose memory a hostile file corrupted could send anything.
Result<Volume> receiveAnswer(AnswerReader& in, const std::string& name) {
    const Status malformed = import::errorIn(name, "the OpenVDB reader process sent a malformed answer: ");
    uint8_t ok = 0;
    uint64_t textBytes = 0;
    if (!in.value(ok) || !in.value(textBytes)) return Status::error(malformed.message() + in.error());
    if (textBytes > kMaxSentNameBytes) return Status::error(malformed.message() + "a text of " + std::to_string(textBytes) + " bytes");
    std::string text(textBytes, '\0');
    if (!in.read(text.data(), textBytes)) return Status::error(malformed.message() + in.error());
    if (!ok) return Status::error(text);
    Volume v;
    v.name = std::move(text);
    if (!in.value(v.indexToWorld) || !in.value(v.origin) || !in.value(v.brickCells) || !in.value(v.material) ||
        !in.vector(v.brickOf, kMaxVolumeBrickCells) || !in.vector(v.voxels, kMaxVolumeBricks * kVolumeBrickVoxels) ||
        !in.vector(v.emissionVoxels, kMaxVolumeBricks * kVolumeBrickVoxels))
        return Status::error(malformed.message() + in.error());
    v.majorant.assign(v.brickOf.size(), 0.0f);
    std::string problem = checkVolume(v);
    if (problem.empty() && !finishVolumeTransform(v)) problem = "its transform cannot be inverted";
    if (!problem.empty()) return Status::error(malformed.message() + problem);
    computeVolumeMajorants(v);
    return v;
}

// Runs in the child: reads the volume and sends it, then ends without the parent's destructors.
[[noreturn]] void childReads(int fd, const VolumeSource& source) {
    for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGPIPE}) ::signal(sig, SIG_DFL);
    // The kernel's OOM killer takes this process before any other (raising one's own score
    // needs no privilege).
    if (const int fd = ::open("/proc/self/oom_score_adj", O_WRONLY | O_CLOEXEC); fd >= 0) {
        const ssize_t written = ::write(fd, "1000", 4);
        (void)written;  // without it the child is only as likely a choice as its size makes it
        ::close(fd);
    }
    // One thread: the parent's TBB workers do not exist here, so OpenVDB's parallel loops
    // run in an arena that asks for none.
    tbb::task_arena arena(1);
    Result<Volume> volume = Status::error("not read");
    arena.execute([&] { volume = readVdbVolume(source.path, source.grid, source.material, source.emissionGrid); });
    sendAnswer(fd, volume);
    ::_exit(0);
}

Result<Volume> readInChildProcess(const VolumeSource& source) {
    const std::string name = import::fileNameOf(source.path);
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) return import::errorIn(name, std::string("pipe: ") + std::strerror(errno));
    const pid_t child = ::fork();
    if (child < 0) {
        ::close(fds[0]), ::close(fds[1]);
        return import::errorIn(name, std::string("fork: ") + std::strerror(errno));
    }
    if (child == 0) {
        ::close(fds[0]);
        childReads(fds[1], source);
    }
    ::close(fds[1]);
    AnswerReader in(fds[0], std::chrono::steady_clock::now() + std::chrono::seconds(kVdbReadSecondsLimit));
    Result<Volume> volume = receiveAnswer(in, name);
    ::close(fds[0]);
    if (!volume) ::kill(child, SIGKILL);  // a child stuck or still writing ends here
    int status = 0;
    while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
    }
    if (in.timedOut())
        return import::errorIn(name, "OpenVDB did not finish reading the file within " +
                                         std::to_string(kVdbReadSecondsLimit) + " s; refused");
    // A child that died before its answer was whole: by its own fault, or killed from outside
    // (the OOM killer sends SIGKILL).
    if (WIFSIGNALED(status) && in.error() == kAnswerEndsEarly) {
        const int sig = WTERMSIG(status);
        return import::errorIn(name, "the OpenVDB reader process " +
                                         std::string(sig == SIGKILL ? "was killed" : "crashed") + " reading the file (signal " +
                                         std::to_string(sig) + ", " + std::string(::strsignal(sig)) +
                                         (sig == SIGKILL ? "; out of memory?" : "") + "); refused");
    }
    return volume;
}

// readVdbVolume's messages begin with the file's name: the source's label replaces it.
Status relabel(const std::string& message, const VolumeSource& source) {
    const std::string name = import::fileNameOf(source.path) + ":";
    if (message.rfind(name, 0) != 0) return Status::error(source.label + ": " + message);
    return Status::error(source.label + message.substr(name.size() - 1));
}

}  // namespace

Status checkVolumeMaterial(const VolumeMaterial& material, const VolumeFieldNames& names) {
    if (!colorWithin(material.albedo, 1.0f))
        return Status::error(names.albedo + " " + colorText(material.albedo) + " is outside [0, 1]");
    if (!(material.densityScale >= 0.0f && material.densityScale <= kMaxVolumeDensity))
        return Status::error(names.density + " " + std::to_string(material.densityScale) + " is outside [0, 1e18]");
    if (!(material.anisotropy > -1.0f && material.anisotropy < 1.0f))
        return Status::error(names.anisotropy + " " + std::to_string(material.anisotropy) + " is outside (-1, 1)");
    if (!colorWithin(material.emission, kMaxVolumeDensity))
        return Status::error(names.emissionScale + " " + colorText(material.emission) + " is outside [0, 1e18]");
    return Status::ok();
}

Result<std::vector<Volume>> readVolumes(const std::vector<VolumeSource>& sources, const VolumeReadOptions& options) {
    if (sources.size() > kMaxVolumes)
        return Status::error(std::to_string(sources.size()) + " volumes exceed the limit of " + std::to_string(kMaxVolumes));
    std::vector<Volume> volumes;
    for (const VolumeSource& source : sources) {
        VASTRAY_TRY(checkVolumeMaterial(source.material, source.names));
        auto volume = options.childProcess
                          ? readInChildProcess(source)
                          : readVdbVolume(source.path, source.grid, source.material, source.emissionGrid);
        if (!volume && !source.label.empty()) return relabel(volume.message(), source);
        if (!volume) return volume.status();
        volumes.push_back(std::move(volume).value());
    }
    return volumes;
}

}  // namespace vastray
