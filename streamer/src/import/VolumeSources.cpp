// The volumes of an import (VolumeImport.h): materials checked, each .vdb opened in this process
// (its bricks stay in the file) or in a child process that writes the bricks to an unlinked
// temporary file and sends the rest back through a pipe. No OpenVDB here: the child calls
// openVdbVolume (VdbVolume.cpp) like the caller would.
#include <tbb/task_arena.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <type_traits>

#include "import/ChildProcess.h"
#include "import/ImportCommon.h"
#include "vastray/core/Blackbody.h"
#include "vastray/streamer/VolumeImport.h"

namespace vastray {
namespace {

// A grid name sent back by the child is at most this long (readVdbVolume's are a file's strings).
constexpr uint64_t kMaxSentNameBytes = 1 << 20;

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

template <typename T>
void writeValue(int fd, const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    import::writeToParent(fd, &value, sizeof value);
}

template <typename T>
void writeVector(int fd, const std::vector<T>& values) {
    writeValue(fd, uint64_t(values.size()));
    import::writeToParent(fd, values.data(), values.size() * sizeof(T));
}

// All of `size` bytes to `fd`; false (errno set) when a write fails.
bool writeAll(int fd, const void* data, uint64_t size) {
    const char* bytes = static_cast<const char*>(data);
    while (size > 0) {
        const ssize_t n = ::write(fd, bytes, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        bytes += n, size -= uint64_t(n);
    }
    return true;
}

// The temporary file a child process writes a volume's bricks to (brick b at b * brick bytes:
// densities, then emission values), already unlinked: it goes when the last volume reading it
// does. The parent reads each brick when the package writer asks for it, and checks it again
// (a child whose memory a hostile file corrupted could write anything): every value in range,
// the brick's largest density the one the child sent.
class SpooledBricks final : public VolumeBrickSource {
public:
    SpooledBricks(std::FILE* file, std::string name, std::vector<float> maximum, bool emission, bool temperature)
        : file_(file), name_(std::move(name)), maximum_(std::move(maximum)), emission_(emission),
          temperature_(temperature) {}
    ~SpooledBricks() override { std::fclose(file_); }

    Status readBrick(uint32_t volume, uint32_t brick, float* density, float* emission, uint8_t*) const override {
        const std::string name = name_ + "brick " + std::to_string(brick);
        if (volume != 0 || brick >= maximum_.size()) return Status::error(name + " does not exist");
        const uint64_t bytes = 4ull * kVolumeBrickVoxels;
        const off_t at = off_t(brick * bytes * (emission_ ? 2 : 1));
        if (::pread(fileno(file_), density, bytes, at) != ssize_t(bytes) ||
            (emission_ && ::pread(fileno(file_), emission, bytes, at + off_t(bytes)) != ssize_t(bytes)))
            return Status::error(name + ": cannot read it back from its temporary file: " + std::strerror(errno));
        float largest = 0.0f;
        for (uint32_t i = 0; i < kVolumeBrickVoxels; ++i) {
            if (!(density[i] >= 0.0f && density[i] <= kMaxVolumeDensity))
                return Status::error(name + " voxel " + std::to_string(i) + " has density " + std::to_string(density[i]));
            largest = std::max(largest, density[i]);
            if (emission_ && !(emission[i] >= 0.0f && emission[i] <= (temperature_ ? kMaxTemperature : kMaxVolumeDensity)))
                return Status::error(name + " emission voxel " + std::to_string(i) + " has the value " +
                                     std::to_string(emission[i]));
        }
        if (largest != maximum_[brick])
            return Status::error(name + ": its largest density " + std::to_string(largest) + " is not the one sent (" +
                                 std::to_string(maximum_[brick]) + ")");
        return Status::ok();
    }

private:
    std::FILE* file_;
    std::string name_;  // "fog.vdb: the OpenVDB reader process sent a malformed answer: "
    std::vector<float> maximum_;
    bool emission_, temperature_;
};

// In the child: opens the volume, writes its bricks to `spool` in order, then answers with a
// byte 0 and the message, or a byte 1 and the volume less its voxels and what the parent
// computes again (worldToIndex, majorants, world bounds), and each brick's largest density.
void sendAnswer(int fd, int spool, const std::string& fileName, Result<Volume> volume) {
    std::vector<float> maximum;
    if (volume) {
        const bool emission = volume->hasEmission();
        std::vector<float> brick(kVolumeBrickVoxels * (emission ? 2 : 1));
        for (uint64_t b = 0; volume && b < volume->brickCount(); ++b) {
            if (Status s = readVolumeBrick(*volume, b, brick.data(), emission ? brick.data() + kVolumeBrickVoxels : nullptr); !s)
                volume = s;
            else if (!writeAll(spool, brick.data(), brick.size() * 4))
                volume = import::errorIn(fileName, std::string("cannot write its bricks to a temporary file: ") +
                                                       std::strerror(errno));
            else
                maximum.push_back(*std::max_element(brick.begin(), brick.begin() + kVolumeBrickVoxels));
        }
    }
    writeValue(fd, uint8_t(volume ? 1 : 0));
    if (!volume) {
        writeValue(fd, uint64_t(volume.message().size()));
        import::writeToParent(fd, volume.message().data(), volume.message().size());
        return;
    }
    const Volume& v = *volume;
    writeValue(fd, uint64_t(v.name.size()));
    import::writeToParent(fd, v.name.data(), v.name.size());
    writeValue(fd, v.indexToWorld), writeValue(fd, v.origin), writeValue(fd, v.brickCells);
    writeValue(fd, v.material), writeValue(fd, uint8_t(v.hasEmission()));
    writeVector(fd, v.brickOf), writeVector(fd, maximum);
}

// The volume (or the child's error) from the pipe, its bricks left in `spool`; the checks it
// passed in the child are made again here, for a child whose memory a hostile file corrupted
// could send anything.
Result<Volume> receiveAnswer(import::ChildAnswer& in, const std::string& name, std::FILE* spool) {
    const Status malformed = import::errorIn(name, "the OpenVDB reader process sent a malformed answer: ");
    uint8_t ok = 0, emission = 0;
    uint64_t textBytes = 0;
    if (!in.value(ok) || !in.value(textBytes)) return Status::error(malformed.message() + in.error());
    if (textBytes > kMaxSentNameBytes) return Status::error(malformed.message() + "a text of " + std::to_string(textBytes) + " bytes");
    std::string text(textBytes, '\0');
    if (!in.read(text.data(), textBytes)) return Status::error(malformed.message() + in.error());
    if (!ok) return Status::error(text);
    Volume v;
    v.name = std::move(text);
    std::vector<float> maximum;
    if (!in.value(v.indexToWorld) || !in.value(v.origin) || !in.value(v.brickCells) || !in.value(v.material) ||
        !in.value(emission) || !in.vector(v.brickOf, kMaxVolumeBrickCells) || !in.vector(maximum, kMaxVolumeBricks))
        return Status::error(malformed.message() + in.error());
    for (float m : maximum)
        if (!(m >= 0.0f && m <= kMaxVolumeDensity))
            return Status::error(malformed.message() + "a brick's largest density " + std::to_string(m));
    struct stat st {};
    const uint64_t bytes = maximum.size() * 4ull * kVolumeBrickVoxels * (emission ? 2 : 1);
    if (::fstat(fileno(spool), &st) != 0 || uint64_t(st.st_size) != bytes)
        return Status::error(malformed.message() + "its bricks' temporary file is not " + std::to_string(bytes) + " bytes");
    const uint64_t count = maximum.size();
    v.bricks = {std::make_shared<SpooledBricks>(spool, malformed.message(), maximum, emission != 0, v.material.temperature),
                0, count, emission != 0};
    v.majorant.assign(v.brickOf.size(), 0.0f);
    std::string problem = checkVolume(v);
    if (problem.empty() && !finishVolumeTransform(v)) problem = "its transform cannot be inverted";
    if (!problem.empty()) return Status::error(malformed.message() + problem);
    computeVolumeMajorants(v, maximum);
    return v;
}

// The memory the OpenVDB child may take beyond what it inherits (ChildReader::memoryLimitBytes):
// kVdbMemoryBaseBytes plus kVdbMemoryPerFileByte times the .vdb file's size. What an honest file
// needs while it is opened (openVdbVolume; its bricks go to the temporary file one at a time):
// - bounded by the volume limits, whatever the file's size (active tiles make cells and bricks
//   out of a few bytes): the cell table and majorants (8 bytes a cell, 2^24 cells: 128 MiB), and
//   per brick its largest value (twice), its sources in the file (8 bytes a grid) and the
//   answer's copy (2^22 bricks: about 160 MiB); the base leaves room for these and the libraries.
//   Measured at the limits (2^22 bricks of active tiles in a grid of 16.4 M cells, a 10 KB file,
//   an 8 GiB temporary file): within this limit, 221 MB resident at the peak;
// - in proportion to the file: OpenVDB's topology. A leaf takes ~110 bytes for its 64-byte mask
//   in the file (and 16 bytes in the nonzero leaves' list); an internal node 8 bytes per child
//   slot (32 KiB, 256 KiB) for its two masks in the file (1 KiB, 8 KiB): at most ~33x the file.
//   A grid read whole (a file written to a stream, or of format 221 or older) holds its leaves'
//   voxels too: 2 KiB for at least 129 bytes of file (two masks and a compression byte), ~17x.
//   The multiple doubles the larger.
// What it catches: a length field that claims more than the file could hold (OpenVDB allocates a
// string, a metadata value or a compressed block as long as the file says before reading it): a
// grid name claiming 2^31 - 1 bytes in a 10 KB file took 2.1 GB and 1.7 s before its read failed;
// now the allocation fails at once.
constexpr uint64_t kVdbMemoryBaseBytes = uint64_t(1) << 30;
constexpr uint64_t kVdbMemoryPerFileByte = 64;

import::ChildReader vdbReader(const std::string& path) {
    std::error_code ec;
    const uint64_t size = std::filesystem::file_size(path, ec);
    const uint64_t limit =
        kVdbMemoryBaseBytes + (ec ? 0 : std::min<uint64_t>(size, kMaxVdbFileBytes) * kVdbMemoryPerFileByte);
    return {"OpenVDB", "the OpenVDB reader process", kVdbReadSecondsLimit, limit,
            import::memoryLimitText(kVdbMemoryBaseBytes) + " + " + std::to_string(kVdbMemoryPerFileByte) +
                " x the file's size"};
}

// Runs in the child: opens the volume (one thread: the parent's TBB workers do not exist here,
// so OpenVDB's parallel loops run in an arena that asks for none) and sends it. An error after
// an allocation failed names the memory limit.
void childReads(int fd, int spool, const VolumeSource& source) {
    const std::string name = import::fileNameOf(source.path);
    tbb::task_arena arena(1);
    arena.execute([&] {
        Result<Volume> volume = openVdbVolume(source.path, source.grid, source.material, source.emissionGrid);
        if (!volume && import::childRanOutOfMemory())
            volume = import::errorIn(name, import::outOfMemoryText(vdbReader(source.path), import::childMemoryLimit()));
        sendAnswer(fd, spool, name, std::move(volume));
    });
}

Result<Volume> readInChildProcess(const VolumeSource& source) {
    const std::string name = import::fileNameOf(source.path);
    std::FILE* spool = std::tmpfile();  // unlinked already; closed by the volume's brick source
    if (!spool) return import::errorIn(name, std::string("cannot create a temporary file for its bricks: ") + std::strerror(errno));
    bool owned = false;  // once the volume's source holds it
    Result<Volume> volume = Status::error("no answer");
    const Status status = import::runInChildProcess(
        name, vdbReader(source.path),
        [&](int fd) { childReads(fd, fileno(spool), source); },
        [&](import::ChildAnswer& in) {
            volume = receiveAnswer(in, name, spool);
            owned = volume && volume->bricks.source;
            return volume.status();
        });
    if (!owned) std::fclose(spool);
    if (!status.isOk()) return status;
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
                          : openVdbVolume(source.path, source.grid, source.material, source.emissionGrid);
        if (!volume && !source.label.empty()) return relabel(volume.message(), source);
        if (!volume) return volume.status();
        volume->codec = source.codec;  // the package writer quantizes (core/VolumeLeaf.h)
        volumes.push_back(std::move(volume).value());
    }
    return volumes;
}

}  // namespace vastray
