#pragma once
// The part's tape simplified once per block of tiles (4 x 4 x 4 by default),
// so that each tile starts from a short tape instead of the whole part's:
// with 10,000 features, every tile interval-testing the full tape costs more
// than all the rest of the voxelization. A block's tape equals the full tape
// everywhere inside the block (simplification is exact there, the origin is
// unchanged), so tiles built from it are identical.

#include "kerf/evaluator/Tape.hpp"
#include "kerf/voxelizer/GridLayout.hpp"

#include <memory>
#include <mutex>
#include <vector>

namespace kerf {

class BlockTapes {
public:
    /// Keeps `tape` and `layout` by reference: both must outlive this.
    BlockTapes(const Tape& tape, const GridLayout& layout, int blockTiles = 4);

    /// The tape to build tile `tile` from. A block's tape is made by the
    /// first thread that asks for it (an edit that dirties a few tiles
    /// simplifies only their blocks); thread-safe.
    const Tape& forTile(const glm::ivec3& tile) const;

private:
    const Tape& tape_;
    const GridLayout& layout_;
    glm::ivec3 blocks_{0};
    int blockTiles_ = 4;
    mutable std::vector<Tape> tapes_;
    mutable std::unique_ptr<std::once_flag[]> made_;
};

} // namespace kerf
