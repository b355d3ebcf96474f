#include "vastray/gpu/VulkanDevice.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <thread>
#include <utility>

#include "VkCheck.h"

namespace vastray::gpu {
namespace {

// How long wait() polls a fence before it blocks (on a GPU).
constexpr std::chrono::milliseconds kFencePollTime{2};

Result<VkInstance> createInstance() {
    auto app = vkStruct<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
    app.pApplicationName = "vastray";
    app.apiVersion = VK_API_VERSION_1_2;
    auto info = vkStruct<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
    info.pApplicationInfo = &app;
    VkInstance instance = VK_NULL_HANDLE;
    const VkResult r = vkCreateInstance(&info, nullptr, &instance);
    if (r != VK_SUCCESS)
        return Status::error(vkStatus(r, "vkCreateInstance").message() +
                             " (is a Vulkan driver installed? lavapipe comes with mesa-vulkan-drivers)");
    return instance;
}

Result<std::vector<VkPhysicalDevice>> physicalDevices(VkInstance instance) {
    uint32_t count = 0;
    VASTRAY_VK_TRY(vkEnumeratePhysicalDevices(instance, &count, nullptr));
    std::vector<VkPhysicalDevice> devices(count);
    VASTRAY_VK_TRY(vkEnumeratePhysicalDevices(instance, &count, devices.data()));
    devices.resize(count);
    return devices;
}

std::vector<VkQueueFamilyProperties> queueFamilies(VkPhysicalDevice device) {
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
    families.resize(count);
    return families;
}

// Index of a queue family with compute, or -1.
int computeQueueFamily(VkPhysicalDevice device) {
    const auto families = queueFamilies(device);
    for (uint32_t i = 0; i < families.size(); ++i)
        if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) return int(i);
    return -1;
}

// A family that only transfers (the DMA engines of a discrete GPU), or -1.
int transferOnlyQueueFamily(VkPhysicalDevice device) {
    const auto families = queueFamilies(device);
    for (uint32_t i = 0; i < families.size(); ++i) {
        const VkQueueFlags f = families[i].queueFlags;
        const bool transferOnly = (f & VK_QUEUE_TRANSFER_BIT) && !(f & (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT));
        if (transferOnly && families[i].queueCount > 0) return int(i);
    }
    return -1;
}

// What the tracer needs: Vulkan 1.2, device addresses, 64-bit ints (addresses in push constants)
// and timeline semaphores (chunk copies on the transfer queue; core in 1.2).
VulkanDeviceInfo describe(VkPhysicalDevice device) {
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(device, &props);
    auto f12 = vkStruct<VkPhysicalDeviceVulkan12Features>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES);
    auto f = vkStruct<VkPhysicalDeviceFeatures2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2);
    f.pNext = &f12;
    if (props.apiVersion >= VK_API_VERSION_1_2) vkGetPhysicalDeviceFeatures2(device, &f);
    VulkanDeviceInfo info;
    info.name = props.deviceName;
    info.type = props.deviceType;
    if (props.apiVersion < VK_API_VERSION_1_2) info.missing = "Vulkan 1.2";
    else if (computeQueueFamily(device) < 0) info.missing = "a compute queue";
    else if (!f12.bufferDeviceAddress) info.missing = "bufferDeviceAddress";
    else if (!f.features.shaderInt64) info.missing = "shaderInt64";
    else if (!f12.timelineSemaphore) info.missing = "timelineSemaphore";
    info.usable = info.missing.empty();
    return info;
}

// -1 when none fits; explicit index first, else the first usable discrete GPU, else any usable.
int pickDevice(const std::vector<VulkanDeviceInfo>& infos, int requested) {
    if (requested >= 0) return requested < int(infos.size()) && infos[size_t(requested)].usable ? requested : -1;
    for (size_t i = 0; i < infos.size(); ++i)
        if (infos[i].usable && infos[i].type == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU) return int(i);
    for (size_t i = 0; i < infos.size(); ++i)
        if (infos[i].usable) return int(i);
    return -1;
}

