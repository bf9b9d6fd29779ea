#pragma once
// Evaluates an encoded tile tape (voxelizer/TileTapeFormat.h) on the device
// at many points, through the GLSL tape library (shaders/tape.glsl) that the
// tracer uses: values, gradients and deciding features, read back. For the
// test that holds the GLSL and C++ tape evaluators to the same values, and
// for anything else that must see what the shaders compute.
//
// Threading: one thread; the context must outlive the probe.

#include "kerf/viewport/VulkanContext.hpp"
#include "kerf/viewport/VulkanHandle.hpp"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <vector>

namespace kerf::vk {

class TapeProbe {
public:
    explicit TapeProbe(const Context& ctx);

    struct Result {
        float value = 0.0f;        // evaluateTileTape
        glm::vec4 dual{0.0f};      // evaluateTileTapeGradient: value, then the gradient
        std::uint32_t feature = 0; // its deciding feature
    };
    /// The tape at each point (tile-relative mm); waits for the device.
    std::vector<Result> evaluate(const std::vector<std::uint32_t>& tape, const std::vector<glm::vec3>& points) const;

private:
    const Context& ctx_;
    ShaderModule module_;
    PipelineLayout layout_;
    Pipeline pipeline_;
};

} // namespace kerf::vk
