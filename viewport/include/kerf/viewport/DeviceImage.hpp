#pragma once
// A device-local image with its memory and a view of all of it (the render
// targets of the rasterizing passes, the brick renderer's 3D atlases), and
// the barrier that changes a colour image's layout.

#include "kerf/viewport/VulkanContext.hpp"
#include "kerf/viewport/VulkanHandle.hpp"

namespace kerf::vk {

struct DeviceImage {
    Image image;
    Memory memory;
    ImageView view;
    std::size_t bytes = 0; // of its memory
};

/// A 2D image when extent.depth is 1, else a 3D one; one mip level, one layer.
DeviceImage makeDeviceImage(const Context& ctx, VkExtent3D extent, VkFormat format, VkImageUsageFlags usage,
                            VkImageAspectFlags aspect);

/// Records a layout change of a colour image's whole (one level, one layer).
void imageBarrier(VkCommandBuffer cb, VkImage image, VkImageLayout from, VkImageLayout to, VkAccessFlags srcAccess,
                  VkAccessFlags dstAccess, VkPipelineStageFlags srcStage, VkPipelineStageFlags dstStage);

} // namespace kerf::vk
