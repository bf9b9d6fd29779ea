#include "kerf/document/NodePlacement.hpp"

#include "kerf/document/NodeBounds.hpp"
#include "kerf/document/PrintableText.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace kerf::edit {

namespace {

bool findPath(const Node& n, std::string_view id, std::vector<const Node*>& path)
{
    path.push_back(&n);
    if (n.id == id) return true;
    for (const Node& c : n.children)
        if (findPath(c, id, path)) return true;
    path.pop_back();
    return false;
}

std::vector<const Node*> existingPath(const Document& doc, std::string_view id)
{
    std::vector<const Node*> path = pathTo(doc, id);
    if (path.empty()) throw std::invalid_argument("no node '" + std::string(id) + "'");
    return path;
}

} // namespace

std::vector<const Node*> pathTo(const Document& doc, std::string_view id)
{
    std::vector<const Node*> path;
    if (!findPath(doc.root, id, path)) path.clear();
    return path;
}

Affine parentFrame(const Document& doc, std::string_view id)
{
    const std::vector<const Node*> path = existingPath(doc, id);
    Affine frame;
    for (std::size_t i = 0; i + 1 < path.size(); ++i) frame = frame * Affine::fromTransform(path[i]->transform);
    return frame;
}

Aabb firstInstanceBounds(const Document& doc, std::string_view id)
{
    const std::vector<const Node*> path = existingPath(doc, id);
    for (const Node* n : path)
        if (!n->visible) return Aabb::empty();
    return parentFrame(doc, id).apply(nodeBounds(*path.back()));
}

void moveNodeInWorld(Document& doc, std::string_view id, const glm::dvec3& worldDelta)
{
    const Affine frame = parentFrame(doc, id);
    Node* n = doc.root.find(id);
    // Ancestors are rotations and reflections: the inverse is the transpose.
    const glm::dvec3 local = frame.inverseOrthogonal().applyLinear(worldDelta);
    n->transform.translate += local;
    // A moved coordinate is the number the move gave, no longer its expression's.
    for (int a = 0; a < 3; ++a)
        if (local[a] != 0.0) n->expressions.erase("transform.translate[" + std::to_string(a) + "]");
}

glm::dvec3 moveKeepingExpressions(const Document& doc, std::string_view id, const glm::dvec3& worldDelta,
                                  std::vector<int>* held)
{
    const Affine frame = parentFrame(doc, id);
    const Node* n = doc.root.find(id);
    glm::dvec3 local = frame.inverseOrthogonal().applyLinear(worldDelta);
    // A change below a nanometre is a rounding of the frame's rotation, not a move.
    constexpr double kNoMove = 1e-9;
    for (int a = 0; a < 3; ++a)
        if (n->expressions.count("transform.translate[" + std::to_string(a) + "]")) {
            if (held && std::abs(local[a]) > kNoMove) held->push_back(a);
            local[a] = 0.0;
        }
    return frame.applyLinear(local);
}

std::string describeFeatureAlone(const Document& doc, std::string_view id)
{
    const std::vector<const Node*> path = existingPath(doc, id);
    const Node& n = *path.back();
    std::string s = n.name.value_or(n.id) + " alone";
    bool mirror = false, array = false;
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
        mirror = mirror || path[i]->type == NodeType::Mirror;
        array = array || path[i]->type == NodeType::Array;
    }
    if (mirror || array)
        s += std::string(", with every copy of the ") + (mirror && array ? "mirror and array" : mirror ? "mirror" : "array") +
             " above it";
    if (isSubtracted(doc, id)) s += ", as a solid: it is a cutter (the part has its shape cut away)";
    // The body of a difference alone has none of its cuts: a newcomer picked
    // the board (the cut list's name for it) and got a plain box for the CNC.
    for (std::size_t i = path.size() - 1; i-- > 0;) {
        const Node& parent = *path[i];
        if (parent.type != NodeType::Difference || parent.children.size() < 2 || &parent.children.front() != path[i + 1])
            continue;
        std::string tools;
        std::size_t named = 0;
        for (std::size_t k = 1; k < parent.children.size() && named < 3; ++k, ++named)
            tools += (tools.empty() ? "" : ", ") + parent.children[k].name.value_or(parent.children[k].id);
        if (parent.children.size() - 1 > named) tools += ", ...";
        const std::string whole = parent.name.value_or(parent.id);
        s += ", without the cuts of " + whole + " (" + tools + "): select " + whole + " for the " +
             n.name.value_or(n.id) + " as cut";
        break;
    }
    return s;
}

std::string featureNamed(const Document& doc, std::string_view idOrName)
{
    if (doc.root.find(idOrName)) return std::string(idOrName);
    std::vector<const Node*> named;
    std::vector<const Node*> stack{&doc.root};
    while (!stack.empty()) {
        const Node* n = stack.back();
        stack.pop_back();
        if (n->name && *n->name == idOrName) named.push_back(n);
        for (auto c = n->children.rbegin(); c != n->children.rend(); ++c) stack.push_back(&*c); // tree order
    }
    if (named.size() == 1) return named.front()->id;
    // Printable: the name comes from a command line or a field (an escape
    // sequence or a newline typed there reached the terminal as it was).
    if (named.empty()) throw std::invalid_argument("no feature has the id or the name '" + printable(idOrName) + "'");
    std::string ids;
    for (const Node* n : named) ids += (ids.empty() ? "" : ", ") + n->id;
    throw std::invalid_argument(std::to_string(named.size()) + " features are named '" + printable(idOrName) +
                                "': give one of their ids (" + ids + ")");
}

bool isSubtracted(const Document& doc, std::string_view id)
{
    const std::vector<const Node*> path = pathTo(doc, id);
    bool subtracted = false;
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
        const Node& parent = *path[i];
        if (parent.type != NodeType::Difference) continue;
        // The base is the first visible child; every later one is a tool.
        for (const Node& c : parent.children) {
            if (!c.visible) continue;
            if (&c != path[i + 1]) subtracted = !subtracted;
            break;
        }
    }
    return subtracted;
}

Document documentOfNodeAlone(const Document& doc, std::string_view id)
{
    const std::vector<const Node*> path = existingPath(doc, id);
    Document alone = doc;
    // Rebuilt from the node upwards: each ancestor keeps only the path's child.
    Node current = *path.back();
    current.visible = true;
    for (std::size_t i = path.size() - 1; i-- > 0;) {
        const Node& ancestor = *path[i];
        Node wrapper;
        if (ancestor.type == NodeType::Array || ancestor.type == NodeType::Mirror) {
            wrapper = ancestor;
            wrapper.children.clear();
        } else {
            wrapper.id = ancestor.id;
            wrapper.type = NodeType::Union;
            wrapper.transform = ancestor.transform;
        }
        wrapper.visible = true;
        wrapper.children.push_back(std::move(current));
        current = std::move(wrapper);
    }
    alone.root = std::move(current);
    return alone;
}

} // namespace kerf::edit
