// gpu/KernelStatistics.h: the driver's figures for every wavefront kernel, or a line saying the device has
// none (Mesa 22's lavapipe offers no VK_KHR_pipeline_executable_properties; NVIDIA's driver does).
#include <gtest/gtest.h>

#include "GpuTestSupport.h"
#include "vastray/gpu/KernelStatistics.h"

namespace vastray::gpu::test {
namespace {

TEST(KernelStatistics, EveryKernelOrWhyNone) {
    auto device = VulkanDevice::create(VulkanDeviceOptions{.kernelStatistics = true});
    ASSERT_TRUE(device.isOk()) << device.message();
    auto text = describeKernels(**device);
    ASSERT_TRUE(text.isOk()) << text.message();
    EXPECT_EQ(text->find((*device)->info().name), 0u) << *text;
    if (!(*device)->kernelStatistics()) {
        EXPECT_NE(text->find("offers no kernel statistics"), std::string::npos) << *text;
        return;
    }
    for (const char* kernel :
         {"wf_walk in core: ", "wf_walk out of core: ", "wf_walk out of core, cost AOV: ",
          "wf_shade (sun, Lambertian): ", "wf_shade (sun, Lambertian), state in host memory: ", "wf_generate: ",
          "wf_accumulate: ", "wf_aov: "}) {
        const size_t at = text->find(kernel);
        ASSERT_NE(at, std::string::npos) << kernel << " missing from:\n" << *text;
        EXPECT_NE(text->find('=', at), std::string::npos) << "no figure for " << kernel << ":\n" << *text;
    }
}

TEST(KernelStatistics, NotAskedForSaysSoInsteadOfFigures) {
    VASTRAY_REQUIRE_DEVICE(device);  // the tests' shared device is made without kernelStatistics
    ASSERT_FALSE(device.kernelStatistics());
    auto text = describeKernels(device);
    ASSERT_TRUE(text.isOk()) << text.message();
    EXPECT_NE(text->find("offers no kernel statistics"), std::string::npos) << *text;
}

}  // namespace
}  // namespace vastray::gpu::test
