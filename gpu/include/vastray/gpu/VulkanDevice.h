#pragma once
// The Vulkan device the GPU backend runs on (a real GPU or Mesa's lavapipe), its compute queue,
// and counted buffers. Every device allocation goes through createBuffer, so liveBytes() and
// peakBytes() are the whole device footprint of whatever uses this device.
#include <vulkan/vulkan.h>

#include <deque>
#include <map>
#include <memory>
#include <mutex>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "vastray/core/Result.h"

namespace vastray::gpu {

struct VulkanDeviceOptions {
    // Index into the physical devices Vulkan reports (listVulkanDevices order); -1 picks the
    // first discrete GPU, else the first device of any kind (lavapipe on a machine without GPU).
    int deviceIndex = -1;
    // A submission the device has not finished after this long fails, naming a hung device,
    // and the device takes no more work (its queue may still hold the submission).
    double submitTimeoutSeconds = 600;
    // Asks the driver to keep each kernel's statistics (registers a thread, binary and memory sizes:
    // VK_KHR_pipeline_executable_properties) where the device offers them: ComputePipeline::statistics,
    // gpu/KernelStatistics.h. Off, pipelines are created as usual.
    bool kernelStatistics = false;
};

struct VulkanDeviceInfo {
    std::string name;
    VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
    bool usable = false;  // has a compute queue and every feature the backend needs
    std::string missing;  // why not usable
};

// A timeline semaphore value a submission waits for before the given stages run.
struct SubmitWait {
    VkSemaphore semaphore = VK_NULL_HANDLE;
    uint64_t value = 0;
    VkPipelineStageFlags stages = VK_PIPELINE_STAGE_ALL_COMMANDS_BIT;
};

// Every physical device, usable or not (for `--gpu-device` help and error messages).
Result<std::vector<VulkanDeviceInfo>> listVulkanDevices();

class VulkanDevice;

// A buffer addressed from shaders by its device address; mapped for its whole life when its
// memory is host-visible (every MemoryUse but DeviceOnly on a discrete GPU). Move-only; releases
// its memory (and its share of the accounting) when destroyed.
class GpuBuffer {
public:
    GpuBuffer() = default;
    GpuBuffer(GpuBuffer&& other) noexcept;
    GpuBuffer& operator=(GpuBuffer&& other) noexcept;
    GpuBuffer(const GpuBuffer&) = delete;
    GpuBuffer& operator=(const GpuBuffer&) = delete;
    ~GpuBuffer();

    uint64_t size() const { return size_; }                // bytes usable
    uint64_t allocatedBytes() const { return allocated_; } // bytes counted against the device
    VkDeviceAddress address() const { return address_; }
    bool isValid() const { return buffer_ != VK_NULL_HANDLE; }
    VkBuffer handle() const { return buffer_; }  // for transfer commands (fills, copies)
    bool isMapped() const { return mapped_ != nullptr; }

    // Copies between host memory and [offset, offset + bytes) of the buffer (an error when it is
    // not mapped). Call only while no dispatch or copy that uses those bytes is running
    // (VulkanDevice::submit waits for completion).
    Status upload(const void* data, uint64_t bytes, uint64_t offset = 0);
    Status download(void* data, uint64_t bytes, uint64_t offset = 0) const;

private:
    friend class VulkanDevice;
    void release();

    VulkanDevice* device_ = nullptr;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    void* mapped_ = nullptr;
    uint64_t size_ = 0;
    uint64_t allocated_ = 0;
    VkDeviceAddress address_ = 0;
};

class VulkanDevice {
public:
    static Result<std::unique_ptr<VulkanDevice>> create(const VulkanDeviceOptions& options = {});
    ~VulkanDevice();
    VulkanDevice(const VulkanDevice&) = delete;
    VulkanDevice& operator=(const VulkanDevice&) = delete;

    const VulkanDeviceInfo& info() const { return info_; }
    VkDevice handle() const { return device_; }
    // Timestamp queries on the compute queue: nanoseconds per tick, and the valid bits of a
    // timestamp (0: the queue has none).
    double timestampPeriodNs() const { return timestampPeriodNs_; }
    uint32_t timestampValidBits() const { return timestampValidBits_; }

    // Where a buffer lives. DeviceLocal: GPU memory the host can map (resizable BAR) when there
    // is such a heap, for data the GPU reads often. Readback: host-cached system memory, for
    // results the host reads: reading device memory through an uncached mapping is very slow.
    // DeviceOnly: GPU memory the host does not map, filled by copies on the transfer queue
    // (readable by the compute queue too); where every device-local type is host-visible
    // (lavapipe) the same memory as DeviceLocal. Staging: pinned host-visible memory the
    // transfer queue copies from, system memory where the device has a type for it.
    enum class MemoryUse { DeviceLocal, Readback, DeviceOnly, Staging };
    // Whether buffers of this use land in a device-local heap (lavapipe, integrated GPUs: one
    // memory) rather than in system memory (Readback and Staging on discrete GPUs).
    bool inDeviceMemory(MemoryUse use) const;
    bool readbackInDeviceMemory() const { return inDeviceMemory(MemoryUse::Readback); }
    // Whether the device has device-local memory the host cannot map and host-visible memory
    // outside its heaps: a discrete GPU, where chunk data can travel by DMA from system memory.
    bool hasSeparateMemory() const;

