#pragma once
// A shader module from SPIR-V embedded at build time (the kerf_embed_shader
// headers): one place for every pipeline's module.

#include "kerf/viewport/VulkanHandle.hpp"

#include <cstddef>
#include <cstdint>

namespace kerf::vk {

/// Throws VulkanError naming `what` when the device refuses the code.
ShaderModule makeShaderModule(VkDevice device, const std::uint32_t* code, std::size_t bytes, const char* what);

} // namespace kerf::vk
