#include "kerf/document/AddFeature.hpp"

#include "kerf/document/DocumentEdits.hpp"

#include <stdexcept>

namespace kerf::edit {

namespace {

bool takesOneChild(NodeType type) { return maxChildren(type) == 1; }

// The placeholder's id for an operation: what addFeature names it.
std::string placeholderBase(const std::string& operationId) { return operationId + "-box"; }

} // namespace

std::string placeholderOf(const Document& doc, const std::string& operationId)
{
    const Node* op = doc.root.find(operationId);
    if (!op || !takesOneChild(op->type) || op->children.size() != 1) return {};
    const Node& child = op->children.front();
    if (child.type != NodeType::Box || child.id.rfind(placeholderBase(operationId), 0) != 0) return {};
    // Untouched: the box as makeNode gives it (an edited one is the user's).
    Node pristine = makeNode(NodeType::Box, child.id);
    pristine.children = child.children;
    return child == pristine ? child.id : std::string();
}

std::string addFeature(Document& doc, NodeType type, const std::vector<std::string>& selection)
{
    const std::string id = uniqueId(doc, std::string(nodeTypeName(type)));
    const Node* selected = selection.size() == 1 ? doc.root.find(selection.front()) : nullptr;

    // An operation over the one selected feature.
    if (!isPrimitive(type) && selected && selected != &doc.root) {
        wrapNodes(doc, {selected->id}, makeNode(type, id));
        return id;
    }
    // A primitive in place of a placeholder.
    if (isPrimitive(type) && selected) {
        if (const std::string box = placeholderOf(doc, selected->id); !box.empty()) {
            Document edited = doc;
            removeNode(edited, box);
            insertNode(edited, selected->id, 0, makeNode(type, id));
            doc = std::move(edited);
            return id;
        }
    }

    std::string parent = doc.root.id;
    std::size_t index = std::size_t(-1);
    if (selected) {
        if (isBoolean(selected->type)) {
            parent = selected->id;
        } else if (selected->children.size() < maxChildren(selected->type)) {
            parent = selected->id; // an empty offset, shell, array or mirror takes it
        } else if (auto loc = locate(doc, selected->id)) {
            parent = loc->parentId;
            index = loc->index + 1;
        }
    }
    Document edited = doc;
    const Node* target = edited.root.find(parent);
    if (!target || (target == &edited.root && maxChildren(edited.root.type) <= edited.root.children.size()))
        parent = wrapNodes(edited, {edited.root.id}, makeNode(NodeType::Union, uniqueId(edited, "part")));
    Node n = makeNode(type, id);
    if (!isPrimitive(type)) n.children.push_back(makeNode(NodeType::Box, uniqueId(edited, placeholderBase(id))));
    insertNode(edited, parent, index, std::move(n));
    doc = std::move(edited);
    return id;
}

} // namespace kerf::edit
