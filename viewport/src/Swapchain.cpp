#include "kerf/viewport/Swapchain.hpp"

#include "kerf/viewport/VulkanError.hpp"

#include <algorithm>

namespace kerf::vk {

Swapchain::Swapchain(const Context& ctx, VkSurfaceKHR surface, bool vsync)
    : ctx_(ctx), surface_(surface), vsync_(vsync)
{
    VkBool32 supported = VK_FALSE;
    check(vkGetPhysicalDeviceSurfaceSupportKHR(ctx.physicalDevice(), ctx.queueFamily(), surface, &supported),
          "vkGetPhysicalDeviceSurfaceSupportKHR");
    if (!supported)
        throw VulkanError("presenting to the window from the device's queue", VK_ERROR_FEATURE_NOT_PRESENT);

    std::uint32_t n = 0;
    check(vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physicalDevice(), surface, &n, nullptr),
          "vkGetPhysicalDeviceSurfaceFormatsKHR");
    std::vector<VkSurfaceFormatKHR> formats(n);
    check(vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physicalDevice(), surface, &n, formats.data()),
          "vkGetPhysicalDeviceSurfaceFormatsKHR");
    if (formats.empty()) throw VulkanError("finding a surface format", VK_ERROR_FORMAT_NOT_SUPPORTED);
    // The picture is already sRGB-encoded (the shading pass encodes it), so a
    // UNORM format keeps its values; an sRGB one would encode them twice.
    auto it = std::find_if(formats.begin(), formats.end(), [](const VkSurfaceFormatKHR& f) {
        return f.format == VK_FORMAT_B8G8R8A8_UNORM || f.format == VK_FORMAT_R8G8B8A8_UNORM;
    });
    const VkSurfaceFormatKHR chosen = it != formats.end() ? *it : formats.front();
    format_ = chosen.format;
    colorSpace_ = chosen.colorSpace;
}

Swapchain::~Swapchain() { release(); }

void Swapchain::release()
{
    if (swapchain_) {
        const auto queueLock = ctx_.lockQueue();
        vkDeviceWaitIdle(ctx_.device());
        vkDestroySwapchainKHR(ctx_.device(), swapchain_, nullptr);
    }
    swapchain_ = VK_NULL_HANDLE;
    images_.clear();
    extent_ = {0, 0};
    outOfDate_ = true;
}

bool Swapchain::ensure(int width, int height)
{
    VkSurfaceCapabilitiesKHR caps;
    check(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(ctx_.physicalDevice(), surface_, &caps),
          "vkGetPhysicalDeviceSurfaceCapabilitiesKHR");
    VkExtent2D want = caps.currentExtent;
    if (want.width == 0xFFFFFFFFu) {
        want.width = std::clamp(std::uint32_t(std::max(width, 1)), caps.minImageExtent.width, caps.maxImageExtent.width);
        want.height =
            std::clamp(std::uint32_t(std::max(height, 1)), caps.minImageExtent.height, caps.maxImageExtent.height);
    }
    if (want.width == 0 || want.height == 0) return false;
    if (!outOfDate_ && swapchain_ && want.width == extent_.width && want.height == extent_.height) return true;

    VkSwapchainCreateInfoKHR ci{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    ci.surface = surface_;
    ci.minImageCount = std::max(caps.minImageCount, 2u);
    if (caps.maxImageCount) ci.minImageCount = std::min(ci.minImageCount, caps.maxImageCount);
    ci.imageFormat = format_;
    ci.imageColorSpace = colorSpace_;
    ci.imageExtent = want;
    ci.imageArrayLayers = 1;
    ci.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
        throw VulkanError("a swapchain whose images can be copied into", VK_ERROR_FEATURE_NOT_PRESENT);
    ci.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    ci.preTransform = caps.currentTransform;
    ci.compositeAlpha = (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR)
                            ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
                            : VkCompositeAlphaFlagBitsKHR(caps.supportedCompositeAlpha & -caps.supportedCompositeAlpha);
    // FIFO is always there; without vsync, IMMEDIATE or MAILBOX where offered.
    ci.presentMode = VK_PRESENT_MODE_FIFO_KHR;
    if (!vsync_) {
        std::uint32_t n = 0;
        vkGetPhysicalDeviceSurfacePresentModesKHR(ctx_.physicalDevice(), surface_, &n, nullptr);
        std::vector<VkPresentModeKHR> modes(n);
        vkGetPhysicalDeviceSurfacePresentModesKHR(ctx_.physicalDevice(), surface_, &n, modes.data());
        for (VkPresentModeKHR m : {VK_PRESENT_MODE_MAILBOX_KHR, VK_PRESENT_MODE_IMMEDIATE_KHR})
            if (std::find(modes.begin(), modes.end(), m) != modes.end()) {
                ci.presentMode = m;
                break;
            }
    }
    ci.clipped = VK_TRUE;
    ci.oldSwapchain = swapchain_;
    VkSwapchainKHR made;
    {
        const auto queueLock = ctx_.lockQueue();
        vkDeviceWaitIdle(ctx_.device());
    }
    check(vkCreateSwapchainKHR(ctx_.device(), &ci, nullptr, &made), "vkCreateSwapchainKHR");
    if (swapchain_) vkDestroySwapchainKHR(ctx_.device(), swapchain_, nullptr);
    swapchain_ = made;
    std::uint32_t count = 0;
    check(vkGetSwapchainImagesKHR(ctx_.device(), swapchain_, &count, nullptr), "vkGetSwapchainImagesKHR");
    images_.resize(count);
    check(vkGetSwapchainImagesKHR(ctx_.device(), swapchain_, &count, images_.data()), "vkGetSwapchainImagesKHR");
    extent_ = want;
    outOfDate_ = false;
    return true;
}

std::optional<std::uint32_t> Swapchain::acquire(VkSemaphore acquired)
{
    if (!swapchain_ || outOfDate_) return std::nullopt;
    std::uint32_t index = 0;
    const VkResult r = vkAcquireNextImageKHR(ctx_.device(), swapchain_, UINT64_MAX, acquired, VK_NULL_HANDLE, &index);
    if (r == VK_ERROR_OUT_OF_DATE_KHR) {
        outOfDate_ = true;
        return std::nullopt;
    }
    if (r != VK_SUBOPTIMAL_KHR) check(r, "vkAcquireNextImageKHR");
    return index;
}

bool Swapchain::present(std::uint32_t index, VkSemaphore rendered)
{
    VkPresentInfoKHR pi{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    pi.waitSemaphoreCount = 1;
    pi.pWaitSemaphores = &rendered;
    pi.swapchainCount = 1;
    pi.pSwapchains = &swapchain_;
    pi.pImageIndices = &index;
    VkResult r;
    {
        const auto queueLock = ctx_.lockQueue();
        r = vkQueuePresentKHR(ctx_.queue(), &pi);
    }
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) {
        outOfDate_ = true;
        return r == VK_SUBOPTIMAL_KHR;
    }
    check(r, "vkQueuePresentKHR");
    return true;
}

} // namespace kerf::vk
