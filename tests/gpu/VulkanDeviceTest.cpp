#include <gtest/gtest.h>

#include <numeric>
#include <vector>

#include "GpuTestSupport.h"
#include "vastray/gpu/GpuChunkTracer.h"

namespace vastray::gpu::test {
namespace {

TEST(VulkanDevice, ListsAtLeastOneUsableDevice) {
    auto devices = listVulkanDevices();
    ASSERT_TRUE(devices.isOk()) << devices.message();
    bool usable = false;
    for (const VulkanDeviceInfo& d : *devices) usable |= d.usable;
    EXPECT_TRUE(usable) << "CI has lavapipe; every device lacks a feature the tracer needs";
}

TEST(VulkanDevice, BadIndexIsAClearError) {
    auto device = VulkanDevice::create(VulkanDeviceOptions{.deviceIndex = 999});
    ASSERT_FALSE(device.isOk());
    EXPECT_NE(device.message().find("device 999 is not usable"), std::string::npos) << device.message();
    EXPECT_NE(device.message().find("[0]"), std::string::npos) << "lists the devices: " << device.message();
}

TEST(VulkanDevice, UploadDownloadRoundTrip) {
    VASTRAY_REQUIRE_DEVICE(device);
    std::vector<uint32_t> data(1000);
    std::iota(data.begin(), data.end(), 7u);
    auto buffer = device.createBuffer(data.size() * sizeof(uint32_t));
    ASSERT_TRUE(buffer.isOk()) << buffer.message();
    ASSERT_TRUE(buffer->upload(data.data(), data.size() * sizeof(uint32_t)).isOk());
    std::vector<uint32_t> back(data.size());
    ASSERT_TRUE(buffer->download(back.data(), back.size() * sizeof(uint32_t)).isOk());
    EXPECT_EQ(back, data);
    EXPECT_NE(buffer->address(), 0u);
    EXPECT_FALSE(buffer->upload(data.data(), 8, buffer->size() - 4).isOk()) << "write past the end";
}

// Chunk slots for DMA uploads live in device memory the host cannot map where the device has
// such memory (a discrete GPU), and are filled by copies from mapped staging memory; on lavapipe
// both are its one memory. Either way a copy through them returns the bytes.
TEST(VulkanDevice, StagingCopiesReachDeviceOnlyBuffers) {
    VASTRAY_REQUIRE_DEVICE(device);
    std::vector<uint32_t> data(4096);
    std::iota(data.begin(), data.end(), 11u);
    const uint64_t bytes = data.size() * sizeof(uint32_t);
    auto staging = device.createBuffer(bytes, VulkanDevice::MemoryUse::Staging);
    auto slot = device.createBuffer(bytes, VulkanDevice::MemoryUse::DeviceOnly);
    auto back = device.createBuffer(bytes, VulkanDevice::MemoryUse::Readback);
    ASSERT_TRUE(staging && slot && back) << staging.message() << slot.message() << back.message();
    ASSERT_TRUE(staging->isMapped());
    EXPECT_NE(slot->address(), 0u);
    EXPECT_EQ(slot->isMapped(), !device.hasSeparateMemory());
    if (!slot->isMapped()) {
        const Status refused = slot->upload(data.data(), 16);
        ASSERT_FALSE(refused.isOk());
        EXPECT_NE(refused.message().find("cannot map"), std::string::npos) << refused.message();
    }
    ASSERT_TRUE(staging->upload(data.data(), bytes).isOk());
    const Status copied = device.submit([&](VkCommandBuffer cmd) {
        const VkBufferCopy region{0, 0, bytes};
        vkCmdCopyBuffer(cmd, staging->handle(), slot->handle(), 1, &region);
        VkMemoryBarrier b{};
        b.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
        b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        b.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &b, 0, nullptr,
                             0, nullptr);
        vkCmdCopyBuffer(cmd, slot->handle(), back->handle(), 1, &region);
    });
    ASSERT_TRUE(copied.isOk()) << copied.message();
    std::vector<uint32_t> read(data.size());
    ASSERT_TRUE(back->download(read.data(), bytes).isOk());
    EXPECT_EQ(read, data);
}

// A device of its own, so that nothing else is allocated on it.
TEST(VulkanDevice, CountsEveryAllocationAndThePeak) {
    auto created = VulkanDevice::create();
    ASSERT_TRUE(created.isOk()) << "no usable Vulkan device (CI: lavapipe): " << created.message();
    VulkanDevice& device = **created;
    EXPECT_EQ(device.liveBytes(), 0u);
    auto a = device.createBuffer(1000);
    auto b = device.createBuffer(1 << 20);
    ASSERT_TRUE(a.isOk() && b.isOk());
    EXPECT_GE(a->allocatedBytes(), 1000u);
    EXPECT_GE(b->allocatedBytes(), uint64_t(1 << 20));
    const uint64_t both = a->allocatedBytes() + b->allocatedBytes();
    EXPECT_EQ(device.liveBytes(), both);
    EXPECT_EQ(device.peakBytes(), both);
    EXPECT_EQ(device.allocationCount(), 2u);
    { GpuBuffer dropped = std::move(a).value(); }
    EXPECT_EQ(device.liveBytes(), b->allocatedBytes());
    EXPECT_EQ(device.peakBytes(), both) << "the peak survives frees";
    EXPECT_EQ(device.allocationCount(), 1u);
}

TEST(VulkanDevice, TracerAllocationsAreAllCounted) {
    auto created = VulkanDevice::create();
    ASSERT_TRUE(created.isOk()) << "no usable Vulkan device (CI: lavapipe): " << created.message();
    VulkanDevice& device = **created;
    const Mesh mesh = makeIcosphere(3, {0, 0, 0}, 1.0f);
    const KdTree tree = mesh.build();
    {
        auto tracer = GpuChunkTracer::create(device);
        ASSERT_TRUE(tracer.isOk()) << tracer.message();
        ASSERT_TRUE((*tracer)->upload(ChunkArrays{&tree, mesh.positions, mesh.indices, {}}).isOk());
        const uint64_t chunkBytes = (*tracer)->residentChunkBytes();
        EXPECT_GE(chunkBytes, mesh.positions.size() * sizeof(Vec3f) + mesh.indices.size() * sizeof(uint32_t) +
                                  tree.nodes.size() * sizeof(KdNode) + tree.leafRefs.size() * sizeof(uint32_t));
        EXPECT_EQ(device.liveBytes(), chunkBytes);
        ASSERT_TRUE((*tracer)->trace(std::vector<TraceRay>(5000)).isOk());
        EXPECT_GE((*tracer)->deviceBytes(), chunkBytes + 5000 * (sizeof(TraceRay) + sizeof(TraceHit)));
        EXPECT_EQ(device.liveBytes(), (*tracer)->deviceBytes());
        EXPECT_EQ(device.peakBytes(), device.liveBytes());
        // Replacing the chunk frees the old one first: the peak does not hold two chunks.
        ASSERT_TRUE((*tracer)->upload(ChunkArrays{&tree, mesh.positions, mesh.indices, {}}).isOk());
        EXPECT_EQ(device.peakBytes(), device.liveBytes());
    }
    EXPECT_EQ(device.liveBytes(), 0u) << "the tracer frees everything it allocated";
    EXPECT_GT(device.peakBytes(), 0u);
}

}  // namespace
}  // namespace vastray::gpu::test
