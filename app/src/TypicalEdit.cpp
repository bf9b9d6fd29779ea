#include "kerf/app/TypicalEdit.hpp"

#include "kerf/document/NodeBounds.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <stdexcept>

namespace kerf {

namespace {

void visit(const Node& node, std::uint64_t copies, std::optional<TypicalEdit>& best)
{
    if (!node.visible) return;
    if (isPrimitive(node.type)) {
        if (node.type == NodeType::Halfspace) return;
        const Aabb box = nodeBounds(node);
        if (box.isEmpty() || !box.isBounded()) return;
        const double diagonal = glm::length(box.size());
        if (!best || diagonal < best->diagonalMm) best = TypicalEdit{node.id, node.type, copies, diagonal};
        return;
    }
    std::uint64_t multiplier = 1;
    if (node.type == NodeType::Mirror) multiplier = 2;
    if (node.type == NodeType::Array) {
        for (std::int64_t c : node.as<ArrayParams>().count)
            multiplier *= std::uint64_t(std::max<std::int64_t>(c, 1));
    }
    for (const Node& child : node.children)
        visit(child, copies * multiplier, best);
}

} // namespace

std::optional<TypicalEdit> chooseTypicalEdit(const Document& doc)
{
    std::optional<TypicalEdit> best;
    visit(doc.root, 1, best);
    return best;
}

Document applyTypicalEdit(Document doc, const TypicalEdit& edit, double offsetMm)
{
    Node* node = doc.root.find(edit.nodeId);
    if (!node) throw std::invalid_argument("typical edit: the document has no node '" + edit.nodeId + "'");
    node->transform.translate.x += offsetMm;
    return doc;
}

} // namespace kerf