std::string deviceListText(const std::vector<VulkanDeviceInfo>& infos) {
    if (infos.empty()) return "Vulkan reports no physical device";
    std::string text = "devices:";
    for (size_t i = 0; i < infos.size(); ++i)
        text += " [" + std::to_string(i) + "] " + infos[i].name +
                (infos[i].usable ? "" : " (lacks " + infos[i].missing + ")");
    return text;
}

}  // namespace

Result<std::vector<VulkanDeviceInfo>> listVulkanDevices() {
    auto instance = createInstance();
    if (!instance) return instance.status();
    auto devices = physicalDevices(*instance);
    std::vector<VulkanDeviceInfo> infos;
    if (devices)
        for (VkPhysicalDevice d : *devices) infos.push_back(describe(d));
    vkDestroyInstance(*instance, nullptr);
    if (!devices) return devices.status();
    return infos;
}

Result<std::unique_ptr<VulkanDevice>> VulkanDevice::create(const VulkanDeviceOptions& options) {
    std::unique_ptr<VulkanDevice> device(new VulkanDevice());
    VASTRAY_TRY(device->init(options).withContext("Vulkan: "));
    return device;
}

Status VulkanDevice::init(const VulkanDeviceOptions& options) {
    submitTimeoutSeconds_ = options.submitTimeoutSeconds;
    auto instance = createInstance();
    if (!instance) return instance.status();
    instance_ = *instance;
    auto devices = physicalDevices(instance_);
    if (!devices) return devices.status();
    std::vector<VulkanDeviceInfo> infos;
    for (VkPhysicalDevice d : *devices) infos.push_back(describe(d));
    const int index = pickDevice(infos, options.deviceIndex);
    if (index < 0) {
        const std::string wanted = options.deviceIndex >= 0
                                       ? "device " + std::to_string(options.deviceIndex) + " is not usable"
                                       : "no usable device";
        return Status::error(wanted + "; " + deviceListText(infos));
    }
    physical_ = (*devices)[size_t(index)];
    info_ = infos[size_t(index)];
    vkGetPhysicalDeviceMemoryProperties(physical_, &memoryProperties_);
    computeFamily_ = uint32_t(computeQueueFamily(physical_));
    const int transfer = transferOnlyQueueFamily(physical_);
    transferFamily_ = transfer >= 0 ? uint32_t(transfer) : computeFamily_;
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(physical_, &props);
    const auto families = queueFamilies(physical_);
    timestampPeriodNs_ = props.limits.timestampPeriod;
    timestampValidBits_ = families[computeFamily_].timestampValidBits;
    transferTimestampValidBits_ = families[transferFamily_].timestampValidBits;
    return createLogicalDevice(physical_, options.kernelStatistics);
}

// Whether the device offers extension `name`.
static bool hasDeviceExtension(VkPhysicalDevice physical, const char* name) {
    uint32_t count = 0;
    if (vkEnumerateDeviceExtensionProperties(physical, nullptr, &count, nullptr) != VK_SUCCESS) return false;
    std::vector<VkExtensionProperties> extensions(count);
    if (vkEnumerateDeviceExtensionProperties(physical, nullptr, &count, extensions.data()) != VK_SUCCESS)
        return false;
    for (const VkExtensionProperties& e : extensions)
        if (std::strcmp(e.extensionName, name) == 0) return true;
    return false;
}

