#pragma once
// One compute pipeline built from embedded SPIR-V, with a push-constant block as its only input
// (shaders reach their buffers through device addresses carried in the push constants).
#include <vulkan/vulkan.h>

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "vastray/core/Result.h"
#include "vastray/gpu/VulkanDevice.h"

namespace vastray::gpu {

class ComputePipeline {
public:
    // spirv: the module's words; entry point "main"; pushConstantBytes: size of the block;
    // specialization: the values of the module's specialization constants 0, 1, ... (32-bit
    // each; a bool constant takes 0 or 1), compiled into the pipeline.
    static Result<std::unique_ptr<ComputePipeline>> create(VulkanDevice& device, std::span<const uint32_t> spirv,
                                                           uint32_t pushConstantBytes,
                                                           std::span<const uint32_t> specialization = {});
    ~ComputePipeline();
    ComputePipeline(const ComputePipeline&) = delete;
    ComputePipeline& operator=(const ComputePipeline&) = delete;

    // Records a dispatch of groupCount workgroups along x, with these push constants.
    void record(VkCommandBuffer cmd, const void* pushConstants, uint32_t groupCount) const;
    // The same, with the workgroup counts read by the device from a VkDispatchIndirectCommand.
    void recordIndirect(VkCommandBuffer cmd, const void* pushConstants, VkBuffer args, uint64_t offset) const;
    // The driver's statistics of the compiled kernel ("Register Count=96, Binary Size=43520, ..." as
    // VK_KHR_pipeline_executable_properties names them), when the device keeps them
    // (VulkanDevice::kernelStatistics); else an error saying so.
    Result<std::string> statistics() const;

private:
    explicit ComputePipeline(VulkanDevice& device) : device_(device) {}
    struct Handles;
    Status init(std::span<const uint32_t> spirv, std::span<const uint32_t> specialization);
    Status compile(Handles& handles, std::span<const uint32_t> spirv, std::span<const uint32_t> specialization);

    VulkanDevice& device_;
    uint32_t pushConstantBytes_ = 0;
    std::shared_ptr<const Handles> handles_;  // shared through the device's kernel cache
    VkPipelineLayout layout_ = VK_NULL_HANDLE;
    VkPipeline pipeline_ = VK_NULL_HANDLE;
};

}  // namespace vastray::gpu
