#include "kerf/viewport/TapeProbe.hpp"

#include "kerf/viewport/GpuBuffer.hpp"
#include "kerf/viewport/ShaderModules.hpp"
#include "kerf/viewport/VulkanError.hpp"

#include "tape_probe.comp.h"

#include <bit>
#include <cstring>

namespace kerf::vk {

namespace {

struct ProbePush {
    std::uint64_t tape, inputs, results;
    std::uint32_t count;
    std::uint32_t boxes;
};

constexpr std::uint32_t kGroup = 64; // tape_probe.comp's local size

} // namespace

TapeProbe::TapeProbe(const Context& ctx)
    : ctx_(ctx), compute_(makeComputePipeline(ctx.device(), kTapeProbeComp, sizeof(kTapeProbeComp), sizeof(ProbePush),
                                              "tape_probe.comp"))
{
}

std::vector<glm::vec4> TapeProbe::run(const std::vector<std::uint32_t>& tape, const std::vector<glm::vec4>& inputs,
                                      std::size_t count, bool boxes) const
{
    const GpuBuffer words = uploadBuffer(ctx_, tape.data(), tape.size() * sizeof(std::uint32_t),
                                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "probe tape");
    const GpuBuffer where = uploadBuffer(ctx_, inputs.data(), inputs.size() * sizeof(glm::vec4),
                                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "probe inputs");
    const GpuBuffer results(ctx_, 2 * count * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                            GpuBuffer::Kind::Readback, "probe results");
    const ProbePush push{words.address(), where.address(), results.address(), std::uint32_t(count), boxes ? 1u : 0u};
    ctx_.submitAndWait([&](VkCommandBuffer cb) {
        vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, compute_.pipeline);
        vkCmdPushConstants(cb, compute_.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
        vkCmdDispatch(cb, (std::uint32_t(count) + kGroup - 1) / kGroup, 1, 1);
        VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
        barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0,
                             nullptr, 0, nullptr);
    });
    std::vector<glm::vec4> raw(2 * count);
    std::memcpy(raw.data(), results.mapped(), raw.size() * sizeof(glm::vec4));
    return raw;
}

std::vector<TapeProbe::Result> TapeProbe::evaluate(const std::vector<std::uint32_t>& tape,
                                                   const std::vector<glm::vec3>& points) const
{
    if (tape.empty() || points.empty()) return {};
    std::vector<glm::vec4> at;
    at.reserve(points.size());
    for (const glm::vec3& p : points)
        at.emplace_back(p, 0.0f);
    const std::vector<glm::vec4> raw = run(tape, at, points.size(), false);
    std::vector<Result> out(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        out[i].value = raw[2 * i].x;
        out[i].feature = std::bit_cast<std::uint32_t>(raw[2 * i].y);
        out[i].dual = raw[2 * i + 1];
    }
    return out;
}

std::vector<glm::vec2> TapeProbe::enclose(const std::vector<std::uint32_t>& tape, const std::vector<Box>& boxes) const
{
    if (tape.empty() || boxes.empty()) return {};
    std::vector<glm::vec4> corners;
    corners.reserve(2 * boxes.size());
    for (const Box& b : boxes) {
        corners.emplace_back(b.lo, 0.0f);
        corners.emplace_back(b.hi, 0.0f);
    }
    const std::vector<glm::vec4> raw = run(tape, corners, boxes.size(), true);
    std::vector<glm::vec2> out(boxes.size());
    for (std::size_t i = 0; i < boxes.size(); ++i)
        out[i] = glm::vec2(raw[2 * i]);
    return out;
}

} // namespace kerf::vk