Status VulkanDevice::createLogicalDevice(VkPhysicalDevice physical, bool kernelStatistics) {
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queueInfos[2];
    for (uint32_t i = 0; i < 2; ++i) {
        queueInfos[i] = vkStruct<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
        queueInfos[i].queueFamilyIndex = i == 0 ? computeFamily_ : transferFamily_;
        queueInfos[i].queueCount = 1;
        queueInfos[i].pQueuePriorities = &priority;
    }
    auto supported12 =
        vkStruct<VkPhysicalDeviceVulkan12Features>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES);
    auto supportedStatistics = vkStruct<VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR>(
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR);
    const char* statisticsExtension = VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME;
    const bool statisticsOffered = kernelStatistics && hasDeviceExtension(physical, statisticsExtension);
    if (statisticsOffered) supported12.pNext = &supportedStatistics;
    auto supported = vkStruct<VkPhysicalDeviceFeatures2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2);
    supported.pNext = &supported12;
    vkGetPhysicalDeviceFeatures2(physical, &supported);
    kernelStatistics_ = statisticsOffered && supportedStatistics.pipelineExecutableInfo == VK_TRUE;
    // Host query resets time the transfer queue's copies (vkCmdResetQueryPool is not a
    // transfer-queue command); without them the copies go untimed.
    hostQueryReset_ = supported12.hostQueryReset == VK_TRUE;
    auto f12 = vkStruct<VkPhysicalDeviceVulkan12Features>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES);
    f12.bufferDeviceAddress = VK_TRUE;
    f12.timelineSemaphore = VK_TRUE;
    f12.hostQueryReset = hostQueryReset_ ? VK_TRUE : VK_FALSE;
    auto features = vkStruct<VkPhysicalDeviceFeatures2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2);
    features.pNext = &f12;
    features.features.shaderInt64 = VK_TRUE;
    auto statistics = vkStruct<VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR>(
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR);
    statistics.pipelineExecutableInfo = VK_TRUE;
    if (kernelStatistics_) f12.pNext = &statistics;
    auto info = vkStruct<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
    info.pNext = &features;
    info.enabledExtensionCount = kernelStatistics_ ? 1 : 0;
    info.ppEnabledExtensionNames = kernelStatistics_ ? &statisticsExtension : nullptr;
    info.queueCreateInfoCount = separateTransferQueue() ? 2 : 1;
    info.pQueueCreateInfos = queueInfos;
    VASTRAY_VK_TRY(vkCreateDevice(physical, &info, nullptr, &device_));
    vkGetDeviceQueue(device_, computeFamily_, 0, &queue_);
    transferQueue_ = queue_;
    if (separateTransferQueue()) vkGetDeviceQueue(device_, transferFamily_, 0, &transferQueue_);
    auto poolInfo = vkStruct<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
    poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    poolInfo.queueFamilyIndex = computeFamily_;
    VASTRAY_VK_TRY(vkCreateCommandPool(device_, &poolInfo, nullptr, &commandPool_));
    auto fenceInfo = vkStruct<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
    VASTRAY_VK_TRY(vkCreateFence(device_, &fenceInfo, nullptr, &fence_));
    return Status::ok();
}

VulkanDevice::~VulkanDevice() {
    if (device_) {
        vkDeviceWaitIdle(device_);
        kernels_.clear();  // their pipelines are destroyed here (or queued below after a failure)
        for (const auto& destroy : abandonedObjects_) destroy(device_);
        for (const auto& [buffer, memory] : abandoned_) {
            vkDestroyBuffer(device_, buffer, nullptr);
            vkFreeMemory(device_, memory, nullptr);  // unmapped implicitly
        }
        if (fence_) vkDestroyFence(device_, fence_, nullptr);
        if (commandPool_) vkDestroyCommandPool(device_, commandPool_, nullptr);
        vkDestroyDevice(device_, nullptr);
    }
    if (instance_) vkDestroyInstance(instance_, nullptr);
}

