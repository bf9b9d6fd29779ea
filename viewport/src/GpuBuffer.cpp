#include "kerf/viewport/GpuBuffer.hpp"

#include "kerf/viewport/VulkanError.hpp"

#include <algorithm>
#include <cstring>

namespace kerf::vk {

GpuBuffer::GpuBuffer(const Context& ctx, std::size_t bytes, VkBufferUsageFlags usage, Kind kind, const char* name)
{
    (void)name; // debug names arrive with VK_EXT_debug_utils object naming
    size_ = std::max<std::size_t>(bytes, 16);
    VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bi.size = size_;
    bi.usage = usage | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
    bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VkBuffer b;
    check(vkCreateBuffer(ctx.device(), &bi, nullptr, &b), "vkCreateBuffer");
    buffer_ = Buffer(ctx.device(), b);

    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(ctx.device(), b, &req);
    VkMemoryPropertyFlags flags = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    if (kind == Kind::HostVisible) flags = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    if (kind == Kind::Readback)
        flags = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT |
                VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
    std::uint32_t type;
    try {
        type = ctx.memoryType(req.memoryTypeBits, flags);
    } catch (const VulkanError&) {
        // Not every device has host-cached memory; coherent will do.
        type = ctx.memoryType(req.memoryTypeBits, kind == Kind::DeviceLocal
                                                      ? VkMemoryPropertyFlags(0)
                                                      : VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    }
    VkMemoryAllocateFlagsInfo flagsInfo{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
    flagsInfo.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    ai.pNext = &flagsInfo;
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = type;
    VkDeviceMemory mem;
    check(vkAllocateMemory(ctx.device(), &ai, nullptr, &mem), "vkAllocateMemory");
    memory_ = Memory(ctx.device(), mem);
    check(vkBindBufferMemory(ctx.device(), b, mem, 0), "vkBindBufferMemory");
    if (kind != Kind::DeviceLocal) check(vkMapMemory(ctx.device(), mem, 0, VK_WHOLE_SIZE, 0, &mapped_), "vkMapMemory");
    VkBufferDeviceAddressInfo addr{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
    addr.buffer = b;
    address_ = vkGetBufferDeviceAddress(ctx.device(), &addr);
}

GpuBuffer uploadBuffer(const Context& ctx, const void* data, std::size_t bytes, VkBufferUsageFlags usage,
                       const char* name)
{
    GpuBuffer dst(ctx, bytes, usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, GpuBuffer::Kind::DeviceLocal, name);
    if (bytes == 0) return dst;
    GpuBuffer staging(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, GpuBuffer::Kind::HostVisible, "staging");
    std::memcpy(staging.mapped(), data, bytes);
    ctx.submitAndWait([&](VkCommandBuffer cb) {
        VkBufferCopy region{0, 0, bytes};
        vkCmdCopyBuffer(cb, staging.buffer(), dst.buffer(), 1, &region);
    });
    return dst;
}

} // namespace kerf::vk
