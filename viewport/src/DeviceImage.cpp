#include "kerf/viewport/DeviceImage.hpp"

#include "kerf/viewport/VulkanError.hpp"

namespace kerf::vk {

DeviceImage makeDeviceImage(const Context& ctx, VkExtent3D extent, VkFormat format, VkImageUsageFlags usage,
                            VkImageAspectFlags aspect)
{
    const bool volume = extent.depth > 1;
    DeviceImage t;
    VkImageCreateInfo ici{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ici.imageType = volume ? VK_IMAGE_TYPE_3D : VK_IMAGE_TYPE_2D;
    ici.format = format;
    ici.extent = extent;
    ici.mipLevels = 1;
    ici.arrayLayers = 1;
    ici.samples = VK_SAMPLE_COUNT_1_BIT;
    ici.tiling = VK_IMAGE_TILING_OPTIMAL;
    ici.usage = usage;
    ici.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkImage img;
    check(vkCreateImage(ctx.device(), &ici, nullptr, &img), "vkCreateImage");
    t.image = Image(ctx.device(), img);
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(ctx.device(), img, &req);
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = ctx.memoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    VkDeviceMemory mem;
    check(vkAllocateMemory(ctx.device(), &ai, nullptr, &mem), "vkAllocateMemory (image)");
    t.memory = Memory(ctx.device(), mem);
    t.bytes = std::size_t(req.size);
    check(vkBindImageMemory(ctx.device(), img, mem, 0), "vkBindImageMemory");
    VkImageViewCreateInfo vci{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vci.image = img;
    vci.viewType = volume ? VK_IMAGE_VIEW_TYPE_3D : VK_IMAGE_VIEW_TYPE_2D;
    vci.format = format;
    vci.subresourceRange = {aspect, 0, 1, 0, 1};
    VkImageView view;
    check(vkCreateImageView(ctx.device(), &vci, nullptr, &view), "vkCreateImageView");
    t.view = ImageView(ctx.device(), view);
    return t;
}

void imageBarrier(VkCommandBuffer cb, VkImage image, VkImageLayout from, VkImageLayout to, VkAccessFlags srcAccess,
                  VkAccessFlags dstAccess, VkPipelineStageFlags srcStage, VkPipelineStageFlags dstStage)
{
    VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    b.oldLayout = from;
    b.newLayout = to;
    b.srcAccessMask = srcAccess;
    b.dstAccessMask = dstAccess;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdPipelineBarrier(cb, srcStage, dstStage, 0, 0, nullptr, 0, nullptr, 1, &b);
}

} // namespace kerf::vk
