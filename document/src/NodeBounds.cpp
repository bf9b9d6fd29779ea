#include "kerf/document/NodeBounds.hpp"

#include "kerf/document/DocumentEdits.hpp"
#include "kerf/document/NodeTypes.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <functional>

namespace kerf {

namespace {

std::vector<const Node*> visibleChildren(const Node& n)
{
    std::vector<const Node*> out;
    for (const auto& c : n.children)
        if (c.visible) out.push_back(&c);
    return out;
}

// Bounds of a primitive's sublevel set {f < margin} in its own frame. Every
// primitive's field is an exact distance, so the set lies within `margin` of
// the solid's box (and inside it when margin <= 0).
Aabb primitiveLocalBounds(const Node& n, double margin)
{
    return nodeTypeSpec(n.type).localBounds(n.params).grown(std::max(margin, 0.0));
}

// Bounds of {f < margin} in the node's own frame (its transform not applied).
Aabb localBounds(const Node& n, double margin);

Aabb boundsInParent(const Node& n, double margin)
{
    if (!n.visible) return Aabb::empty();
    return Affine::fromTransform(n.transform).apply(localBounds(n, margin));
}

Aabb arrayOffsets(const ArrayParams& p)
{
    Aabb offsets{glm::dvec3(0.0), glm::dvec3(0.0)};
    for (int i = 0; i < 3; ++i) {
        const double far = static_cast<double>(p.count[static_cast<std::size_t>(i)] - 1) * p.step[i];
        offsets.min[i] = std::min(0.0, far);
        offsets.max[i] = std::max(0.0, far);
    }
    return offsets;
}

Aabb localBounds(const Node& n, double margin)
{
    if (isPrimitive(n.type)) return primitiveLocalBounds(n, margin);
    const auto kids = visibleChildren(n);
    if (kids.empty()) return Aabb::empty();
    switch (n.type) {
    case NodeType::Union: {
        // smin(a, b) >= min(a, b) - k/4: the blend adds material at most k/4 past
        // where a child's field is below the margin.
        const double k = n.as<BooleanParams>().blend;
        Aabb box;
        for (const Node* c : kids) box = box.merged(boundsInParent(*c, margin + 0.25 * k));
        return box;
    }
    case NodeType::Intersection: {
        // smax >= max: below the margin only where every child is.
        Aabb box = Aabb::infinite();
        for (const Node* c : kids) box = box.intersected(boundsInParent(*c, margin));
        return box;
    }
    case NodeType::Difference: return boundsInParent(*kids.front(), margin);
    case NodeType::Offset: return boundsInParent(*kids.front(), margin + n.as<OffsetParams>().distance);
    case NodeType::Shell: return boundsInParent(*kids.front(), margin);
    case NodeType::Array: return boundsInParent(*kids.front(), margin).swept(arrayOffsets(n.as<ArrayParams>()));
    case NodeType::Mirror: {
        const auto& p = n.as<MirrorParams>();
        const Aabb child = boundsInParent(*kids.front(), margin);
        return child.merged(Affine::reflection(p.normal, p.offset).apply(child));
    }
    default: return Aabb::empty();
    }
}

// Maps a box in some node's frame to world bounds over every instance of that
// node: a chain of stages from the node outwards (placements, array sweeps,
// mirror images).
using ToWorld = std::function<Aabb(const Aabb&)>;

void collectWorldBounds(const Node& n, const ToWorld& parentToWorld, double margin,
                        std::unordered_map<std::string, Aabb>& out)
{
    if (!n.visible) return;
    out[n.id] = parentToWorld(boundsInParent(n, margin));
    const Affine placement = Affine::fromTransform(n.transform);
    ToWorld selfToWorld;
    switch (n.type) {
    case NodeType::Array: {
        const Aabb offsets = arrayOffsets(n.as<ArrayParams>());
        selfToWorld = [=](const Aabb& b) { return parentToWorld(placement.apply(b.swept(offsets))); };
        break;
    }
    case NodeType::Mirror: {
        const auto& p = n.as<MirrorParams>();
        const Affine reflect = Affine::reflection(p.normal, p.offset);
        selfToWorld = [=](const Aabb& b) { return parentToWorld(placement.apply(b.merged(reflect.apply(b)))); };
        break;
    }
    default: selfToWorld = [=](const Aabb& b) { return parentToWorld(placement.apply(b)); }; break;
    }
    // Margins reaching children: the same rules as localBounds.
    double childMargin = margin;
    if (n.type == NodeType::Union) childMargin += 0.25 * n.as<BooleanParams>().blend;
    if (n.type == NodeType::Offset) childMargin += n.as<OffsetParams>().distance;
    for (const auto& c : n.children) collectWorldBounds(c, selfToWorld, childMargin, out);
}

} // namespace

Aabb nodeBounds(const Node& node, double margin) { return boundsInParent(node, margin); }

std::unordered_map<std::string, Aabb> worldBoundsOfNodes(const Document& doc, double margin)
{
    std::unordered_map<std::string, Aabb> out;
    collectWorldBounds(doc.root, [](const Aabb& b) { return b; }, margin, out);
    return out;
}

Aabb partBounds(const Document& doc)
{
    Aabb box = nodeBounds(doc.root);
    if (doc.settings.bounds) box = box.intersected(Aabb{doc.settings.bounds->min, doc.settings.bounds->max});
    return box;
}

std::vector<std::string> toolsCuttingNothing(const Document& doc)
{
    const std::unordered_map<std::string, Aabb> bounds = worldBoundsOfNodes(doc);
    const auto boundsOf = [&](const Node& n) {
        const auto it = bounds.find(n.id);
        return it == bounds.end() ? Aabb{} : it->second;
    };
    std::vector<std::string> idle;
    const auto walk = [&](const auto& self, const Node& n) -> void {
        const bool blended = n.type == NodeType::Difference && n.as<BooleanParams>().blend > 0.0;
        if (n.type == NodeType::Difference && n.visible && n.children.size() > 1 && !blended) {
            const Aabb base = boundsOf(n.children.front());
            for (std::size_t i = 1; i < n.children.size(); ++i) {
                const Aabb tool = boundsOf(n.children[i]);
                if (!base.isEmpty() && !tool.isEmpty() && !tool.overlaps(base)) idle.push_back(n.children[i].id);
            }
        }
        for (const Node& c : n.children) self(self, c);
    };
    walk(walk, doc.root);
    return idle;
}

std::string describeToolsCuttingNothing(const Document& doc)
{
    const std::vector<std::string> idle = toolsCuttingNothing(doc);
    if (idle.empty()) return {};
    const auto named = [](const Node& n) {
        return n.name ? *n.name + " ('" + n.id + "')" : "the " + std::string(nodeTypeName(n.type)) + " '" + n.id + "'";
    };
    constexpr std::size_t kNamed = 3;
    std::string s;
    for (std::size_t i = 0; i < idle.size() && i < kNamed; ++i) {
        const auto location = edit::locate(doc, idle[i]);
        const Node* tool = doc.root.find(idle[i]);
        const Node* difference = location ? doc.root.find(location->parentId) : nullptr;
        if (!tool || !difference) continue;
        if (!s.empty()) s += "; ";
        s += named(*tool) + " cuts nothing: it lies clear of " + named(difference->children.front());
    }
    if (idle.size() > kNamed) s += "; and " + std::to_string(idle.size() - kNamed) + " more";
    return s;
}

} // namespace kerf