// In order of preference, the properties a type must have and those it must not have.
// Host-visible and coherent (the buffers stay mapped), device-local too when a heap offers both
// (lavapipe: all memory; discrete GPUs: the resizable-BAR heap); DeviceOnly prefers device-local
// memory the host cannot see, Staging host memory outside the device's heaps.
Result<uint32_t> VulkanDevice::findMemoryType(uint32_t typeBits, MemoryUse use) const {
    const VkMemoryPropertyFlags host = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    const VkMemoryPropertyFlags local = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    struct Choice {
        VkMemoryPropertyFlags with, without;
    };
    std::vector<Choice> choices;
    switch (use) {
        case MemoryUse::Readback: choices = {{host | VK_MEMORY_PROPERTY_HOST_CACHED_BIT, 0}, {host, 0}}; break;
        case MemoryUse::DeviceLocal: choices = {{host | local, 0}, {host, 0}}; break;
        case MemoryUse::DeviceOnly:
            choices = {{local, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT}, {host | local, 0}, {host, 0}};
            break;
        case MemoryUse::Staging: choices = {{host, local}, {host, 0}}; break;
    }
    for (const Choice& c : choices)
        for (uint32_t i = 0; i < memoryProperties_.memoryTypeCount; ++i) {
            const VkMemoryPropertyFlags flags = memoryProperties_.memoryTypes[i].propertyFlags;
            if ((typeBits & (1u << i)) && (flags & c.with) == c.with && (flags & c.without) == 0) return i;
        }
    return Status::error("no host-visible coherent memory type for a buffer");
}

bool VulkanDevice::inDeviceMemory(MemoryUse use) const {
    auto type = findMemoryType(~0u, use);
    if (!type) return true;
    const uint32_t heap = memoryProperties_.memoryTypes[*type].heapIndex;
    return (memoryProperties_.memoryHeaps[heap].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) != 0;
}

bool VulkanDevice::hasSeparateMemory() const {
    auto deviceOnly = findMemoryType(~0u, MemoryUse::DeviceOnly);
    if (!deviceOnly) return false;
    const VkMemoryPropertyFlags flags = memoryProperties_.memoryTypes[*deviceOnly].propertyFlags;
    return !(flags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) && !inDeviceMemory(MemoryUse::Staging);
}

Status VulkanDevice::submit(const std::function<void(VkCommandBuffer)>& record) {
    VASTRAY_TRY(begin(record));
    return wait();
}

Status VulkanDevice::begin(const std::function<void(VkCommandBuffer)>& record, const SubmitWait* after) {
    VASTRAY_TRY(wait());
    if (!failure_.empty()) return Status::error(failure_);
    auto allocInfo = vkStruct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
    allocInfo.commandPool = commandPool_;
    allocInfo.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    allocInfo.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VASTRAY_VK_TRY(vkAllocateCommandBuffers(device_, &allocInfo, &cmd));
    struct FreeOnError {
        VkDevice device;
        VkCommandPool pool;
        VkCommandBuffer cmd;
        ~FreeOnError() {
            if (cmd != VK_NULL_HANDLE) vkFreeCommandBuffers(device, pool, 1, &cmd);
        }
    } freeOnError{device_, commandPool_, cmd};
    auto beginInfo = vkStruct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
    beginInfo.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VASTRAY_VK_TRY(vkBeginCommandBuffer(cmd, &beginInfo));
    record(cmd);
    // Host writes before the submit are visible to it (submission order); make the shaders'
    // writes visible to host reads after the fence.
    auto barrier = vkStruct<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
    barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0,
                         nullptr, 0, nullptr);
    VASTRAY_VK_TRY(vkEndCommandBuffer(cmd));
    auto submitInfo = vkStruct<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
    submitInfo.commandBufferCount = 1;
    submitInfo.pCommandBuffers = &cmd;
    auto timeline = vkStruct<VkTimelineSemaphoreSubmitInfo>(VK_STRUCTURE_TYPE_TIMELINE_SEMAPHORE_SUBMIT_INFO);
    if (after && after->semaphore != VK_NULL_HANDLE) {
        timeline.waitSemaphoreValueCount = 1;
        timeline.pWaitSemaphoreValues = &after->value;
        submitInfo.pNext = &timeline;
        submitInfo.waitSemaphoreCount = 1;
        submitInfo.pWaitSemaphores = &after->semaphore;
        submitInfo.pWaitDstStageMask = &after->stages;
    }
    VASTRAY_VK_TRY(vkResetFences(device_, 1, &fence_));
    const VkResult submitted = vkQueueSubmit(queue_, 1, &submitInfo, fence_);
    if (submitted == VK_ERROR_DEVICE_LOST) failure_ = info_.name + ": the device was lost (VK_ERROR_DEVICE_LOST)";
    VASTRAY_TRY(failure_.empty() ? vkStatus(submitted, "vkQueueSubmit") : Status::error(failure_));
    pending_ = cmd;
    freeOnError.cmd = VK_NULL_HANDLE;
    return Status::ok();
}

