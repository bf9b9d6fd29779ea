#include "kerf/viewport/ShaderModules.hpp"

#include "kerf/viewport/VulkanError.hpp"

namespace kerf::vk {

ShaderModule makeShaderModule(VkDevice device, const std::uint32_t* code, std::size_t bytes, const char* what)
{
    VkShaderModuleCreateInfo ci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    ci.codeSize = bytes;
    ci.pCode = code;
    VkShaderModule m;
    check(vkCreateShaderModule(device, &ci, nullptr, &m), what);
    return ShaderModule(device, m);
}

} // namespace kerf::vk
