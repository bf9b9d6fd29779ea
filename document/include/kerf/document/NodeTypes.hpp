#pragma once
// One table row per node type: its spelling in a document, what it is (a
// primitive, a boolean, an operation on one child), its fields and their
// rules, its defaults, and for primitives the bounds of the solid. The
// document reader and writer, makeNode, the property editor's rows, the
// add-feature menus and the tests' random shapes all read this table, so a
// new node type is one row here (and its parameter struct in Node.hpp).

#include "kerf/document/Aabb.hpp"
#include "kerf/document/Node.hpp"

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace kerf {

enum class NodeCategory : std::uint8_t {
    Primitive, // no children
    Boolean,   // one or more children
    Operation, // exactly one child
};

/// How a field is written in a document and edited.
enum class FieldShape : std::uint8_t {
    Number,    // one number
    Vector,    // [x, y, z]
    Direction, // [x, y, z], made unit length on load; lengths along it are divided by the length it had
    Counts,    // [i, j, k] integers
    Points,    // [[a, b], ...] a profile (its defects are the node type's check)
};

enum class FieldUnit : std::uint8_t { Length, Angle, Plain, Count };

struct FieldSpec {
    std::string_view key;   // the JSON key ("radius_bottom")
    std::string_view label; // the property editor's row ("Bottom radius")
    std::string_view help;  // what it means, for tooltips and docs
    FieldShape shape = FieldShape::Number;
    FieldUnit unit = FieldUnit::Length;
    /// Every number of the field (each component, each count) is >= min, or
    /// > min when minExclusive; lengths are also within limits::kMaxLength.
    double min = -std::numeric_limits<double>::infinity();
    bool minExclusive = false;
    /// Optional fields take `absent` when missing and are not written when
    /// they hold it (Number fields only); others are required.
    bool optional = false;
    double absent = 0.0;
    /// A length measured along the node's Direction field (a plane's offset).
    bool alongDirection = false;
    /// Points: the names of a point's two coordinates ("x", "y" or "r", "z").
    std::string_view pointAxes[2] = {"x", "y"};
    /// The tests' random shapes draw numbers between these (and profiles of this radius).
    double typicalLow = 1.0, typicalHigh = 40.0;

    // Where the field lives in a node's parameters (the one matching `shape`).
    double* (*number)(NodeParams&) = nullptr;
    glm::dvec3* (*vector)(NodeParams&) = nullptr;             // Vector and Direction
    std::array<std::int64_t, 3>* (*counts)(NodeParams&) = nullptr;
    std::vector<glm::dvec2>* (*points)(NodeParams&) = nullptr;

    double& numberIn(Node& n) const { return *number(n.params); }
    double numberIn(const Node& n) const { return *number(const_cast<NodeParams&>(n.params)); }
    glm::dvec3& vectorIn(Node& n) const { return *vector(n.params); }
    glm::dvec3 vectorIn(const Node& n) const { return *vector(const_cast<NodeParams&>(n.params)); }
    std::array<std::int64_t, 3>& countsIn(Node& n) const { return *counts(n.params); }
    const std::array<std::int64_t, 3>& countsIn(const Node& n) const { return *counts(const_cast<NodeParams&>(n.params)); }
    std::vector<glm::dvec2>& pointsIn(Node& n) const { return *points(n.params); }
    const std::vector<glm::dvec2>& pointsIn(const Node& n) const { return *points(const_cast<NodeParams&>(n.params)); }
};

/// A rule that involves more than one number was broken: which field to name and why.
struct FieldRefusal {
    std::string field;
    std::string reason;
};

struct NodeTypeSpec {
    NodeType type;
    std::string_view name; // the document's spelling ("box")
    std::string_view help;
    NodeCategory category;
    std::vector<FieldSpec> fields; // in the order they are written
    NodeParams defaults;           // what makeNode gives a new feature
    /// Rules across fields (a round no larger than half the box, a simple
    /// profile), checked after each field's own; empty when none is broken.
    std::optional<FieldRefusal> (*check)(const NodeParams&) = nullptr;
    /// Primitives: the solid's bounds in its own frame.
    Aabb (*localBounds)(const NodeParams&) = nullptr;

    const FieldSpec* field(std::string_view key) const;
};

/// Every node type, primitives first, in the order menus list them.
std::span<const NodeTypeSpec> nodeTypeSpecs();
const NodeTypeSpec& nodeTypeSpec(NodeType type);

/// A field's numbers as written in messages ("12.5").
std::string formatFieldNumber(double v);

} // namespace kerf
