#include "kerf/viewport/VulkanContext.hpp"

#include "kerf/viewport/VulkanError.hpp"

#include <algorithm>
#include <cstring>
#include <mutex>

namespace kerf::vk {

struct Context::Messages {
    std::mutex mutex;
    int errors = 0;
    std::vector<std::string> texts;
};

namespace {

bool hasLayer(const char* name)
{
    std::uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, nullptr);
    std::vector<VkLayerProperties> layers(n);
    vkEnumerateInstanceLayerProperties(&n, layers.data());
    return std::any_of(layers.begin(), layers.end(), [&](const auto& l) { return std::strcmp(l.layerName, name) == 0; });
}

bool hasInstanceExtension(const char* name)
{
    std::uint32_t n = 0;
    vkEnumerateInstanceExtensionProperties(nullptr, &n, nullptr);
    std::vector<VkExtensionProperties> ext(n);
    vkEnumerateInstanceExtensionProperties(nullptr, &n, ext.data());
    return std::any_of(ext.begin(), ext.end(), [&](const auto& e) { return std::strcmp(e.extensionName, name) == 0; });
}

bool hasDeviceExtension(VkPhysicalDevice d, const char* name)
{
    std::uint32_t n = 0;
    vkEnumerateDeviceExtensionProperties(d, nullptr, &n, nullptr);
    std::vector<VkExtensionProperties> ext(n);
    vkEnumerateDeviceExtensionProperties(d, nullptr, &n, ext.data());
    return std::any_of(ext.begin(), ext.end(), [&](const auto& e) { return std::strcmp(e.extensionName, name) == 0; });
}

int deviceRank(VkPhysicalDeviceType t, bool preferCpu)
{
    if (preferCpu) return t == VK_PHYSICAL_DEVICE_TYPE_CPU ? 0 : 1;
    switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
    default: return 4;
    }
}

const char* typeName(VkPhysicalDeviceType t)
{
    switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU implementation";
    default: return "other device";
    }
}

} // namespace

VKAPI_ATTR VkBool32 VKAPI_CALL Context::onDebugMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                       VkDebugUtilsMessageTypeFlagsEXT,
                                                       const VkDebugUtilsMessengerCallbackDataEXT* data, void* user)
{
    auto* m = static_cast<Messages*>(user);
    std::lock_guard lock(m->mutex);
    if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) ++m->errors;
    m->texts.emplace_back(data && data->pMessage ? data->pMessage : "(no message)");
    return VK_FALSE; // never abort the call that triggered it
}

