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

ComputePipeline makeComputePipeline(VkDevice device, const std::uint32_t* code, std::size_t bytes,
                                    std::uint32_t pushBytes, const char* what)
{
    ComputePipeline c;
    c.module = makeShaderModule(device, code, bytes, what);
    const VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, pushBytes};
    VkPipelineLayoutCreateInfo plci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    plci.pushConstantRangeCount = 1;
    plci.pPushConstantRanges = &range;
    VkPipelineLayout pl;
    check(vkCreatePipelineLayout(device, &plci, nullptr, &pl), what);
    c.layout = PipelineLayout(device, pl);
    VkComputePipelineCreateInfo cpci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    cpci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    cpci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    cpci.stage.module = c.module;
    cpci.stage.pName = "main";
    cpci.layout = c.layout;
    VkPipeline p;
    check(vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &cpci, nullptr, &p), what);
    c.pipeline = Pipeline(device, p);
    return c;
}

} // namespace kerf::vk
