#include "kerf/voxelizer/DirtyRegion.hpp"

#include "kerf/document/NodeBounds.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace kerf {

namespace {

using BoundsMap = std::unordered_map<std::string, Aabb>;

// Differences of the node itself that change its field (name and colour do not).
bool fieldDiffers(const Node& a, const Node& b)
{
    return a.type != b.type || a.params != b.params || a.transform.translate != b.transform.translate ||
           a.transform.rotate != b.transform.rotate || a.visible != b.visible;
}

std::vector<std::string> childIds(const Node& n)
{
    std::vector<std::string> ids;
    for (const auto& c : n.children) ids.push_back(c.id);
    return ids;
}

// Whether the order of the children matters for the field: the first child
// of a difference is special, and smooth booleans fold left to right.
bool orderMatters(const Node& n)
{
    if (n.type == NodeType::Difference) return true;
    if (isBoolean(n.type)) return n.as<BooleanParams>().blend > 0.0;
    return false;
}

class Differ {
public:
    Differ(const BoundsMap& before, const BoundsMap& after, DirtyRegion& out) : before_(before), after_(after), out_(out) {}

    // The node's old and new reach (a node keeps its id across versions).
    void add(const std::string& id)
    {
        for (const BoundsMap* m : {&before_, &after_}) {
            const auto it = m->find(id);
            if (it != m->end() && !it->second.isEmpty()) out_.boxes.push_back(it->second);
        }
        out_.geometryChanged = true;
    }

    void diff(const Node& a, const Node& b)
    {
        if (fieldDiffers(a, b)) return add(a.id);
        if (!a.visible) return; // hidden on both sides: nothing below matters
        const auto ia = childIds(a), ib = childIds(b);
        if (ia != ib && orderMatters(a)) {
            // The surviving children's order matters: the whole node.
            std::vector<std::string> common;
            std::unordered_set<std::string> inB(ib.begin(), ib.end());
            for (const auto& id : ia)
                if (inB.count(id)) common.push_back(id);
            std::vector<std::string> commonB;
            std::unordered_set<std::string> inA(ia.begin(), ia.end());
            for (const auto& id : ib)
                if (inA.count(id)) commonB.push_back(id);
            const bool firstChanged = ia.empty() || ib.empty() || ia.front() != ib.front();
            if (common != commonB || (a.type == NodeType::Difference && firstChanged)) return add(a.id);
        }
        std::unordered_map<std::string, const Node*> bKids;
        for (const auto& c : b.children) bKids[c.id] = &c;
        std::unordered_set<std::string> seen;
        for (const auto& c : a.children) {
            seen.insert(c.id);
            const auto it = bKids.find(c.id);
            if (it == bKids.end())
                add(c.id); // removed
            else
                diff(c, *it->second);
        }
        for (const auto& c : b.children)
            if (!seen.count(c.id)) add(c.id); // added
    }

private:
    const BoundsMap& before_;
    const BoundsMap& after_;
    DirtyRegion& out_;
};

} // namespace

DirtyRegion dirtyRegion(const Document& before, const Document& after, double margin)
{
    DirtyRegion r;
    if (before.settings.bounds != after.settings.bounds || before.settings.featureSize != after.settings.featureSize ||
        before.root.id != after.root.id) {
        r.everything = r.geometryChanged = true;
        return r;
    }
    const BoundsMap b = worldBoundsOfNodes(before, margin), a = worldBoundsOfNodes(after, margin);
    Differ(b, a, r).diff(before.root, after.root);
    return r;
}

std::vector<long> tilesReached(const DirtyRegion& region, const GridLayout& layout)
{
    std::vector<long> tiles;
    if (region.everything) {
        tiles.resize(std::size_t(layout.tileCount()));
        for (long i = 0; i < layout.tileCount(); ++i) tiles[std::size_t(i)] = i;
        return tiles;
    }
    for (const Aabb& box : region.boxes) {
        const Aabb clipped = box.intersected(layout.bounds());
        if (clipped.isEmpty()) continue;
        const glm::ivec3 lo = glm::clamp(glm::ivec3(glm::floor((clipped.min - layout.origin) / layout.tileSize)),
                                         glm::ivec3(0), layout.dims - 1);
        const glm::ivec3 hi = glm::clamp(glm::ivec3(glm::floor((clipped.max - layout.origin) / layout.tileSize)),
                                         glm::ivec3(0), layout.dims - 1);
        for (int z = lo.z; z <= hi.z; ++z)
            for (int y = lo.y; y <= hi.y; ++y)
                for (int x = lo.x; x <= hi.x; ++x) tiles.push_back(layout.tileIndex({x, y, z}));
    }
    std::sort(tiles.begin(), tiles.end());
    tiles.erase(std::unique(tiles.begin(), tiles.end()), tiles.end());
    return tiles;
}

std::vector<long> tilesAnEditReaches(const Document& before, const Document& after, const GridLayout& layout)
{
    return tilesReached(dirtyRegion(before, after, 2.0 * std::sqrt(3.0) * layout.voxelSize), layout);
}

} // namespace kerf
