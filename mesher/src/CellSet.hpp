#pragma once
// The set of cells a tile has examined, as one bit per cell in 8 x 8 x 8
// bricks allocated where the surface passes: about a bit and a half per
// surface cell, against 13 to 26 bytes in a hash set. Keys are tile-local
// (Lattice.hpp). Not thread-safe; one owner.

#include "FlatHash.hpp"
#include "Lattice.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace kerf::mesher {

class CellSet {
public:
    /// Adds a cell; true when it was not there.
    bool insert(const I3& local)
    {
        auto [index, added] = bricks_.insert(brickKey(local), std::uint32_t(bits_.size()));
        if (added) bits_.emplace_back();
        std::uint64_t& word = bits_[*index][std::size_t(bitIndex(local) >> 6)];
        const std::uint64_t bit = std::uint64_t(1) << (bitIndex(local) & 63);
        if (word & bit) return false;
        word |= bit;
        return true;
    }
    bool contains(const I3& local) const
    {
        const std::uint32_t* index = bricks_.find(brickKey(local));
        return index && (bits_[*index][std::size_t(bitIndex(local) >> 6)] >> (bitIndex(local) & 63) & 1);
    }
    void release()
    {
        bricks_.release();
        std::vector<std::array<std::uint64_t, 8>>().swap(bits_);
    }
    std::size_t bytes() const { return bricks_.bytes() + bits_.capacity() * sizeof(bits_[0]); }

private:
    static std::uint64_t brickKey(const I3& l) { return localKey({l.x >> 3, l.y >> 3, l.z >> 3}); }
    static int bitIndex(const I3& l) { return int((l.x & 7) | (l.y & 7) << 3 | (l.z & 7) << 6); }

    FlatMap<std::uint32_t> bricks_;
    std::vector<std::array<std::uint64_t, 8>> bits_;
};

} // namespace kerf::mesher
