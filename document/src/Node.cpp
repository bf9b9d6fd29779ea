#include "kerf/document/Node.hpp"

#include <cstdio>

namespace kerf {

namespace {
struct TypeName {
    NodeType type;
    std::string_view name;
};
constexpr TypeName kTypeNames[] = {
    {NodeType::Box, "box"},           {NodeType::Sphere, "sphere"},
    {NodeType::Cylinder, "cylinder"}, {NodeType::Cone, "cone"},
    {NodeType::Torus, "torus"},       {NodeType::Extrude, "extrude"},
    {NodeType::Halfspace, "halfspace"}, {NodeType::Union, "union"},
    {NodeType::Intersection, "intersection"}, {NodeType::Difference, "difference"},
    {NodeType::Offset, "offset"},     {NodeType::Shell, "shell"},
    {NodeType::Array, "array"},       {NodeType::Mirror, "mirror"},
};

int hexDigit(char c)
{
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}
} // namespace

std::string_view nodeTypeName(NodeType type)
{
    for (const auto& t : kTypeNames)
        if (t.type == type) return t.name;
    return "?";
}

std::optional<NodeType> nodeTypeFromName(std::string_view name)
{
    for (const auto& t : kTypeNames)
        if (t.name == name) return t.type;
    return std::nullopt;
}

bool isPrimitive(NodeType type)
{
    // Named one by one (no default): a type added to NodeType must be placed
    // here or the build fails (-Wswitch), whatever its place in the enum.
    switch (type) {
    case NodeType::Box:
    case NodeType::Sphere:
    case NodeType::Cylinder:
    case NodeType::Cone:
    case NodeType::Torus:
    case NodeType::Extrude:
    case NodeType::Halfspace: return true;
    case NodeType::Union:
    case NodeType::Intersection:
    case NodeType::Difference:
    case NodeType::Offset:
    case NodeType::Shell:
    case NodeType::Array:
    case NodeType::Mirror: return false;
    }
    return false;
}

bool isBoolean(NodeType type)
{
    return type == NodeType::Union || type == NodeType::Intersection || type == NodeType::Difference;
}

std::optional<Color> parseColor(std::string_view text)
{
    if (text.size() != 7 || text[0] != '#') return std::nullopt;
    int v[6];
    for (int i = 0; i < 6; ++i) {
        v[i] = hexDigit(text[static_cast<std::size_t>(i) + 1]);
        if (v[i] < 0) return std::nullopt;
    }
    return Color{static_cast<std::uint8_t>(v[0] * 16 + v[1]), static_cast<std::uint8_t>(v[2] * 16 + v[3]),
                 static_cast<std::uint8_t>(v[4] * 16 + v[5])};
}

std::string formatColor(Color c)
{
    char buf[8];
    std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c.r, c.g, c.b);
    return buf;
}

const Node* Node::find(std::string_view nodeId) const
{
    if (id == nodeId) return this;
    for (const auto& c : children)
        if (const Node* n = c.find(nodeId)) return n;
    return nullptr;
}

Node* Node::find(std::string_view nodeId)
{
    return const_cast<Node*>(static_cast<const Node*>(this)->find(nodeId));
}

std::size_t Node::count() const
{
    std::size_t n = 1;
    for (const auto& c : children) n += c.count();
    return n;
}

Node makeNode(NodeType type, std::string id)
{
    Node n;
    n.id = std::move(id);
    n.type = type;
    switch (type) {
    case NodeType::Box: n.params = BoxParams{{20.0, 20.0, 20.0}, 0.0}; break;
    case NodeType::Sphere: n.params = SphereParams{10.0}; break;
    case NodeType::Cylinder: n.params = CylinderParams{10.0, 20.0}; break;
    case NodeType::Cone: n.params = ConeParams{10.0, 0.0, 20.0}; break;
    case NodeType::Torus: n.params = TorusParams{20.0, 5.0}; break;
    case NodeType::Extrude:
        n.params = ExtrudeParams{{{-10.0, -10.0}, {10.0, -10.0}, {10.0, 10.0}, {-10.0, 10.0}}, 20.0};
        break;
    case NodeType::Halfspace: n.params = HalfspaceParams{{0.0, 0.0, 1.0}, 0.0}; break;
    case NodeType::Union:
    case NodeType::Intersection:
    case NodeType::Difference: n.params = BooleanParams{0.0}; break;
    case NodeType::Offset: n.params = OffsetParams{1.0}; break;
    case NodeType::Shell: n.params = ShellParams{2.0}; break;
    case NodeType::Array: n.params = ArrayParams{{2, 1, 1}, {50.0, 0.0, 0.0}}; break;
    case NodeType::Mirror: n.params = MirrorParams{{1.0, 0.0, 0.0}, 0.0}; break;
    }
    return n;
}

} // namespace kerf