std::shared_ptr<const void> VulkanDevice::cachedKernel(const std::string& key) {
    std::lock_guard<std::mutex> lock(kernelMutex_);
    const auto found = kernels_.find(key);
    return found == kernels_.end() ? nullptr : found->second;
}

std::shared_ptr<const void> VulkanDevice::keepKernel(const std::string& key, std::shared_ptr<const void> kernel) {
    std::shared_ptr<const void> givenUp;  // released after the lock (its destructor destroys a pipeline)
    std::lock_guard<std::mutex> lock(kernelMutex_);
    const auto [at, inserted] = kernels_.emplace(key, std::move(kernel));
    if (inserted) {
        kernelOrder_.push_back(key);
        if (kernelOrder_.size() > kKernelCacheEntries) {
            const auto oldest = kernels_.find(kernelOrder_.front());
            givenUp = std::move(oldest->second);
            kernels_.erase(oldest);
            kernelOrder_.pop_front();
        }
    }
    return at->second;
}

void VulkanDevice::destroyWhenIdle(const std::function<void(VkDevice)>& destroy) {
    if (failure_.empty()) destroy(device_);
    else abandonedObjects_.push_back(destroy);
}

Status VulkanDevice::wait() {
    if (pending_ == VK_NULL_HANDLE) return Status::ok();
    const double limit = std::clamp(submitTimeoutSeconds_, 0.0, 1e9);
    // On a GPU, poll the fence for a while before blocking: out of core a render waits for
    // hundreds of paging steps of about a millisecond each, and the driver's blocking wait
    // returns later than a poll sees the fence (H200: city 10M 4x over budget 0.90 -> 0.85 s,
    // 16x 6.6 -> 5.8 s; docs/PERF_NOTES.md 57). Not on a CPU device (lavapipe), whose threads
    // need the cores the poll would take.
    if (info_.type != VK_PHYSICAL_DEVICE_TYPE_CPU) {
        const auto until = std::chrono::steady_clock::now() + kFencePollTime;
        while (vkGetFenceStatus(device_, fence_) == VK_NOT_READY && std::chrono::steady_clock::now() < until)
            std::this_thread::yield();
    }
    const VkResult waited = vkWaitForFences(device_, 1, &fence_, VK_TRUE, uint64_t(limit * 1e9));
    if (waited == VK_TIMEOUT) {
        // Still executing: the command buffer is freed with the pool, once idle.
        char seconds[32];
        std::snprintf(seconds, sizeof seconds, "%g", limit);
        failure_ = info_.name + ": the device did not finish a submission within " + seconds +
                   " s (hung device?); it takes no more work";
    } else {
        if (waited == VK_ERROR_DEVICE_LOST) failure_ = info_.name + ": the device was lost (VK_ERROR_DEVICE_LOST)";
        vkFreeCommandBuffers(device_, commandPool_, 1, &pending_);
    }
    pending_ = VK_NULL_HANDLE;
    return failure_.empty() ? vkStatus(waited, "vkWaitForFences") : Status::error(failure_);
}

}  // namespace vastray::gpu
