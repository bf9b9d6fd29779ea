#pragma once
// What the GPU tests share: a Vulkan context with the validation layers (the
// test skips without a device), and a pixel-by-pixel comparison of a GPU
// image with the CPU reference tracer's.

#include "kerf/tracer/Image.hpp"
#include "kerf/viewport/VulkanContext.hpp"
#include "kerf/viewport/VulkanError.hpp"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <cmath>
#include <memory>
#include <string>

namespace kerf {

struct Comparison {
    std::size_t pixels = 0, bothHit = 0, depthClose = 0, holes = 0, extra = 0, normalClose = 0, featureSame = 0;
};

inline Comparison compare(const TraceImage& gpu, const TraceImage& cpu, double depthTolerance)
{
    Comparison c;
    c.pixels = gpu.depth.size();
    for (std::size_t i = 0; i < c.pixels; ++i) {
        const bool g = gpu.hit(i), r = cpu.hit(i);
        if (r && !g) ++c.holes;
        if (g && !r) ++c.extra;
        if (!(g && r)) continue;
        ++c.bothHit;
        if (std::fabs(gpu.depth[i] - cpu.depth[i]) <= depthTolerance) ++c.depthClose;
        if (glm::dot(gpu.normal[i], cpu.normal[i]) > std::cos(glm::radians(2.0f))) ++c.normalClose;
        if (gpu.feature[i] == cpu.feature[i]) ++c.featureSame;
    }
    return c;
}

inline std::string allMessages(const vk::Context& c)
{
    std::string s;
    for (const auto& m : c.validationMessages()) s += m + "\n";
    return s;
}

class VulkanTracer : public ::testing::Test {
protected:
    static void SetUpTestSuite()
    {
        try {
            context = std::make_unique<vk::Context>(vk::ContextOptions{.validation = true, .preferCpu = false});
        } catch (const vk::VulkanError& e) {
            skipReason = e.what();
        }
    }
    static void TearDownTestSuite() { context.reset(); }
    void SetUp() override
    {
        if (!context) GTEST_SKIP() << "no Vulkan device: " << skipReason;
    }
    static inline std::unique_ptr<vk::Context> context;
    static inline std::string skipReason;
};


} // namespace kerf
