#pragma once
// One owner per Vulkan object: a move-only handle that destroys its object
// with the function it was created for. Objects of a device are destroyed
// with that device, which must outlive them (the context owns the device and
// is destroyed last).

#include <vulkan/vulkan.h>

#include <utility>

namespace kerf::vk {

template <class Handle, class Parent, void (*Destroy)(Parent, Handle, const VkAllocationCallbacks*)>
class Owned {
public:
    Owned() = default;
    Owned(Parent parent, Handle handle) : parent_(parent), handle_(handle) {}
    ~Owned() { reset(); }
    Owned(Owned&& o) noexcept : parent_(o.parent_), handle_(std::exchange(o.handle_, VK_NULL_HANDLE)) {}
    Owned& operator=(Owned&& o) noexcept
    {
        if (this != &o) {
            reset();
            parent_ = o.parent_;
            handle_ = std::exchange(o.handle_, VK_NULL_HANDLE);
        }
        return *this;
    }
    Owned(const Owned&) = delete;
    Owned& operator=(const Owned&) = delete;

    void reset()
    {
        if (handle_ != VK_NULL_HANDLE) Destroy(parent_, handle_, nullptr);
        handle_ = VK_NULL_HANDLE;
    }
    Handle get() const { return handle_; }
    operator Handle() const { return handle_; }
    explicit operator bool() const { return handle_ != VK_NULL_HANDLE; }

private:
    Parent parent_ = VK_NULL_HANDLE;
    Handle handle_ = VK_NULL_HANDLE;
};

using Buffer = Owned<VkBuffer, VkDevice, vkDestroyBuffer>;
using Memory = Owned<VkDeviceMemory, VkDevice, vkFreeMemory>;
using ShaderModule = Owned<VkShaderModule, VkDevice, vkDestroyShaderModule>;
using Pipeline = Owned<VkPipeline, VkDevice, vkDestroyPipeline>;
using PipelineLayout = Owned<VkPipelineLayout, VkDevice, vkDestroyPipelineLayout>;
using DescriptorSetLayout = Owned<VkDescriptorSetLayout, VkDevice, vkDestroyDescriptorSetLayout>;
using DescriptorPool = Owned<VkDescriptorPool, VkDevice, vkDestroyDescriptorPool>;
using CommandPool = Owned<VkCommandPool, VkDevice, vkDestroyCommandPool>;
using Fence = Owned<VkFence, VkDevice, vkDestroyFence>;
using Semaphore = Owned<VkSemaphore, VkDevice, vkDestroySemaphore>;
using QueryPool = Owned<VkQueryPool, VkDevice, vkDestroyQueryPool>;
using Image = Owned<VkImage, VkDevice, vkDestroyImage>;
using ImageView = Owned<VkImageView, VkDevice, vkDestroyImageView>;
using RenderPass = Owned<VkRenderPass, VkDevice, vkDestroyRenderPass>;
using Framebuffer = Owned<VkFramebuffer, VkDevice, vkDestroyFramebuffer>;
using Sampler = Owned<VkSampler, VkDevice, vkDestroySampler>;

} // namespace kerf::vk