Context::Context(const ContextOptions& options) : messages_(std::make_unique<Messages>())
{
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "Kerf";
    app.pEngineName = "Kerf";
    app.apiVersion = VK_API_VERSION_1_2;

    std::vector<const char*> layers, extensions;
    validation_ = options.validation && hasLayer("VK_LAYER_KHRONOS_validation");
    if (validation_) layers.push_back("VK_LAYER_KHRONOS_validation");
    const bool debugUtils = validation_ && hasInstanceExtension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    if (debugUtils) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);

    VkDebugUtilsMessengerCreateInfoEXT dbg{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    dbg.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    dbg.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                      VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    dbg.pfnUserCallback = onDebugMessage;
    dbg.pUserData = messages_.get();

    if (options.externalInstance) {
        instance_ = options.externalInstance;
        ownsInstance_ = false;
        validation_ = options.validation;
    } else {
        VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
        ici.pApplicationInfo = &app;
        ici.enabledLayerCount = std::uint32_t(layers.size());
        ici.ppEnabledLayerNames = layers.data();
        ici.enabledExtensionCount = std::uint32_t(extensions.size());
        ici.ppEnabledExtensionNames = extensions.data();
        if (debugUtils) ici.pNext = &dbg;
        check(vkCreateInstance(&ici, nullptr, &instance_), "vkCreateInstance");
    }

    if (debugUtils || (options.externalInstance && options.validation)) {
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
        if (create) create(instance_, &dbg, nullptr, &messenger_);
    }

    std::uint32_t count = 0;
    vkEnumeratePhysicalDevices(instance_, &count, nullptr);
    std::vector<VkPhysicalDevice> devices(count);
    vkEnumeratePhysicalDevices(instance_, &count, devices.data());
    int best = 99;
    for (VkPhysicalDevice d : devices) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(d, &p);
        if (p.apiVersion < VK_API_VERSION_1_2) continue;
        VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
        VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
        f2.pNext = &f12;
        vkGetPhysicalDeviceFeatures2(d, &f2);
        if (!f12.bufferDeviceAddress || !f2.features.shaderInt64) continue;
        if (options.presentation && !hasDeviceExtension(d, VK_KHR_SWAPCHAIN_EXTENSION_NAME)) continue;
        const int rank = deviceRank(p.deviceType, options.preferCpu);
        if (rank < best) {
            best = rank;
            physical_ = d;
            properties_ = p;
        }
    }
    if (!physical_) {
        if (ownsInstance_) vkDestroyInstance(instance_, nullptr);
        instance_ = VK_NULL_HANDLE;
        throw VulkanError(options.presentation
                              ? "finding a Vulkan 1.2 device with buffer device addresses, 64-bit integers and swapchains"
                              : "finding a Vulkan 1.2 device with buffer device addresses and 64-bit integers",
                          VK_ERROR_INCOMPATIBLE_DRIVER);
    }
    vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);
    VkPhysicalDeviceMaintenance3Properties m3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
    VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    p2.pNext = &m3;
    vkGetPhysicalDeviceProperties2(physical_, &p2);
    maxAllocation_ = std::size_t(m3.maxMemoryAllocationSize);

    std::uint32_t nf = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &nf, nullptr);
    std::vector<VkQueueFamilyProperties> families(nf);
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &nf, families.data());
    queueFamily_ = UINT32_MAX;
    for (std::uint32_t i = 0; i < nf; ++i) // prefer a family with graphics too (the viewport draws meshes)
        if ((families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) && (families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT)) {
            queueFamily_ = i;
            break;
        }
    for (std::uint32_t i = 0; i < nf && queueFamily_ == UINT32_MAX; ++i)
        if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) queueFamily_ = i;
    if (queueFamily_ == UINT32_MAX) throw VulkanError("finding a compute queue", VK_ERROR_FEATURE_NOT_PRESENT);

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qci.queueFamilyIndex = queueFamily_;
    qci.queueCount = 1;
    qci.pQueuePriorities = &priority;
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    f12.bufferDeviceAddress = VK_TRUE;
    f12.scalarBlockLayout = VK_FALSE;
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    f2.pNext = &f12;
    f2.features.shaderInt64 = VK_TRUE;
    std::vector<const char*> deviceExtensions;
    if (options.presentation) deviceExtensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR executableInfo{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR};
    if (options.pipelineStatistics && hasDeviceExtension(physical_, VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME)) {
        deviceExtensions.push_back(VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME);
        executableInfo.pipelineExecutableInfo = VK_TRUE;
        f12.pNext = &executableInfo;
        pipelineStatistics_ = true;
    }
    VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    dci.pNext = &f2;
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    dci.enabledExtensionCount = std::uint32_t(deviceExtensions.size());
    dci.ppEnabledExtensionNames = deviceExtensions.data();
    check(vkCreateDevice(physical_, &dci, nullptr, &device_), "vkCreateDevice");
    vkGetDeviceQueue(device_, queueFamily_, 0, &queue_);

    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = queueFamily_;
    VkCommandPool pool;
    check(vkCreateCommandPool(device_, &pci, nullptr, &pool), "vkCreateCommandPool");
    pool_ = CommandPool(device_, pool);
}

Context::~Context()
{
    if (device_) vkDeviceWaitIdle(device_);
    pool_.reset();
    if (device_) vkDestroyDevice(device_, nullptr);
    if (messenger_) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
        if (destroy) destroy(instance_, messenger_, nullptr);
    }
    if (instance_ && ownsInstance_) vkDestroyInstance(instance_, nullptr);
}

std::string Context::deviceDescription() const
{
    const std::uint32_t v = properties_.apiVersion;
    return std::string(properties_.deviceName) + " (" + typeName(properties_.deviceType) + ", Vulkan " +
           std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) + "." +
           std::to_string(VK_API_VERSION_PATCH(v)) + ")";
}

