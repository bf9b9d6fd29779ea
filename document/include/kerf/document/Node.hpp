#pragma once
// The feature tree of a Kerf document (docs/document-format.md).
// Plain data: parameters in millimetres and degrees exactly as the file says,
// plus every field this version does not know, so that a load/save round trip
// keeps them. Geometry is derived from this tree elsewhere (evaluator).

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace kerf {

using Json = nlohmann::ordered_json;

enum class NodeType {
    Box,
    Sphere,
    Cylinder,
    Cone,
    Torus,
    Extrude,
    Halfspace,
    Revolve,
    Union,
    Intersection,
    Difference,
    Offset,
    Shell,
    Array,
    Mirror,
};

/// The spelling of a node type in a document ("box", "union", ...).
/// These read the node type table (NodeTypes.hpp).
std::string_view nodeTypeName(NodeType type);
/// Parses a type name; empty when unknown.
std::optional<NodeType> nodeTypeFromName(std::string_view name);
bool isPrimitive(NodeType type);
bool isBoolean(NodeType type); // union, intersection, difference

/// Places a node's local frame in its parent's frame:
/// p_parent = translate + Rz(rz) * Ry(ry) * Rx(rx) * p_local, angles in degrees.
struct Transform {
    glm::dvec3 translate{0.0};
    glm::dvec3 rotate{0.0};
    /// Unknown fields inside the transform object, kept for round trips.
    nlohmann::ordered_json extra = nlohmann::ordered_json::object();
    bool isIdentity() const { return translate == glm::dvec3(0.0) && rotate == glm::dvec3(0.0); }
    bool operator==(const Transform&) const = default;
};

/// An sRGB colour as written in a document ("#rrggbb").
struct Color {
    std::uint8_t r = 0, g = 0, b = 0;
    bool operator==(const Color&) const = default;
};
std::optional<Color> parseColor(std::string_view text);
std::string formatColor(Color c);

struct BoxParams {
    glm::dvec3 size{1.0};
    double round = 0.0;
    bool operator==(const BoxParams&) const = default;
};
struct SphereParams {
    double radius = 1.0;
    bool operator==(const SphereParams&) const = default;
};
struct CylinderParams {
    double radius = 1.0;
    double height = 1.0;
    bool operator==(const CylinderParams&) const = default;
};
struct ConeParams {
    double radiusBottom = 1.0;
    double radiusTop = 0.0;
    double height = 1.0;
    bool operator==(const ConeParams&) const = default;
};
struct TorusParams {
    double majorRadius = 2.0;
    double minorRadius = 1.0;
    bool operator==(const TorusParams&) const = default;
};
struct ExtrudeParams {
    std::vector<glm::dvec2> profile;
    double height = 1.0;
    bool operator==(const ExtrudeParams&) const = default;
};
/// A profile in the XZ half-plane ([r, z] points, r >= 0) swept about the local Z axis.
struct RevolveParams {
    std::vector<glm::dvec2> profile;
    bool operator==(const RevolveParams&) const = default;
};
struct HalfspaceParams {
    glm::dvec3 normal{0.0, 0.0, 1.0}; // unit length after load
    double offset = 0.0;
    bool operator==(const HalfspaceParams&) const = default;
};
struct BooleanParams {
    double blend = 0.0;
    bool operator==(const BooleanParams&) const = default;
};
struct OffsetParams {
    double distance = 0.0;
    bool operator==(const OffsetParams&) const = default;
};
struct ShellParams {
    double thickness = 1.0;
    bool operator==(const ShellParams&) const = default;
};
struct ArrayParams {
    std::array<std::int64_t, 3> count{1, 1, 1};
    glm::dvec3 step{0.0};
    bool operator==(const ArrayParams&) const = default;
};
struct MirrorParams {
    glm::dvec3 normal{1.0, 0.0, 0.0}; // unit length after load
    double offset = 0.0;
    bool operator==(const MirrorParams&) const = default;
};

using NodeParams = std::variant<BoxParams, SphereParams, CylinderParams, ConeParams, TorusParams,
                                ExtrudeParams, RevolveParams, HalfspaceParams, BooleanParams, OffsetParams,
                                ShellParams, ArrayParams, MirrorParams>;

struct Node {
    std::string id;
    NodeType type = NodeType::Union;
    std::optional<std::string> name;
    Transform transform;
    bool visible = true;
    std::optional<Color> color;
    NodeParams params = BooleanParams{};
    std::vector<Node> children;
    /// Fields this version does not know, in file order; written back on save.
    Json extra = Json::object();
    /// The fields that hold an expression instead of a number, by path
    /// ("radius", "size[0]", "profile[2][1]", "transform.translate[2]"):
    /// the number in the field is the expression's value, resolved on load.
    std::map<std::string, std::string> expressions;

    bool operator==(const Node&) const = default;

    template <class P> const P& as() const { return std::get<P>(params); }
    template <class P> P& as() { return std::get<P>(params); }

    /// The node with this id in the subtree, or nullptr.
    const Node* find(std::string_view nodeId) const;
    Node* find(std::string_view nodeId);
    /// Number of nodes in the subtree, this one included.
    std::size_t count() const;
};

/// A node with the type's default parameters (used by editors to add features;
/// NodeTypes.hpp's table holds them).
Node makeNode(NodeType type, std::string id);

} // namespace kerf
