// Peak memory and time of importing a .vdb volume into a package (docs/PERFORMANCE.md, "Volume
// import memory"), one mode per process (the peak is the process's VmHWM):
//
//   usage: volume_import_memory FILE.vdb OUT.vast streamed|whole|child [EMISSION_GRID]
//
// streamed: openVdbVolume, each brick read from the .vdb when the package writer writes it (what
//           `vastray import --volume` does);
// whole:    readVdbVolume, every brick in memory before the write (the import before bricks were
//           streamed);
// child:    readVolumes in a child process, as the service reads uploads: the child writes the
//           bricks to a temporary file that the writer reads back (this process's peak only;
//           the child's is its own).
// The package holds one small triangle beside the volume (a package needs a mesh). Prints one
// JSON line: bricks, voxel bytes, the resident peak before the import (libraries loaded) and
// after it, and the seconds to open (or read) the grid and to build the package.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "vastray/streamer/PackageBuilder.h"
#include "vastray/streamer/VolumeImport.h"

namespace {

// VmHWM (peak resident set) of this process in bytes, from /proc/self/status.
uint64_t peakResidentBytes() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("VmHWM:", 0) == 0) return std::strtoull(line.c_str() + 6, nullptr, 10) * 1024;
    return 0;
}

vastray::Result<vastray::Volume> readInChild(const std::string& path, const std::string& emission) {
    vastray::VolumeSource source;
    source.path = path;
    source.emissionGrid = emission;
    vastray::VolumeReadOptions options;
    options.childProcess = true;
    auto volumes = vastray::readVolumes({source}, options);
    if (!volumes) return volumes.status();
    return std::move((*volumes)[0]);
}

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
    const std::string mode = argc >= 4 ? argv[3] : "";
    if ((argc != 4 && argc != 5) || (mode != "streamed" && mode != "whole" && mode != "child")) {
        std::fprintf(stderr, "usage: %s FILE.vdb OUT.vast streamed|whole|child [EMISSION_GRID]\n", argv[0]);
        return 2;
    }
    using namespace vastray;
    const std::string emission = argc == 5 ? argv[4] : "";
    const uint64_t peakBefore = peakResidentBytes();
    auto start = std::chrono::steady_clock::now();
    auto volume = mode == "streamed" ? openVdbVolume(argv[1], "", VolumeMaterial{}, emission)
                  : mode == "whole"  ? readVdbVolume(argv[1], "", VolumeMaterial{}, emission)
                                     : readInChild(argv[1], emission);
    if (!volume) {
        std::fprintf(stderr, "%s\n", volume.message().c_str());
        return 1;
    }
    const double openSeconds = secondsSince(start);
    const uint64_t bricks = volume->brickCount();
    const bool glows = volume->hasEmission();
    TriangleMesh mesh;
    mesh.positions = {{3, 3, 3}, {4, 3, 3}, {3, 4, 3}};
    mesh.indices = {0, 1, 2};
    mesh.materials.emplace_back().name = "far";
    PackageBuildOptions options;
    options.progress = Progress::Mode::None;
    options.volumes.push_back(std::move(volume).value());
    start = std::chrono::steady_clock::now();
    auto report = buildPackage(std::move(mesh), argv[2], options);
    if (!report) {
        std::fprintf(stderr, "%s\n", report.message().c_str());
        return 1;
    }
    std::printf("{\"mode\": \"%s\", \"bricks\": %llu, \"voxel_bytes\": %llu, \"peak_rss_before\": %llu, "
                "\"peak_rss\": %llu, \"open_s\": %.3f, \"build_s\": %.3f}\n",
                mode.c_str(), (unsigned long long)bricks,
                (unsigned long long)(bricks * kVolumeBrickVoxels * 4 * (glows ? 2 : 1)),
                (unsigned long long)peakBefore, (unsigned long long)peakResidentBytes(), openSeconds,
                secondsSince(start));
    return 0;
}
