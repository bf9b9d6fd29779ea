#include "kerf/voxelizer/BlockTapes.hpp"

#include "kerf/evaluator/IntervalEvaluator.hpp"
#include "kerf/voxelizer/TileBuilder.hpp"

#include <glm/glm.hpp>

namespace kerf {

BlockTapes::BlockTapes(const Tape& tape, const GridLayout& layout, int blockTiles)
    : tape_(tape), layout_(layout), blockTiles_(blockTiles)
{
    blocks_ = (layout.dims + blockTiles - 1) / blockTiles;
    const std::size_t count = std::size_t(blocks_.x) * std::size_t(blocks_.y) * std::size_t(blocks_.z);
    tapes_.resize(count);
    made_ = std::make_unique<std::once_flag[]>(count);
}

const Tape& BlockTapes::forTile(const glm::ivec3& tile) const
{
    const glm::ivec3 b = tile / blockTiles_;
    const std::size_t i = std::size_t(b.x + long(blocks_.x) * (b.y + long(blocks_.y) * b.z));
    std::call_once(made_[i], [&] {
        const glm::ivec3 first = b * blockTiles_;
        const glm::ivec3 last = glm::min(first + blockTiles_, layout_.dims) - 1;
        IntervalEvaluator evaluator;
        // Exact over the block grown by the hair its tiles' boxes grow by.
        const Aabb block{layout_.tileBox(first).min, layout_.tileBox(last).max};
        evaluator.simplify(tape_, block.grown(layout_.tileSize * kIntervalBoxHair), tapes_[i]);
    });
    return tapes_[i];
}

} // namespace kerf
