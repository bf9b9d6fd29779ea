#pragma once
// The images a window shows: a VkSwapchainKHR over a surface that the
// window system made (Qt's QVulkanInstance::surfaceForWindow in the
// desktop application). The picture is copied in with a blit, so the
// swapchain's images need only colour-attachment and transfer-destination
// use, and any 8-bit colour format the surface offers will do.
//
// Lifetime: the surface must outlive the swapchain; destroy the swapchain
// (or call release()) before the window system destroys the surface.
// Threading: one thread (the render thread).

#include "kerf/viewport/VulkanContext.hpp"

#include <cstdint>
#include <optional>
#include <vector>

namespace kerf::vk {

class Swapchain {
public:
    /// Throws VulkanError when the context's queue cannot present to the surface.
    Swapchain(const Context& ctx, VkSurfaceKHR surface, bool vsync = true);
    ~Swapchain();
    Swapchain(const Swapchain&) = delete;
    Swapchain& operator=(const Swapchain&) = delete;

    /// (Re)creates the images when the size changed or the last present said
    /// they are out of date. `width` and `height` (pixels) are used where the
    /// surface leaves the size to the application. False when the surface
    /// has no area (a minimized window): nothing can be shown.
    bool ensure(int width, int height);
    /// Acquires the next image, signalling `acquired` when it may be written.
    /// Nothing when the images are out of date (call ensure() again).
    std::optional<std::uint32_t> acquire(VkSemaphore acquired);
    /// Queues image `index` for presentation after `rendered` is signalled.
    /// False when the images went out of date (they are re-made next ensure()).
    bool present(std::uint32_t index, VkSemaphore rendered);
    /// Destroys the images and the swapchain (before the surface goes away).
    void release();

    VkImage image(std::uint32_t index) const { return images_[index]; }
    VkFormat format() const { return format_; }
    int width() const { return int(extent_.width); }
    int height() const { return int(extent_.height); }

private:
    void create(int width, int height);

    const Context& ctx_;
    VkSurfaceKHR surface_;
    bool vsync_;
    VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
    std::vector<VkImage> images_;
    VkFormat format_ = VK_FORMAT_UNDEFINED;
    VkColorSpaceKHR colorSpace_ = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
    VkExtent2D extent_{0, 0};
    bool outOfDate_ = true;
};

} // namespace kerf::vk
