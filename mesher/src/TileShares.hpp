#pragma once
// Every tile's share of the mesh, by mesher tile: the grid densely,
// tiles outside it (reached only if the flood fill ever left the grid, which
// the grid's one-voxel margin should prevent) in a map. Not thread-safe for
// insertion; lookups may run concurrently.

#include "Lattice.hpp"
#include "TileMesher.hpp"

#include <algorithm>
#include <map>
#include <memory>
#include <vector>

namespace kerf::mesher {

class TileShares {
public:
    explicit TileShares(const Lattice& lattice)
        : lattice_(lattice), grid_(std::size_t(lattice.dims.x * lattice.dims.y * lattice.dims.z))
    {
    }

    /// The slot of tile t (null until someone fills it).
    std::unique_ptr<TileShare>& slot(const I3& t)
    {
        if (lattice_.inGrid(t)) return grid_[gridIndex(t)];
        return outside_[tileKey(t)];
    }
    /// The slot of a tile in the grid; tasks working on distinct tiles may
    /// fill their slots concurrently.
    std::unique_ptr<TileShare>& gridSlot(const I3& t) { return grid_[gridIndex(t)]; }
    TileShare* find(const I3& t) const
    {
        if (lattice_.inGrid(t)) return grid_[gridIndex(t)].get();
        const auto it = outside_.find(tileKey(t));
        return it == outside_.end() ? nullptr : it->second.get();
    }
    /// Every share, in tile key order (z, then y, then x), so that merging
    /// does not depend on scheduling.
    std::vector<TileShare*> ordered() const
    {
        std::vector<std::pair<std::uint64_t, TileShare*>> all;
        for (const auto& s : grid_)
            if (s) all.emplace_back(tileKey(s->tile), s.get());
        for (const auto& [key, s] : outside_)
            if (s) all.emplace_back(key, s.get());
        std::sort(all.begin(), all.end());
        std::vector<TileShare*> out;
        for (const auto& [key, s] : all)
            out.push_back(s);
        return out;
    }
    void clear()
    {
        grid_.clear();
        outside_.clear();
    }

private:
    std::size_t gridIndex(const I3& t) const
    {
        return std::size_t(t.x + lattice_.dims.x * (t.y + lattice_.dims.y * t.z));
    }
    Lattice lattice_;
    std::vector<std::unique_ptr<TileShare>> grid_;
    std::map<std::uint64_t, std::unique_ptr<TileShare>> outside_;
};

} // namespace kerf::mesher