    // A zero-size request allocates a small buffer, so that every binding has a valid address.
    Result<GpuBuffer> createBuffer(uint64_t bytes, MemoryUse use = MemoryUse::DeviceLocal);
    uint64_t liveBytes() const { return liveBytes_; }
    uint64_t peakBytes() const { return peakBytes_; }
    uint32_t allocationCount() const { return allocationCount_; }

    // Records commands into a fresh command buffer, submits it to the compute queue and waits
    // (at most options.submitTimeoutSeconds). After a lost device or a timeout every later
    // submit fails at once with the same message: the render stops instead of hanging.
    Status submit(const std::function<void(VkCommandBuffer)>& record);
    // submit in two halves, so that the host can work while the device runs: begin records and
    // submits (after waiting for a submission still running), wait waits for it (nothing to do
    // when none runs). The host may write buffers the running submission does not read.
    // after, when given, holds the submission's stages until its semaphore value is reached
    // (copies on the transfer queue that the kernels read).
    Status begin(const std::function<void(VkCommandBuffer)>& record, const SubmitWait* after = nullptr);
    Status wait();
    bool running() const { return pending_ != VK_NULL_HANDLE; }

    // The transfer queue: a queue of a transfer-only family (a DMA engine) when the device has
    // one, else the compute queue itself. Submissions to it come from the thread that submits
    // compute work (the queues are not locked). Buffers of MemoryUse::DeviceOnly are shared by
    // both families (VK_SHARING_MODE_CONCURRENT) when they differ.
    VkQueue transferQueue() const { return transferQueue_; }
    uint32_t transferFamily() const { return transferFamily_; }
    uint32_t computeFamily() const { return computeFamily_; }
    bool separateTransferQueue() const { return transferFamily_ != computeFamily_; }
    uint32_t transferTimestampValidBits() const { return transferTimestampValidBits_; }
    bool hostQueryReset() const { return hostQueryReset_; }  // vkResetQueryPool may be called
    // VulkanDeviceOptions::kernelStatistics was asked for and the device offers them.
    bool kernelStatistics() const { return kernelStatistics_; }
    double submitTimeoutSeconds() const { return submitTimeoutSeconds_; }
    // Marks the device failed (a lost device, a timeout seen elsewhere): later submits fail.
    void fail(const std::string& message) {
        if (failure_.empty()) failure_ = message;
    }
    // Runs `destroy` (which destroys a Vulkan object: a pipeline, a query pool) now; after a
    // timed-out submission, which may still use the object, only once the device is idle, in
    // ~VulkanDevice (as GpuBuffer's memory is).
    void destroyWhenIdle(const std::function<void(VkDevice)>& destroy);
    // Compiled kernels kept for the device's life (ComputePipeline's cache, keyed by the SPIR-V
    // words, the push-constant size and the specialization values): a backend created for the
    // next scene or job takes the kernels an earlier one compiled (0.3-0.5 s each on the H200,
    // ~0.5 s on lavapipe) instead of compiling them again. Null when the key is not cached.
    std::shared_ptr<const void> cachedKernel(const std::string& key);
    // Keeps `kernel` under `key` (the first one kept wins) and returns the one kept; at most
    // kKernelCacheEntries are kept, the oldest given up first (its users keep it alive).
    std::shared_ptr<const void> keepKernel(const std::string& key, std::shared_ptr<const void> kernel);
    static constexpr size_t kKernelCacheEntries = 64;

private:
    friend class GpuBuffer;
    VulkanDevice() = default;
    Status init(const VulkanDeviceOptions& options);
    Status createLogicalDevice(VkPhysicalDevice physical, bool kernelStatistics);
    Result<uint32_t> findMemoryType(uint32_t typeBits, MemoryUse use) const;
    void freeBuffer(GpuBuffer& buffer);

    VulkanDeviceInfo info_;
    VkInstance instance_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    VkQueue transferQueue_ = VK_NULL_HANDLE;
    uint32_t computeFamily_ = 0, transferFamily_ = 0;
    uint32_t transferTimestampValidBits_ = 0;
    bool hostQueryReset_ = false;
    bool kernelStatistics_ = false;
    VkCommandPool commandPool_ = VK_NULL_HANDLE;
    VkFence fence_ = VK_NULL_HANDLE;
    VkCommandBuffer pending_ = VK_NULL_HANDLE;  // submitted, not yet waited for
    VkPhysicalDeviceMemoryProperties memoryProperties_{};
    double submitTimeoutSeconds_ = 600;
    double timestampPeriodNs_ = 0;
    uint32_t timestampValidBits_ = 0;
    std::string failure_;  // set once the device is lost or hung
    std::vector<std::pair<VkBuffer, VkDeviceMemory>> abandoned_;  // freed after failure_: released when idle
    std::vector<std::function<void(VkDevice)>> abandonedObjects_;   // destroyed after failure_: when idle
    std::mutex kernelMutex_;  // kernels are created on threads of their own (Wavefront)
    std::map<std::string, std::shared_ptr<const void>> kernels_;
    std::deque<std::string> kernelOrder_;  // oldest first
    uint64_t liveBytes_ = 0;
    uint64_t peakBytes_ = 0;
    uint32_t allocationCount_ = 0;
};

}  // namespace vastray::gpu
