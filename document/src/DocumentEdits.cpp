#include "kerf/document/DocumentEdits.hpp"

#include "FieldPath.hpp"
#include "kerf/document/Expression.hpp"
#include "kerf/document/NodeTypes.hpp"

#include <cctype>

#include <algorithm>
#include <map>
#include <limits>
#include <stdexcept>
#include <unordered_set>

namespace kerf::edit {

namespace {

[[noreturn]] void refuse(const std::string& why) { throw std::invalid_argument(why); }

std::string inQuotes(std::string_view id) { return "'" + std::string(id) + "'"; }

// The parent of the node with this id, and the node's index; null when the
// id is the root's or unknown.
Node* parentOf(Node& tree, std::string_view id, std::size_t& index)
{
    for (std::size_t i = 0; i < tree.children.size(); ++i)
        if (tree.children[i].id == id) {
            index = i;
            return &tree;
        }
    for (auto& c : tree.children)
        if (Node* p = parentOf(c, id, index)) return p;
    return nullptr;
}

Node* parentOf(Document& doc, std::string_view id, std::size_t& index) { return parentOf(doc.root, id, index); }

void collectIds(const Node& n, std::unordered_set<std::string>& ids)
{
    ids.insert(n.id);
    for (const auto& c : n.children) collectIds(c, ids);
}

Node& requireNode(Document& doc, std::string_view id)
{
    Node* n = doc.root.find(id);
    if (!n) refuse("there is no node " + inQuotes(id));
    return *n;
}

void requireRoom(const Node& parent, std::size_t extra)
{
    const std::size_t limit = maxChildren(parent.type);
    if (limit == 0) refuse("a " + std::string(nodeTypeName(parent.type)) + " has no children");
    if (parent.children.size() + extra > limit)
        // Named as the tree shows it: by its name where it has one.
        refuse("a " + std::string(nodeTypeName(parent.type)) + " takes exactly 1 child, and " +
               inQuotes(parent.name.value_or(parent.id)) + " has one already");
}

void renumber(const Document& doc, Node& n, std::unordered_set<std::string>& taken)
{
    // "leg-3" copies as "leg-4", "board" as "board-2".
    std::string base = n.id;
    int k = 2;
    const auto dash = base.find_last_of('-');
    if (dash != std::string::npos && dash + 1 < base.size() && base.size() - dash <= 9 &&
        std::all_of(base.begin() + long(dash) + 1, base.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        k = std::stoi(base.substr(dash + 1)) + 1;
        base.resize(dash);
    }
    std::string id = base + "-" + std::to_string(k);
    while (taken.count(id) || doc.root.find(id)) id = base + "-" + std::to_string(++k);
    taken.insert(id);
    n.id = id;
    for (auto& c : n.children) renumber(doc, c, taken);
}

} // namespace

std::optional<NodeLocation> locate(const Document& doc, std::string_view id)
{
    std::size_t index = 0;
    const Node* parent = parentOf(const_cast<Document&>(doc), id, index);
    if (!parent) return std::nullopt;
    return NodeLocation{parent->id, index};
}

std::size_t maxChildren(NodeType type)
{
    if (isPrimitive(type)) return 0;
    if (isBoolean(type)) return std::numeric_limits<std::size_t>::max();
    return 1;
}

std::string uniqueId(const Document& doc, std::string_view base)
{
    std::string id(base.empty() ? "node" : base);
    const std::string stem = id;
    for (int k = 2; doc.root.find(id); ++k) id = stem + "-" + std::to_string(k);
    return id;
}

void insertNode(Document& doc, std::string_view parentId, std::size_t index, Node node)
{
    Node& parent = requireNode(doc, parentId);
    requireRoom(parent, 1);
    std::unordered_set<std::string> ids;
    collectIds(node, ids);
    if (ids.size() != node.count()) refuse("the inserted nodes repeat an id");
    for (const auto& id : ids)
        if (doc.root.find(id)) refuse("a node " + inQuotes(id) + " exists already");
    index = std::min(index, parent.children.size());
    parent.children.insert(parent.children.begin() + long(index), std::move(node));
}

Node removeNode(Document& doc, std::string_view id)
{
    if (doc.root.id == id) refuse("the root cannot be removed");
    std::size_t index = 0;
    Node* parent = parentOf(doc, id, index);
    if (!parent) refuse("there is no node " + inQuotes(id));
    Node removed = std::move(parent->children[index]);
    parent->children.erase(parent->children.begin() + long(index));
    return removed;
}

void moveNode(Document& doc, std::string_view id, std::string_view newParentId, std::size_t index)
{
    if (doc.root.id == id) refuse("the root cannot be moved");
    const Node* node = doc.root.find(id);
    if (!node) refuse("there is no node " + inQuotes(id));
    if (node->find(newParentId)) refuse(inQuotes(id) + " cannot move into its own subtree");
    Node& newParent = requireNode(doc, newParentId);
    std::size_t from = 0;
    Node* oldParent = parentOf(doc, id, from);
    const bool sameParent = oldParent == &newParent;
    if (!sameParent) requireRoom(newParent, 1);
    index = std::min(index, newParent.children.size());
    // Removing first shifts later siblings of the same parent down by one.
    if (sameParent && index > from) --index;
    Node moving = std::move(oldParent->children[from]);
    oldParent->children.erase(oldParent->children.begin() + long(from));
    // Node pointers into the tree may have moved with the erase: look again.
    Node& target = *doc.root.find(newParentId);
    target.children.insert(target.children.begin() + long(std::min(index, target.children.size())),
                           std::move(moving));
}

std::string duplicateNode(Document& doc, std::string_view id)
{
    if (doc.root.id == id) refuse("the root cannot be duplicated");
    std::size_t index = 0;
    Node* parent = parentOf(doc, id, index);
    if (!parent) refuse("there is no node " + inQuotes(id));
    requireRoom(*parent, 1);
    Node copy = parent->children[index];
    std::unordered_set<std::string> taken;
    renumber(doc, copy, taken);
    if (copy.name) *copy.name += " copy";
    const std::string copyId = copy.id;
    parent->children.insert(parent->children.begin() + long(index) + 1, std::move(copy));
    return copyId;
}

std::string wrapNodes(Document& doc, const std::vector<std::string>& ids, Node op)
{
    if (ids.empty()) refuse("nothing to group");
    if (isPrimitive(op.type)) refuse("nodes can only be grouped under an operation");
    if (ids.size() > maxChildren(op.type))
        refuse("a " + std::string(nodeTypeName(op.type)) + " takes exactly 1 child, not " +
               std::to_string(ids.size()));
    if (doc.root.find(op.id)) refuse("a node " + inQuotes(op.id) + " exists already");
    op.children.clear();
    const std::string opId = op.id;
    if (ids.size() == 1 && ids.front() == doc.root.id) {
        op.children.push_back(std::move(doc.root));
        doc.root = std::move(op);
        return opId;
    }
    std::size_t first = 0;
    Node* parent = parentOf(doc, ids.front(), first);
    if (!parent) refuse("there is no node " + inQuotes(ids.front()) + " (or it is the root, which groups alone)");
    std::vector<std::size_t> indices;
    for (const auto& id : ids) {
        std::size_t i = 0;
        if (parentOf(doc, id, i) != parent) refuse("only nodes with the same parent can be grouped");
        if (std::find(indices.begin(), indices.end(), i) != indices.end()) refuse("a node is listed twice");
        indices.push_back(i);
    }
    std::sort(indices.begin(), indices.end());
    for (std::size_t i : indices) op.children.push_back(parent->children[i]);
    for (auto it = indices.rbegin(); it != indices.rend(); ++it)
        parent->children.erase(parent->children.begin() + long(*it));
    parent->children.insert(parent->children.begin() + long(indices.front()), std::move(op));
    return opId;
}

void updateNode(Document& doc, std::string_view id, const Node& updated)
{
    Node& n = requireNode(doc, id);
    if (updated.type != n.type) refuse("a node's type cannot change");
    if (updated.id != n.id) refuse("a node's id cannot change here");
    // An expression stays where its field keeps its number; a number typed
    // over a driven field replaces the expression.
    std::map<std::string, std::string> expressions = updated.expressions;
    for (auto it = expressions.begin(); it != expressions.end();) {
        if (detail::numberAt(n, it->first) != detail::numberAt(updated, it->first)) it = expressions.erase(it);
        else ++it;
    }
    n.expressions = std::move(expressions);
    n.name = updated.name;
    n.transform = updated.transform;
    n.visible = updated.visible;
    n.color = updated.color;
    n.params = updated.params;
    n.extra = updated.extra;
}

void setProfile(Document& doc, std::string_view id, std::vector<glm::dvec2> points,
                const std::vector<std::array<std::string, 2>>& expressions)
{
    Node& n = requireNode(doc, id);
    const FieldSpec* profile = nullptr;
    for (const FieldSpec& f : nodeTypeSpec(n.type).fields)
        if (f.shape == FieldShape::Points) profile = &f;
    if (!profile) refuse("a " + std::string(nodeTypeName(n.type)) + " has no profile");
    const std::string prefix = std::string(profile->key) + "[";
    std::erase_if(n.expressions, [&](const auto& e) { return e.first.starts_with(prefix); });
    for (std::size_t i = 0; i < expressions.size() && i < points.size(); ++i)
        for (std::size_t c = 0; c < 2; ++c)
            if (!expressions[i][c].empty())
                n.expressions[prefix + std::to_string(i) + "][" + std::to_string(c) + "]"] = expressions[i][c];
    profile->pointsIn(n) = std::move(points);
}

std::unordered_set<std::string> idsInSubtree(const Node& node)
{
    std::unordered_set<std::string> ids;
    collectIds(node, ids);
    return ids;
}

std::unordered_set<std::string> primitiveIdsInSubtree(const Node& node)
{
    std::unordered_set<std::string> ids;
    const auto walk = [&](const auto& self, const Node& n) -> void {
        if (isPrimitive(n.type)) ids.insert(n.id);
        for (const Node& c : n.children) self(self, c);
    };
    walk(walk, node);
    return ids;
}

std::vector<std::string> inTreeOrder(const Document& doc, const std::vector<std::string>& ids)
{
    const std::unordered_set<std::string> wanted(ids.begin(), ids.end());
    std::vector<std::string> ordered;
    const auto walk = [&](const auto& self, const Node& n) -> void {
        if (wanted.count(n.id)) ordered.push_back(n.id);
        for (const Node& c : n.children) self(self, c);
    };
    walk(walk, doc.root);
    return ordered;
}

std::string addMeshReference(Document& doc, const std::filesystem::path& file,
                             const std::optional<std::filesystem::path>& documentFolder)
{
    const std::string stem = file.stem().string();
    const std::string base = stem.empty() ? "mesh" : stem;
    auto taken = [&](const std::string& id) {
        return std::any_of(doc.meshes.begin(), doc.meshes.end(), [&](const MeshReference& m) { return m.id == id; });
    };
    std::string id = base;
    for (int k = 2; taken(id); ++k) id = base + "-" + std::to_string(k);
    std::filesystem::path path = std::filesystem::absolute(file);
    if (documentFolder) path = path.lexically_relative(std::filesystem::absolute(*documentFolder));
    MeshReference m;
    m.id = id;
    m.path = path.generic_string();
    doc.meshes.push_back(std::move(m));
    return id;
}

namespace {

bool isName(const std::string& s)
{
    if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
    return std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

// Calls f(where, expression text) for every expression of the document.
// (Doc is Document or const Document: the texts are editable through the first.)
template <class Doc, class F> void forEachExpression(Doc& doc, F&& f)
{
    for (auto& p : doc.parameters) f("parameters." + p.name, p.expression);
    std::vector<decltype(&doc.root)> stack{&doc.root};
    while (!stack.empty()) {
        auto* n = stack.back();
        stack.pop_back();
        for (auto& [path, text] : n->expressions) f(n->id + "." + path, text);
        for (auto it = n->children.rbegin(); it != n->children.rend(); ++it) stack.push_back(&*it);
    }
}

Parameter* findParameter(Document& doc, const std::string& name)
{
    for (Parameter& p : doc.parameters)
        if (p.name == name) return &p;
    return nullptr;
}

} // namespace

std::string addParameter(Document& doc, const std::string& base, const std::string& expression)
{
    if (!isName(base)) refuse("'" + base + "' is not a name (letters, digits and _, not starting with a digit)");
    if (expr::isUnitName(base)) refuse("'" + base + "' is a unit: a parameter so named would read as one (18" + base + ")");
    std::string name = base;
    for (int k = 2; findParameter(doc, name); ++k) name = base + std::to_string(k);
    Parameter p;
    p.name = name;
    p.expression = expression;
    doc.parameters.push_back(std::move(p));
    return name;
}

std::vector<std::string> parameterUses(const Document& doc, const std::string& name)
{
    std::vector<std::string> where;
    forEachExpression(doc, [&](const std::string& at, const std::string& text) {
        try {
            const expr::Uses u = expr::uses(text);
            if (std::find(u.names.begin(), u.names.end(), name) != u.names.end()) where.push_back(at);
        } catch (const expr::ExpressionError&) {
            // A malformed expression uses nothing it can be asked about.
        }
    });
    return where;
}

std::vector<std::string> nodeUses(const Document& doc, const std::vector<std::string>& ids)
{
    std::unordered_set<std::string> going;
    for (const std::string& id : ids)
        if (const Node* n = doc.root.find(id)) going.merge(idsInSubtree(*n));
    std::vector<std::string> where;
    forEachExpression(doc, [&](const std::string& at, const std::string& text) {
        // An id holds no dot, so the first one ends it; what goes with the
        // deletion does not stop it.
        if (going.contains(at.substr(0, at.find('.')))) return;
        try {
            for (const std::string& reference : expr::uses(text).references)
                if (going.contains(reference.substr(0, reference.find('.')))) {
                    where.push_back(at);
                    return;
                }
        } catch (const expr::ExpressionError&) {
            // A malformed expression refers to nothing it can be asked about.
        }
    });
    return where;
}

void renameParameter(Document& doc, const std::string& from, const std::string& to)
{
    if (!findParameter(doc, from)) refuse("there is no parameter '" + from + "'");
    if (from == to) return;
    if (!isName(to)) refuse("'" + to + "' is not a name (letters, digits and _, not starting with a digit)");
    // Files that hold such a name still load; a new one is refused.
    if (expr::isUnitName(to)) refuse("'" + to + "' is a unit: a parameter so named would read as one (18" + to + ")");
    if (findParameter(doc, to)) refuse("there is a parameter '" + to + "' already");
    Document renamed = doc;
    forEachExpression(renamed, [&](const std::string&, std::string& text) {
        try {
            text = expr::renameName(text, from, to);
        } catch (const expr::ExpressionError&) {
            // Left as written: it is refused on its own when resolved.
        }
    });
    findParameter(renamed, from)->name = to;
    doc = std::move(renamed);
}

void removeParameter(Document& doc, const std::string& name)
{
    const auto it = std::find_if(doc.parameters.begin(), doc.parameters.end(), [&](const Parameter& p) { return p.name == name; });
    if (it == doc.parameters.end()) refuse("there is no parameter '" + name + "'");
    const std::vector<std::string> uses = parameterUses(doc, name);
    if (!uses.empty()) {
        std::string list;
        for (std::size_t i = 0; i < uses.size() && i < 5; ++i) list += (i ? ", " : "") + uses[i];
        if (uses.size() > 5) list += " and " + std::to_string(uses.size() - 5) + " more";
        refuse("'" + name + "' is used by " + list);
    }
    doc.parameters.erase(it);
}

void removeNodes(Document& doc, const std::vector<std::string>& ids)
{
    Document edited = doc;
    for (const std::string& id : ids)
        if (edited.root.find(id)) removeNode(edited, id);
    doc = std::move(edited);
}

std::vector<std::string> emptiedByRemoving(const Document& doc, const std::vector<std::string>& ids)
{
    std::unordered_set<std::string> gone(ids.begin(), ids.end());
    std::vector<std::string> emptied;
    // Children first: a group emptied empties the group around it in turn.
    const auto visit = [&](const auto& self, const Node& n) -> bool { // whether n goes
        if (gone.count(n.id)) return true;
        if (n.children.empty()) return false;
        bool allGo = true;
        for (const Node& c : n.children)
            allGo = self(self, c) && allGo;
        if (allGo && &n != &doc.root) {
            emptied.push_back(n.id);
            return true;
        }
        return false;
    };
    visit(visit, doc.root);
    // A parent before what it holds.
    std::reverse(emptied.begin(), emptied.end());
    return emptied;
}

Document emptyDocument()
{
    Document doc;
    doc.root = makeNode(NodeType::Union, "root");
    doc.root.name = "Part";
    return doc;
}

namespace {
void collectDifferences(const Node& n, std::vector<const Node*>& out)
{
    if (n.type == NodeType::Difference) out.push_back(&n);
    for (const Node& c : n.children)
        collectDifferences(c, out);
}
} // namespace

std::vector<std::string> differencesWithNewBase(const Document& before, const Document& after)
{
    std::vector<const Node*> differences;
    collectDifferences(after.root, differences);
    std::vector<std::string> changed;
    for (const Node* d : differences) {
        const Node* old = before.root.find(d->id);
        if (!old || old->type != NodeType::Difference || old->children.empty()) continue;
        if (d->children.empty() || d->children.front().id != old->children.front().id) changed.push_back(d->id);
    }
    return changed;
}

std::string differenceWithNewBase(const Document& before, const Document& after)
{
    const std::vector<std::string> changed = differencesWithNewBase(before, after);
    return changed.empty() ? std::string() : changed.front();
}

} // namespace kerf::edit
