// The volumes of an import (VolumeImport.h): materials checked, each .vdb read in this process
// or in a child process that sends the volume back through a pipe. No OpenVDB here: the child
// calls readVdbVolume (VdbVolume.cpp) like the caller would.
#include <tbb/task_arena.h>

#include <charconv>
#include <type_traits>

#include "import/ChildProcess.h"
#include "import/ImportCommon.h"
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

// In the child: the answer is a byte 0 and the message, or a byte 1 and the volume less what
// the parent computes again (worldToIndex, majorants, world bounds).
void sendAnswer(int fd, const Result<Volume>& volume) {
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
    writeValue(fd, v.material);
    writeVector(fd, v.brickOf), writeVector(fd, v.voxels), writeVector(fd, v.emissionVoxels);
}

// The volume (or the child's error) from the pipe; the checks it passed in the child are made
// again here, for a child whose memory a hostile file corrupted could send anything.
Result<Volume> receiveAnswer(import::ChildAnswer& in, const std::string& name) {
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

// Runs in the child: reads the volume and sends it.
void childReads(int fd, const VolumeSource& source) {
    // One thread: the parent's TBB workers do not exist here, so OpenVDB's parallel loops
    // run in an arena that asks for none.
    tbb::task_arena arena(1);
    Result<Volume> volume = Status::error("not read");
    arena.execute([&] { volume = readVdbVolume(source.path, source.grid, source.material, source.emissionGrid); });
    sendAnswer(fd, volume);
}

Result<Volume> readInChildProcess(const VolumeSource& source) {
    const std::string name = import::fileNameOf(source.path);
    Result<Volume> volume = Status::error("no answer");
    const Status status = import::runInChildProcess(
        name, {"OpenVDB", "the OpenVDB reader process", kVdbReadSecondsLimit},
        [&](int fd) { childReads(fd, source); },
        [&](import::ChildAnswer& in) {
            volume = receiveAnswer(in, name);
            return volume.status();
        });
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
        volumes.push_back(std::move(volume).value());
    }
    return volumes;
}

}  // namespace vastray
