#pragma once
// A shader module from SPIR-V embedded at build time (the kerf_embed_shader
// headers): one place for every pipeline's module, and the plain compute
// pipelines made of one.

#include "kerf/viewport/VulkanHandle.hpp"

#include <cstddef>
#include <cstdint>

namespace kerf::vk {

/// Throws VulkanError naming `what` when the device refuses the code.
ShaderModule makeShaderModule(VkDevice device, const std::uint32_t* code, std::size_t bytes, const char* what);

/// A compute pipeline of one shader whose only input is a push-constant
/// block of `pushBytes` (everything else reached by device address).
struct ComputePipeline {
    ShaderModule module;
    PipelineLayout layout;
    Pipeline pipeline;
};
ComputePipeline makeComputePipeline(VkDevice device, const std::uint32_t* code, std::size_t bytes,
                                    std::uint32_t pushBytes, const char* what);

} // namespace kerf::vk
