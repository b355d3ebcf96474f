// Counted, persistently mapped buffers (VulkanDevice::createBuffer and GpuBuffer).
#include <algorithm>
#include <cstring>
#include <utility>

#include "VkCheck.h"
#include "vastray/gpu/VulkanDevice.h"

namespace vastray::gpu {
namespace {

// Buffers are read by shaders through device addresses (and by indirect dispatches) and filled
// by the host through a map or by copies.
constexpr VkBufferUsageFlags kBufferUsage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                            VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT |
                                            VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                                            VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;
constexpr uint64_t kMinBufferBytes = 16;

}  // namespace


Result<GpuBuffer> VulkanDevice::createBuffer(uint64_t bytes, MemoryUse use) {
    GpuBuffer buffer;  // released by its destructor on any early return below
    buffer.device_ = this;
    buffer.size_ = bytes;
    auto info = vkStruct<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
    info.size = std::max(bytes, kMinBufferBytes);
    info.usage = kBufferUsage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    // Filled on the transfer queue and read by the kernels: concurrent sharing spares the queue
    // family ownership transfers (a release and an acquire barrier per copy).
    const uint32_t families[2] = {computeFamily_, transferFamily_};
    if (use == MemoryUse::DeviceOnly && separateTransferQueue()) {
        info.sharingMode = VK_SHARING_MODE_CONCURRENT;
        info.queueFamilyIndexCount = 2;
        info.pQueueFamilyIndices = families;
    }
    VASTRAY_VK_TRY(vkCreateBuffer(device_, &info, nullptr, &buffer.buffer_));
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device_, buffer.buffer_, &req);
    auto type = findMemoryType(req.memoryTypeBits, use);
    VASTRAY_TRY(type);
    auto flags = vkStruct<VkMemoryAllocateFlagsInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO);
    flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
    auto alloc = vkStruct<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
    alloc.pNext = &flags;
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex = *type;
    VASTRAY_VK_TRY(vkAllocateMemory(device_, &alloc, nullptr, &buffer.memory_));
    buffer.allocated_ = req.size;
    liveBytes_ += req.size;
    peakBytes_ = std::max(peakBytes_, liveBytes_);
    ++allocationCount_;
    VASTRAY_VK_TRY(vkBindBufferMemory(device_, buffer.buffer_, buffer.memory_, 0));
    if (memoryProperties_.memoryTypes[*type].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT)
        VASTRAY_VK_TRY(vkMapMemory(device_, buffer.memory_, 0, VK_WHOLE_SIZE, 0, &buffer.mapped_));
    auto addressInfo = vkStruct<VkBufferDeviceAddressInfo>(VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO);
    addressInfo.buffer = buffer.buffer_;
    buffer.address_ = vkGetBufferDeviceAddress(device_, &addressInfo);
    return buffer;
}

void VulkanDevice::freeBuffer(GpuBuffer& buffer) {
    // After a timed-out submission the device may still write this memory: it is released only
    // once the device is idle, when the VulkanDevice is destroyed.
    if (!failure_.empty()) {
        if (buffer.memory_) abandoned_.push_back({buffer.buffer_, buffer.memory_});
        return;
    }
    if (buffer.mapped_) vkUnmapMemory(device_, buffer.memory_);
    if (buffer.buffer_) vkDestroyBuffer(device_, buffer.buffer_, nullptr);
    if (buffer.memory_) {
        vkFreeMemory(device_, buffer.memory_, nullptr);
        liveBytes_ -= buffer.allocated_;
        --allocationCount_;
    }
}

GpuBuffer::GpuBuffer(GpuBuffer&& other) noexcept { *this = std::move(other); }

GpuBuffer& GpuBuffer::operator=(GpuBuffer&& other) noexcept {
    if (this != &other) {
        release();
        device_ = std::exchange(other.device_, nullptr);
        buffer_ = std::exchange(other.buffer_, VK_NULL_HANDLE);
        memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
        mapped_ = std::exchange(other.mapped_, nullptr);
        size_ = std::exchange(other.size_, 0);
        allocated_ = std::exchange(other.allocated_, 0);
        address_ = std::exchange(other.address_, 0);
    }
    return *this;
}

GpuBuffer::~GpuBuffer() { release(); }

void GpuBuffer::release() {
    if (device_) device_->freeBuffer(*this);
    device_ = nullptr;
    buffer_ = VK_NULL_HANDLE;
    memory_ = VK_NULL_HANDLE;
    mapped_ = nullptr;
    size_ = allocated_ = 0;
    address_ = 0;
}

Status GpuBuffer::upload(const void* data, uint64_t bytes, uint64_t offset) {
    if (!mapped_ && buffer_) return Status::error("upload into a buffer the host cannot map (copy it on the device)");
    if (!mapped_ || offset > size_ || bytes > size_ - offset)
        return Status::error("upload of " + std::to_string(bytes) + " bytes at " + std::to_string(offset) +
                             " exceeds a buffer of " + std::to_string(size_) + " bytes");
    if (bytes) std::memcpy(static_cast<uint8_t*>(mapped_) + offset, data, bytes);
    return Status::ok();
}

Status GpuBuffer::download(void* data, uint64_t bytes, uint64_t offset) const {
    if (!mapped_ && buffer_) return Status::error("download from a buffer the host cannot map (copy it on the device)");
    if (!mapped_ || offset > size_ || bytes > size_ - offset)
        return Status::error("download of " + std::to_string(bytes) + " bytes at " + std::to_string(offset) +
                             " exceeds a buffer of " + std::to_string(size_) + " bytes");
    if (bytes) std::memcpy(data, static_cast<const uint8_t*>(mapped_) + offset, bytes);
    return Status::ok();
}

}  // namespace vastray::gpu
