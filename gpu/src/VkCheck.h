#pragma once
// Vulkan errors as Status values that name the call and the VkResult.
#include <vulkan/vulkan.h>

#include <string>

#include "vastray/core/Result.h"

namespace vastray::gpu {

std::string vkResultName(VkResult result);

// A zeroed Vulkan struct with its sType set (T{sType} would trip -Wmissing-field-initializers).
template <typename T>
T vkStruct(VkStructureType type) {
    T s{};
    s.sType = type;
    return s;
}

inline Status vkStatus(VkResult result, const char* call) {
    if (result == VK_SUCCESS) return Status::ok();
    return Status::error(std::string(call) + " failed: " + vkResultName(result));
}

}  // namespace vastray::gpu

// Returns the Status of a failed Vulkan call, e.g. "vkAllocateMemory failed: VK_ERROR_OUT_OF_DEVICE_MEMORY".
#define VASTRAY_VK_TRY(call) VASTRAY_TRY(::vastray::gpu::vkStatus((call), #call))
