#include "kerf/viewport/BrickAtlas.hpp"

#include "kerf/viewport/VulkanError.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

namespace kerf::vk {

BrickAtlas BrickAtlas::pack(const BrickLeaves& leaves, std::uint32_t maxImageDimension3D)
{
    BrickAtlas a;
    const std::size_t n = leaves.bricks.size();
    if (n == 0) return a;
    const std::uint32_t maxSlots = maxImageDimension3D / std::uint32_t(kBrickSamples);
    const std::uint32_t side = std::max<std::uint32_t>(
        1, std::min(maxSlots, std::uint32_t(std::ceil(std::cbrt(double(n))))));
    const std::size_t layers = (n + std::size_t(side) * side - 1) / (std::size_t(side) * side);
    if (maxSlots == 0 || layers > maxSlots)
        throw VulkanError(std::to_string(n) + " bricks do not fit one atlas of this device's largest 3D image (" +
                                std::to_string(maxImageDimension3D) + " texels a side)",
                          VK_ERROR_OUT_OF_DEVICE_MEMORY);
    a.slotCount = {side, side, std::uint32_t(layers)};
    a.texels = a.slotCount * std::uint32_t(kBrickSamples);
    const std::size_t texels = std::size_t(a.texels.x) * a.texels.y * a.texels.z;
    // Texels of the last layer's empty slots stay zero: never sampled.
    a.distance.assign(texels, 0);
    a.normal.assign(texels, 0);
    a.feature.assign(texels, 0);
    const std::size_t width = a.texels.x, height = a.texels.y;
    for (std::size_t b = 0; b < n; ++b) {
        const glm::uvec3 base = slotOf(b, side) * std::uint32_t(kBrickSamples);
        for (int z = 0; z < kBrickSamples; ++z)
            for (int y = 0; y < kBrickSamples; ++y) {
                const std::size_t to = base.x + width * ((base.y + std::size_t(y)) + height * (base.z + std::size_t(z)));
                const std::size_t from = BrickLeaves::sampleIndex(b, 0, y, z);
                std::memcpy(&a.distance[to], &leaves.distance[from], kBrickSamples * sizeof(std::int16_t));
                std::memcpy(&a.normal[to], &leaves.normal[from], kBrickSamples * sizeof(std::uint32_t));
                std::memcpy(&a.feature[to], &leaves.feature[from], kBrickSamples * sizeof(std::uint16_t));
            }
    }
    return a;
}

} // namespace kerf::vk
