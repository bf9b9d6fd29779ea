#pragma once
// Vulkan failures as exceptions that say what failed and with which VkResult.
// Library code never exits the process; callers decide (fall back to the CPU
// tracer, report, retry).

#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>

namespace kerf::vk {

const char* resultName(VkResult r);

class VulkanError : public std::runtime_error {
public:
    VulkanError(const std::string& what, VkResult result)
        : std::runtime_error(what + " failed: " + resultName(result)), result_(result)
    {
    }
    VkResult result() const { return result_; }

private:
    VkResult result_;
};

inline void check(VkResult r, const char* what)
{
    if (r != VK_SUCCESS) throw VulkanError(what, r);
}

} // namespace kerf::vk
