#pragma once
// Host memory a render needs, estimated and checked before anything is allocated: a
// 16384x16384 image (the largest allowed) asked for gigabytes at once and ended in an
// uncaught std::bad_alloc, in the CLI and in the service alike.
#include <cstdint>
#include <string>

#include "vastray/core/RenderOptions.h"
#include "vastray/core/Result.h"

namespace vastray {

// Host bytes that grow with the image: its buffers (beauty, alpha, requested AOVs) and the
// writer's packed copy (PNG: 4 bytes per pixel; EXR: every channel as 4 bytes). The
// renderers' other host memory does not grow with the image. Measured: 16384x16384 to PNG
// with Embree peaked at 5.1 GiB resident; the estimate is 5.0 GiB.
struct RenderHostMemory {
    uint64_t imageBytes = 0, writerBytes = 0;
    uint64_t total() const { return imageBytes + writerBytes; }
};
RenderHostMemory estimateRenderHostBytes(const RenderOptions& options, bool exrOutput);

// The machine's physical memory (sysconf); 0 when it cannot be read.
uint64_t physicalHostBytes();

// Memory this process may still take: the least of MemAvailable (/proc/meminfo), the cgroup
// (v2) limit's headroom and the address-space limit's (ulimit -v) headroom, where each is
// set. 0 when none can be read.
uint64_t availableHostBytes();

// "a 16384x16384 render needs 8.0 GiB of host memory (image 4.0 GiB + writer 4.0 GiB);
// 2.9 GiB is available" when the estimate exceeds `available` (default availableHostBytes()).
Status checkRenderHostMemory(const RenderOptions& options, bool exrOutput,
                             uint64_t available = availableHostBytes());

}  // namespace vastray
