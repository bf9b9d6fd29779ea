#pragma once
// Evaluates an encoded tile tape (voxelizer/TileTapeFormat.h) on the device
// through the GLSL tape library (shaders/tape.glsl) that the tracer uses:
// values, gradients and deciding features at many points, or intervals over
// many boxes, read back. For the
// test that holds the GLSL and C++ tape evaluators to the same values, and
// for anything else that must see what the shaders compute.
//
// Threading: one thread; the context must outlive the probe.

#include "kerf/viewport/VulkanContext.hpp"
#include "kerf/viewport/ShaderModules.hpp"
#include "kerf/viewport/VulkanHandle.hpp"

#include <glm/vec2.hpp>
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

    struct Box {
        glm::vec3 lo{0.0f}, hi{0.0f}; // tile-relative mm
    };
    /// evaluateTileTapeInterval over each box: (lo, hi); waits for the device.
    std::vector<glm::vec2> enclose(const std::vector<std::uint32_t>& tape, const std::vector<Box>& boxes) const;

private:
    /// Runs the kernel over `count` inputs (one vec4 per point, two per box); two vec4 of results each.
    std::vector<glm::vec4> run(const std::vector<std::uint32_t>& tape, const std::vector<glm::vec4>& inputs,
                               std::size_t count, bool boxes) const;

    const Context& ctx_;
    ComputePipeline compute_;
};

} // namespace kerf::vk
