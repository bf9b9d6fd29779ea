#pragma once
// The Vulkan instance and device Kerf renders with: a discrete GPU when
// there is one, else an integrated or virtual one, else a CPU implementation
// (lavapipe). Headless: needs no window system. Validation layers are on when
// asked for (tests) and their error messages are counted.
//
// Threading: the viewport's render thread and the GPU voxelizer's worker
// share a context. Everything that touches the one queue (submissions,
// presentation, waiting for the device to be idle) holds lockQueue();
// submitAndWait() does so itself and may be called from any thread.

#include "kerf/viewport/VulkanHandle.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace kerf::vk {

struct ContextOptions {
    bool validation = false;   // enable VK_LAYER_KHRONOS_validation when installed
    bool preferCpu = false;    // pick lavapipe even when a GPU exists (tests)
    /// Enable VK_KHR_swapchain: the device must be able to present (a
    /// viewport in a window). Devices without it are passed over.
    bool presentation = false;
    /// Adopt this instance instead of creating one (a window system's
    /// instance, created with its surface extensions): the context does not
    /// destroy it. `validation` then only says whether the instance was
    /// created with the validation layer and VK_EXT_debug_utils, so that
    /// the context counts their messages.
    VkInstance externalInstance = VK_NULL_HANDLE;
    /// Enable VK_KHR_pipeline_executable_properties where the device has it,
    /// so that pipelines made with capturesPipelineStatistics() report their
    /// compiler's figures (registers, spills: kerf_gpu_bench
    /// --pipeline-statistics). Off elsewhere: capturing may slow pipeline
    /// creation and keep drivers from caching.
    bool pipelineStatistics = false;
};

class Context {
public:
    /// Throws VulkanError when there is no Vulkan implementation at all.
    explicit Context(const ContextOptions& options = {});
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    VkInstance instance() const { return instance_; }
    VkPhysicalDevice physicalDevice() const { return physical_; }
    VkDevice device() const { return device_; }
    VkQueue queue() const { return queue_; }
    std::uint32_t queueFamily() const { return queueFamily_; }
    const VkPhysicalDeviceProperties& properties() const { return properties_; }
    /// "NVIDIA H100 80GB HBM3 (discrete GPU, driver ...)".
    std::string deviceDescription() const;
    /// Largest single memory allocation the device allows (bytes).
    std::size_t maxAllocationBytes() const { return maxAllocation_; }
    bool isCpuDevice() const { return properties_.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU; }
    /// Validation messages of error severity seen so far (0 without validation).
    int validationErrors() const;
    std::vector<std::string> validationMessages() const;
    bool validationEnabled() const { return validation_; }
    /// Whether pipelines should be made with
    /// VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR (ContextOptions::pipelineStatistics
    /// on a device that has the extension).
    bool capturesPipelineStatistics() const { return pipelineStatistics_; }
    /// The compiler's statistics of each executable of `pipeline` ("Register
    /// Count: 96", ...) as the driver names them; empty unless
    /// capturesPipelineStatistics() and the pipeline was made with the flag.
    std::vector<std::string> pipelineStatistics(VkPipeline pipeline) const;

    /// Memory type index with the given properties, or throws.
    std::uint32_t memoryType(std::uint32_t typeBits, VkMemoryPropertyFlags flags) const;

    /// Records commands into a one-time command buffer, submits it and waits.
    void submitAndWait(const std::function<void(VkCommandBuffer)>& record) const;
    /// Held around every use of queue() (vkQueueSubmit, vkQueuePresentKHR)
    /// and vkDeviceWaitIdle: Vulkan requires their callers to be serialized.
    [[nodiscard]] std::unique_lock<std::mutex> lockQueue() const { return std::unique_lock(queueMutex_); }

private:
    struct Messages;
    static VKAPI_ATTR VkBool32 VKAPI_CALL onDebugMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                         VkDebugUtilsMessageTypeFlagsEXT type,
                                                         const VkDebugUtilsMessengerCallbackDataEXT* data, void* user);

    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    std::uint32_t queueFamily_ = 0;
    VkPhysicalDeviceProperties properties_{};
    VkPhysicalDeviceMemoryProperties memory_{};
    std::size_t maxAllocation_ = std::size_t(1) << 30;
    bool validation_ = false;
    bool pipelineStatistics_ = false;
    bool ownsInstance_ = true;
    mutable std::mutex queueMutex_;
    mutable std::mutex poolMutex_; // submitAndWait's command pool
    std::unique_ptr<Messages> messages_;
    CommandPool pool_;
};

} // namespace kerf::vk
