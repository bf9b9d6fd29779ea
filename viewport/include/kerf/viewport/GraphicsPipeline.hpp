#pragma once
// The rasterizing passes' pipelines (the scene renderer's, the brick
// renderer's): triangle lists, one viewport and scissor set per frame,
// depth tested, and what differs between them in a style.

#include "kerf/viewport/VulkanHandle.hpp"

#include <cstdint>
#include <span>

namespace kerf::vk {

struct GraphicsPipelineStyle {
    bool meshInput = false; // a vertex buffer of position + normal (six floats); else none
    VkCompareOp depthCompare = VK_COMPARE_OP_ALWAYS;
    bool depthWrite = true;
    bool blend = false; // alpha blending over what is there (the picture's alpha kept)
    std::uint32_t colorAttachments = 1;
    VkCullModeFlags cullMode = VK_CULL_MODE_NONE;
    VkFrontFace frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
};

/// Throws VulkanError naming `what` when the device refuses it.
Pipeline makeGraphicsPipeline(VkDevice device, VkRenderPass renderPass, VkPipelineLayout layout,
                              const ShaderModule& vs, const ShaderModule& fs, const GraphicsPipelineStyle& style,
                              const char* what);

/// A render pass of one subpass: the colour targets cleared and left ready to
/// be copied from (TRANSFER_SRC_OPTIMAL), the depth target (the last
/// attachment) cleared and dropped. A frame's copies of the last frame's
/// colour finish before it draws again.
RenderPass makeCopiedRenderPass(VkDevice device, std::span<const VkFormat> colourFormats, VkFormat depthFormat,
                                const char* what);

} // namespace kerf::vk
