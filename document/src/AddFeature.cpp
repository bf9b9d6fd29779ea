#include "kerf/document/AddFeature.hpp"

#include "kerf/document/DocumentEdits.hpp"
#include "kerf/document/NodeBounds.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

namespace kerf::edit {

namespace {

bool takesOneChild(NodeType type) { return maxChildren(type) == 1; }

// The placeholder's id for an operation: what addFeature names it.
std::string placeholderBase(const std::string& operationId) { return operationId + "-box"; }

// A new primitive rests on the ground grid (z = 0), centred on the Z axis,
// as a board laid on a bench: centred on the origin, half of it was under
// the grid, and a newcomer took it for a part sunk into the floor. A
// half-space has no bottom and stays as it is.
Node newPrimitive(NodeType type, std::string id)
{
    Node n = makeNode(type, std::move(id));
    const Aabb b = nodeBounds(n);
    if (!b.isEmpty() && b.isBounded()) n.transform.translate.z -= b.min.z;
    return n;
}

// A primitive added to a difference after its body is a tool: it is put
// where it cuts the body, centred on the body's top face (half of it above,
// so the cut shows from above), not on the grid at the origin, where a
// newcomer's first dowel hole into a board placed away from the origin cut
// nothing and seemed lost. The body: the difference's first visible child
// (what isSubtracted counts as the material); none, or one without bounds
// (a half-space), leaves the tool where newPrimitive put it.
void placeToolOnBody(const Node& difference, std::size_t index, Node& tool)
{
    const auto body = std::find_if(difference.children.begin(), difference.children.end(),
                                   [](const Node& c) { return c.visible; });
    if (body == difference.children.end() || std::size_t(body - difference.children.begin()) >= index) return;
    const Aabb b = nodeBounds(*body), t = nodeBounds(tool);
    if (b.isEmpty() || !b.isBounded() || t.isEmpty() || !t.isBounded()) return;
    const glm::dvec3 target(0.5 * (b.min.x + b.max.x), 0.5 * (b.min.y + b.max.y), b.max.z);
    const glm::dvec3 centre = 0.5 * (t.min + t.max);
    tool.transform.translate += target - centre;
}

} // namespace

std::string placeholderOf(const Document& doc, const std::string& operationId)
{
    const Node* op = doc.root.find(operationId);
    if (!op || !takesOneChild(op->type) || op->children.size() != 1) return {};
    const Node& child = op->children.front();
    if (child.type != NodeType::Box || child.id.rfind(placeholderBase(operationId), 0) != 0) return {};
    // Untouched: the box as addFeature gives it, or as it gave it before
    // new features rested on the grid (an edited one is the user's).
    for (Node pristine : {newPrimitive(NodeType::Box, child.id), makeNode(NodeType::Box, child.id)}) {
        pristine.children = child.children;
        if (child == pristine) return child.id;
    }
    return {};
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
            insertNode(edited, selected->id, 0, newPrimitive(type, id));
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
    // With nothing selected a new feature is new material beside the part:
    // at the end of a root intersection it cut the whole part down to
    // itself (a newcomer's Box emptied the side chair, whose root keeps it
    // above the floor plane), of a root difference it was a cut.
    const bool rootTakesItAsMaterial = edited.root.type != NodeType::Intersection &&
                                       edited.root.type != NodeType::Difference;
    if (!target || (target == &edited.root && (maxChildren(edited.root.type) <= edited.root.children.size() ||
                                               (!selected && !rootTakesItAsMaterial))))
        parent = wrapNodes(edited, {edited.root.id}, makeNode(NodeType::Union, uniqueId(edited, "part")));
    Node n = isPrimitive(type) ? newPrimitive(type, id) : makeNode(type, id);
    if (!isPrimitive(type)) n.children.push_back(newPrimitive(NodeType::Box, uniqueId(edited, placeholderBase(id))));
    if (const Node* into = edited.root.find(parent); isPrimitive(type) && into && into->type == NodeType::Difference)
        placeToolOnBody(*into, std::min(index, into->children.size()), n);
    insertNode(edited, parent, index, std::move(n));
    doc = std::move(edited);
    return id;
}

namespace {
constexpr const char* kPositionZ = "transform.translate[2]";
} // namespace

std::optional<std::string> restingExpression(const Node& n)
{
    if (n.transform.rotate != glm::dvec3(0.0)) return std::nullopt;
    // The field that sets the height, and the height over the centre.
    const char* field = nullptr;
    bool half = true;
    switch (n.type) {
    case NodeType::Box: field = "size[2]"; break;
    case NodeType::Cylinder:
    case NodeType::Cone:
    case NodeType::Extrude: field = "height"; break;
    case NodeType::Sphere: field = "radius", half = false; break;
    default: return std::nullopt;
    }
    const auto it = n.expressions.find(field);
    if (it == n.expressions.end()) return std::nullopt;
    const std::string& e = it->second;
    if (!half) return e;
    const bool name = !e.empty() && std::all_of(e.begin(), e.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
    }) && !std::isdigit(static_cast<unsigned char>(e[0]));
    return (name ? e : "(" + e + ")") + "/2";
}

