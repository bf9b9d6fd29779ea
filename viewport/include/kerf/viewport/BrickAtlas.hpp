#pragma once
// The brick leaves' samples laid out as the brick renderer's three 3D
// atlases, in host memory: slots of kBrickSamples texels a side, brick b in
// slot (b % side, (b / side) % side, b / side^2), each atlas in the image's
// own texel order (x fastest, then y, then z). Packing is plain host work,
// done on the thread that made the bricks, so that a frame only copies
// rows of it into the staging ring (BrickRenderer::recordUpload).
//
// A "row" is one line of texels along x, across every atlas at once: the
// unit the upload is cut into (width texels of each atlas, 8 bytes a texel
// in all).

#include "kerf/voxelizer/BrickLeaves.hpp"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace kerf::vk {

struct BrickAtlas {
    glm::uvec3 slotCount{0}; // bricks along each axis (the last layer may be partly empty)
    glm::uvec3 texels{0}; // slotCount * kBrickSamples
    std::vector<std::int16_t> distance;
    std::vector<std::uint32_t> normal;
    std::vector<std::uint16_t> feature;

    /// Bytes of one texel in the three atlases together.
    static constexpr std::size_t kTexelBytes = sizeof(std::int16_t) + sizeof(std::uint32_t) + sizeof(std::uint16_t);

    /// Lays `leaves` out in atlases as near a cube as `maxImageDimension3D`
    /// (the device's largest 3D image, in texels) allows. Throws
    /// VulkanError (out of device memory) when they do not fit one such atlas.
    static BrickAtlas pack(const BrickLeaves& leaves, std::uint32_t maxImageDimension3D);

    std::size_t rows() const { return std::size_t(texels.y) * texels.z; }
    std::size_t rowBytes() const { return std::size_t(texels.x) * kTexelBytes; }
    /// The slot of brick `b` in an atlas of `side` slots along x and y, in
    /// slots (the renderer's instances address the same slots).
    static glm::uvec3 slotOf(std::size_t b, std::uint32_t side)
    {
        const std::size_t s = side;
        return {std::uint32_t(b % s), std::uint32_t((b / s) % s), std::uint32_t(b / (s * s))};
    }
};

} // namespace kerf::vk
