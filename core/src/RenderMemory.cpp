#include "vastray/core/RenderMemory.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "vastray/core/ByteSize.h"

namespace vastray {
namespace {

uint64_t imageBytesPerPixel(uint32_t aovs) {
    uint64_t bytes = 4 * sizeof(float);  // rgb + alpha
    if (aovs & kAovDepth) bytes += sizeof(float);
    if (aovs & kAovNormal) bytes += 3 * sizeof(float);
    if (aovs & kAovAlbedo) bytes += 3 * sizeof(float);
    if (aovs & kAovPrimId) bytes += sizeof(uint32_t);
    if (aovs & kAovChunkId) bytes += sizeof(uint32_t);
    if (aovs & kAovCost) bytes += 2 * sizeof(float);
    if (aovs & kAovUv) bytes += 2 * sizeof(float);
    return bytes;
}

uint64_t readMemAvailable() {
    std::ifstream in("/proc/meminfo");
    std::string key;
    uint64_t kib = 0;
    std::string unit;
    while (in >> key >> kib >> unit)
        if (key == "MemAvailable:") return kib * 1024;
    return 0;
}

// cgroup v2: memory.max is "max" or a byte count; the headroom is max - current.
uint64_t readCgroupHeadroom() {
    std::ifstream maxFile("/sys/fs/cgroup/memory.max"), currentFile("/sys/fs/cgroup/memory.current");
    std::string max;
    uint64_t current = 0;
    if (!(maxFile >> max) || max == "max" || !(currentFile >> current)) return 0;
    std::istringstream parse(max);
    uint64_t limit = 0;
    if (!(parse >> limit)) return 0;
    return limit > current ? limit - current : 1;
}

// RLIMIT_AS (ulimit -v) less the address space already mapped (VmSize).
uint64_t readAddressSpaceHeadroom() {
    rlimit limit{};
    if (::getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return 0;
    std::ifstream in("/proc/self/status");
    std::string key;
    while (in >> key) {
        if (key != "VmSize:") continue;
        uint64_t kib = 0;
        in >> kib;
        const uint64_t used = kib * 1024;
        return limit.rlim_cur > used ? limit.rlim_cur - used : 1;
    }
    return 0;
}

}  // namespace

RenderHostMemory estimateRenderHostBytes(const RenderOptions& options, bool exrOutput) {
    const uint64_t pixels = renderBounds(options).pixelCount();
    const uint64_t image = pixels * imageBytesPerPixel(options.aovs);
    return {image, exrOutput ? image : 4 * pixels};
}

uint64_t physicalHostBytes() {
    const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGESIZE);
    return pages > 0 && pageSize > 0 ? uint64_t(pages) * uint64_t(pageSize) : 0;
}

uint64_t availableHostBytes() {
    uint64_t available = 0;
    for (uint64_t bound : {readMemAvailable(), readCgroupHeadroom(), readAddressSpaceHeadroom()})
        if (bound != 0) available = available == 0 ? bound : std::min(available, bound);
    return available;
}

Status checkRenderHostMemory(const RenderOptions& options, bool exrOutput, uint64_t available) {
    const RenderHostMemory need = estimateRenderHostBytes(options, exrOutput);
    if (available == 0 || need.total() <= available) return Status::ok();
    const PixelBounds bounds = renderBounds(options);
    return Status::error("a " + std::to_string(bounds.width()) + "x" + std::to_string(bounds.height()) +
                         " render needs " + formatBytes(need.total()) + " of host memory (image " +
                         formatBytes(need.imageBytes) + " + writer " + formatBytes(need.writerBytes) + "); " +
                         formatBytes(available) + " is available");
}

}  // namespace vastray
