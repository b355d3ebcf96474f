#include "vastray/gpu/ComputePipeline.h"

#include <vector>

#include "VkCheck.h"

namespace vastray::gpu {

Result<std::unique_ptr<ComputePipeline>> ComputePipeline::create(VulkanDevice& device,
                                                                 std::span<const uint32_t> spirv,
                                                                 uint32_t pushConstantBytes,
                                                                 std::span<const uint32_t> specialization) {
    std::unique_ptr<ComputePipeline> pipeline(new ComputePipeline(device));
    pipeline->pushConstantBytes_ = pushConstantBytes;
    VASTRAY_TRY(pipeline->init(spirv, specialization).withContext("compute pipeline: "));
    return pipeline;
}

// A compiled kernel: destroyed (when the device is idle) once neither the device's cache nor a
// ComputePipeline holds it.
struct ComputePipeline::Handles {
    VulkanDevice& device;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline pipeline = VK_NULL_HANDLE;
    explicit Handles(VulkanDevice& d) : device(d) {}
    Handles(const Handles&) = delete;
    Handles& operator=(const Handles&) = delete;
    ~Handles() {
        if (!pipeline && !layout) return;
        device.destroyWhenIdle([pipeline = pipeline, layout = layout](VkDevice d) {
            if (pipeline) vkDestroyPipeline(d, pipeline, nullptr);
            if (layout) vkDestroyPipelineLayout(d, layout, nullptr);
        });
    }
};

namespace {

// The cache key: everything the compiled kernel depends on (the device's options are its own).
std::string kernelKey(std::span<const uint32_t> spirv, uint32_t pushConstantBytes,
                      std::span<const uint32_t> specialization) {
    std::string key;
    const uint32_t counts[2] = {pushConstantBytes, uint32_t(specialization.size())};
    key.append(reinterpret_cast<const char*>(counts), sizeof(counts));
    key.append(reinterpret_cast<const char*>(specialization.data()), specialization.size_bytes());
    key.append(reinterpret_cast<const char*>(spirv.data()), spirv.size_bytes());
    return key;
}

}  // namespace

Status ComputePipeline::init(std::span<const uint32_t> spirv, std::span<const uint32_t> specialization) {
    const std::string key = kernelKey(spirv, pushConstantBytes_, specialization);
    if (auto cached = device_.cachedKernel(key)) {
        handles_ = std::static_pointer_cast<const Handles>(cached);
        layout_ = handles_->layout, pipeline_ = handles_->pipeline;
        return Status::ok();
    }
    auto handles = std::make_shared<Handles>(device_);
    VASTRAY_TRY(compile(*handles, spirv, specialization));
    handles_ = std::static_pointer_cast<const Handles>(device_.keepKernel(key, std::move(handles)));
    layout_ = handles_->layout, pipeline_ = handles_->pipeline;
    return Status::ok();
}

Status ComputePipeline::compile(Handles& handles, std::span<const uint32_t> spirv,
                                std::span<const uint32_t> specialization) {
    const VkDevice device = device_.handle();
    VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, pushConstantBytes_};
    auto layoutInfo = vkStruct<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
    layoutInfo.pushConstantRangeCount = 1;
    layoutInfo.pPushConstantRanges = &range;
    VASTRAY_VK_TRY(vkCreatePipelineLayout(device, &layoutInfo, nullptr, &handles.layout));
    auto moduleInfo = vkStruct<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
    moduleInfo.codeSize = spirv.size_bytes();
    moduleInfo.pCode = spirv.data();
    VkShaderModule module = VK_NULL_HANDLE;
    VASTRAY_VK_TRY(vkCreateShaderModule(device, &moduleInfo, nullptr, &module));
    auto info = vkStruct<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
    info.stage = vkStruct<VkPipelineShaderStageCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO);
    info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    info.stage.module = module;
    info.stage.pName = "main";
    std::vector<VkSpecializationMapEntry> entries(specialization.size());
    for (uint32_t i = 0; i < entries.size(); ++i) entries[i] = {i, i * 4u, 4u};
    VkSpecializationInfo constants{uint32_t(entries.size()), entries.data(), specialization.size_bytes(),
                                   specialization.data()};
    if (!specialization.empty()) info.stage.pSpecializationInfo = &constants;
    info.layout = handles.layout;
    if (device_.kernelStatistics()) info.flags |= VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR;
    const VkResult r = vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &info, nullptr, &handles.pipeline);
    vkDestroyShaderModule(device, module, nullptr);  // the pipeline keeps what it needs
    return vkStatus(r, "vkCreateComputePipelines");
}

Result<std::string> ComputePipeline::statistics() const {
    if (!device_.kernelStatistics())
        return Status::error("the device keeps no kernel statistics (VK_KHR_pipeline_executable_properties "
                             "not offered or not asked for)");
    const VkDevice device = device_.handle();
    auto properties = reinterpret_cast<PFN_vkGetPipelineExecutablePropertiesKHR>(
        vkGetDeviceProcAddr(device, "vkGetPipelineExecutablePropertiesKHR"));
    auto statistics = reinterpret_cast<PFN_vkGetPipelineExecutableStatisticsKHR>(
        vkGetDeviceProcAddr(device, "vkGetPipelineExecutableStatisticsKHR"));
    if (!properties || !statistics)
        return Status::error("the driver has no vkGetPipelineExecutableStatisticsKHR");
    auto pipelineInfo = vkStruct<VkPipelineInfoKHR>(VK_STRUCTURE_TYPE_PIPELINE_INFO_KHR);
    pipelineInfo.pipeline = pipeline_;
    uint32_t executables = 0;
    VASTRAY_VK_TRY(properties(device, &pipelineInfo, &executables, nullptr));
    std::string text;
    for (uint32_t e = 0; e < executables; ++e) {
        auto executable = vkStruct<VkPipelineExecutableInfoKHR>(VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_INFO_KHR);
        executable.pipeline = pipeline_, executable.executableIndex = e;
        uint32_t count = 0;
        VASTRAY_VK_TRY(statistics(device, &executable, &count, nullptr));
        std::vector<VkPipelineExecutableStatisticKHR> values(
            count, vkStruct<VkPipelineExecutableStatisticKHR>(VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_STATISTIC_KHR));
        VASTRAY_VK_TRY(statistics(device, &executable, &count, values.data()));
        for (const VkPipelineExecutableStatisticKHR& v : values) {
            text += (text.empty() ? "" : ", ") + std::string(v.name) + "=";
            switch (v.format) {
                case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_BOOL32_KHR:
                    text += v.value.b32 ? "true" : "false";
                    break;
                case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_INT64_KHR:
                    text += std::to_string(v.value.i64);
                    break;
                case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_UINT64_KHR:
                    text += std::to_string(v.value.u64);
                    break;
                default:
                    text += std::to_string(v.value.f64);
            }
        }
    }
    return text;
}

ComputePipeline::~ComputePipeline() = default;  // handles_ goes with the last holder

void ComputePipeline::record(VkCommandBuffer cmd, const void* pushConstants, uint32_t groupCount) const {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
    vkCmdPushConstants(cmd, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, pushConstantBytes_, pushConstants);
    vkCmdDispatch(cmd, groupCount, 1, 1);
}

void ComputePipeline::recordIndirect(VkCommandBuffer cmd, const void* pushConstants, VkBuffer args,
                                     uint64_t offset) const {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
    vkCmdPushConstants(cmd, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, pushConstantBytes_, pushConstants);
    vkCmdDispatchIndirect(cmd, args, offset);
}

}  // namespace vastray::gpu
