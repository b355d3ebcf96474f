#pragma once
// The driver's figures for the wavefront's kernels: registers a thread, binary and memory sizes, as
// VK_KHR_pipeline_executable_properties reports them. The registers set how many rays a walk pass holds
// at once (docs/PERF_NOTES.md 84); `stream_render_bench --kernel-stats` prints them.
#include <string>

#include "vastray/core/Result.h"
#include "vastray/gpu/VulkanDevice.h"

namespace vastray::gpu {

// One line per kernel and variant (the walk in core and out of core, with and without the cost AOV;
// the shade for the default scene with the path state in device and in host memory; generate,
// accumulate, aov), each created afresh on `device`. A device made without
// VulkanDeviceOptions::kernelStatistics, or whose driver offers none, gets one line saying so.
Result<std::string> describeKernels(VulkanDevice& device);

}  // namespace vastray::gpu