namespace {

// Resting: its bottom on the grid, to the rounding a typed position leaves.
bool rests(const Aabb& b) { return std::abs(b.min.z) <= 1e-9 * std::max(1.0, b.max.z - b.min.z); }

// Turned where it stands (only its rotation changed): a primitive that
// rested on the grid lies on it again, by its bounds in its parent's frame.
// A leg turned to lie along the bench hung 180 mm above it.
void keepRestingTurned(const Node& before, Node& after)
{
    Node unturned = after;
    unturned.transform.rotate = before.transform.rotate;
    if (!(unturned == before)) return; // something else changed too: the edit's own
    const auto placedBy = before.expressions.find(kPositionZ);
    const bool ours = placedBy != before.expressions.end() && placedBy->second == restingExpression(before);
    if (placedBy != before.expressions.end() && !ours) return;
    const Aabb was = nodeBounds(before), now = nodeBounds(after);
    if (was.isEmpty() || !was.isBounded() || now.isEmpty() || !now.isBounded() || !rests(was)) return;
    after.transform.translate.z -= now.min.z;
    if (const auto e = restingExpression(after))
        after.expressions[kPositionZ] = *e;
    else
        after.expressions.erase(kPositionZ);
}

} // namespace

void keepResting(const Node& before, Node& after)
{
    if (!isPrimitive(before.type) || before.type != after.type) return;
    if (before.transform.translate == after.transform.translate &&
        before.transform.rotate != after.transform.rotate) {
        keepRestingTurned(before, after);
        return;
    }
    if (!(before.transform == after.transform) || before.transform.rotate != glm::dvec3(0.0)) return;
    // An expression placing it is the user's rule, not ours, unless it is
    // the one this rule wrote for the height it had (then it follows the new one).
    const auto placedBy = before.expressions.find(kPositionZ);
    const bool ours = placedBy != before.expressions.end() && placedBy->second == restingExpression(before);
    if (after.expressions.count(kPositionZ) && !ours) return;
    const Aabb was = nodeBounds(before);
    const Aabb now = nodeBounds(after);
    if (was.isEmpty() || !was.isBounded() || now.isEmpty() || !now.isBounded()) return;
    if (!rests(was)) return;
    after.transform.translate.z -= now.min.z;
    // A height set by an expression (Size Z "=thickness") places it by one
    // too, so that it stays on the grid when the parameter changes: a
    // newcomer's panel stayed centred at 9 mm when thickness went from 18
    // to 25, and every cut measured from its top came out shallower.
    if (const auto e = restingExpression(after))
        after.expressions[kPositionZ] = *e;
    else
        after.expressions.erase(kPositionZ);
}

} // namespace kerf::edit