std::vector<std::string> Context::pipelineStatistics(VkPipeline pipeline) const
{
    std::vector<std::string> lines;
    if (!pipelineStatistics_) return lines;
    const auto properties = reinterpret_cast<PFN_vkGetPipelineExecutablePropertiesKHR>(
        vkGetDeviceProcAddr(device_, "vkGetPipelineExecutablePropertiesKHR"));
    const auto statistics = reinterpret_cast<PFN_vkGetPipelineExecutableStatisticsKHR>(
        vkGetDeviceProcAddr(device_, "vkGetPipelineExecutableStatisticsKHR"));
    if (!properties || !statistics) return lines;
    VkPipelineInfoKHR info{VK_STRUCTURE_TYPE_PIPELINE_INFO_KHR};
    info.pipeline = pipeline;
    std::uint32_t executables = 0;
    if (properties(device_, &info, &executables, nullptr) != VK_SUCCESS) return lines;
    for (std::uint32_t e = 0; e < executables; ++e) {
        VkPipelineExecutableInfoKHR which{VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_INFO_KHR};
        which.pipeline = pipeline;
        which.executableIndex = e;
        std::uint32_t count = 0;
        if (statistics(device_, &which, &count, nullptr) != VK_SUCCESS) continue;
        std::vector<VkPipelineExecutableStatisticKHR> stats(count, {VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_STATISTIC_KHR});
        if (statistics(device_, &which, &count, stats.data()) != VK_SUCCESS) continue;
        for (const VkPipelineExecutableStatisticKHR& st : stats) {
            std::string value;
            switch (st.format) {
            case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_BOOL32_KHR: value = st.value.b32 ? "yes" : "no"; break;
            case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_INT64_KHR: value = std::to_string(st.value.i64); break;
            case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_UINT64_KHR: value = std::to_string(st.value.u64); break;
            default: value = std::to_string(st.value.f64); break;
            }
            lines.push_back(std::string(st.name) + ": " + value);
        }
    }
    return lines;
}

int Context::validationErrors() const
{
    std::lock_guard lock(messages_->mutex);
    return messages_->errors;
}

std::vector<std::string> Context::validationMessages() const
{
    std::lock_guard lock(messages_->mutex);
    return messages_->texts;
}

std::uint32_t Context::memoryType(std::uint32_t typeBits, VkMemoryPropertyFlags flags) const
{
    for (std::uint32_t i = 0; i < memory_.memoryTypeCount; ++i)
        if ((typeBits & (1u << i)) && (memory_.memoryTypes[i].propertyFlags & flags) == flags) return i;
    throw VulkanError("finding a memory type", VK_ERROR_FEATURE_NOT_PRESENT);
}

void Context::submitAndWait(const std::function<void(VkCommandBuffer)>& record) const
{
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = pool_;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    // The pool and its command buffers are used by one thread at a time;
    // the wait for the device happens with neither lock held.
    std::unique_lock poolLock(poolMutex_);
    VkCommandBuffer cb;
    check(vkAllocateCommandBuffers(device_, &ai, &cb), "vkAllocateCommandBuffers");
    struct Free {
        VkDevice d;
        VkCommandPool p;
        VkCommandBuffer c;
        std::unique_lock<std::mutex>& lock;
        ~Free()
        {
            if (!lock.owns_lock()) lock.lock();
            vkFreeCommandBuffers(d, p, 1, &c);
        }
    } freeLater{device_, pool_, cb, poolLock};
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vkBeginCommandBuffer(cb, &bi), "vkBeginCommandBuffer");
    record(cb);
    check(vkEndCommandBuffer(cb), "vkEndCommandBuffer");
    VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence;
    check(vkCreateFence(device_, &fi, nullptr, &fence), "vkCreateFence");
    Fence owned(device_, fence);
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cb;
    {
        const auto queueLock = lockQueue();
        check(vkQueueSubmit(queue_, 1, &si, fence), "vkQueueSubmit");
    }
    poolLock.unlock();
    check(vkWaitForFences(device_, 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
}

} // namespace kerf::vk
