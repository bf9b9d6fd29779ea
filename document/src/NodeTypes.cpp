#include "kerf/document/NodeTypes.hpp"

#include "kerf/document/ProfileCheck.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace kerf {

namespace {

// Where a field lives in its type's parameter struct.
template <class P, double P::*M> double* number(NodeParams& p) { return &(std::get<P>(p).*M); }
template <class P, glm::dvec3 P::*M> glm::dvec3* vector(NodeParams& p) { return &(std::get<P>(p).*M); }
template <class P, std::array<std::int64_t, 3> P::*M> std::array<std::int64_t, 3>* counts(NodeParams& p)
{
    return &(std::get<P>(p).*M);
}
template <class P, std::vector<glm::dvec2> P::*M> std::vector<glm::dvec2>* points(NodeParams& p)
{
    return &(std::get<P>(p).*M);
}

// A positive length (a radius, a height).
template <class P, double P::*M> FieldSpec positiveLength(std::string_view key, std::string_view label, std::string_view help,
                                                          double low = 1.0, double high = 40.0)
{
    return {.key = key, .label = label, .help = help, .min = 0.0, .minExclusive = true, .typicalLow = low,
            .typicalHigh = high, .number = &number<P, M>};
}

std::optional<FieldRefusal> profileDefect(const std::vector<glm::dvec2>& profile)
{
    if (auto defect = findProfileDefect(profile)) return FieldRefusal{"profile", *defect};
    return std::nullopt;
}

Aabb profileBounds(const std::vector<glm::dvec2>& profile)
{
    Aabb box;
    for (const auto& v : profile) box = box.merged(Aabb{{v.x, v.y, 0.0}, {v.x, v.y, 0.0}});
    return box;
}

std::vector<NodeTypeSpec> buildTable()
{
    std::vector<NodeTypeSpec> t;
    // Primitives.
    t.push_back({
        .type = NodeType::Box, .name = "box", .help = "A board or block, centred on its origin, optionally with rounded edges.",
        .category = NodeCategory::Primitive,
        .fields = {
            {.key = "size", .label = "Size", .help = "Length, width and thickness along X, Y and Z.",
             .shape = FieldShape::Vector, .min = 0.0, .minExclusive = true, .vector = &vector<BoxParams, &BoxParams::size>},
            {.key = "round", .label = "Round", .help = "Radius of every edge and corner (0: square).", .min = 0.0,
             .optional = true, .typicalLow = 0.0, .typicalHigh = 5.0, .number = &number<BoxParams, &BoxParams::round>},
        },
        .defaults = BoxParams{{20.0, 20.0, 20.0}, 0.0},
        .check = [](const NodeParams& p) -> std::optional<FieldRefusal> {
            const auto& b = std::get<BoxParams>(p);
            const double limit = 0.5 * std::min({b.size.x, b.size.y, b.size.z});
            if (b.round > limit)
                return FieldRefusal{"round", "must be <= half the smallest size (" + formatFieldNumber(limit) +
                                                 "), not " + formatFieldNumber(b.round)};
            return std::nullopt;
        },
        .localBounds = [](const NodeParams& p) { return Aabb::centered(0.5 * std::get<BoxParams>(p).size); },
    });
    t.push_back({
        .type = NodeType::Sphere, .name = "sphere", .help = "A ball centred on its origin.",
        .category = NodeCategory::Primitive,
        .fields = {positiveLength<SphereParams, &SphereParams::radius>("radius", "Radius", "Radius of the ball.", 0.5, 25.0)},
        .defaults = SphereParams{10.0},
        .localBounds = [](const NodeParams& p) { return Aabb::centered(glm::dvec3(std::get<SphereParams>(p).radius)); },
    });
    t.push_back({
        .type = NodeType::Cylinder, .name = "cylinder", .help = "A dowel or hole along Z, centred on its origin.",
        .category = NodeCategory::Primitive,
        .fields = {positiveLength<CylinderParams, &CylinderParams::radius>("radius", "Radius", "Radius across Z.", 0.5, 20.0),
                   positiveLength<CylinderParams, &CylinderParams::height>("height", "Height", "Length along Z.")},
        .defaults = CylinderParams{10.0, 20.0},
        .localBounds = [](const NodeParams& p) {
            const auto& c = std::get<CylinderParams>(p);
            return Aabb::centered({c.radius, c.radius, 0.5 * c.height});
        },
    });
    t.push_back({
        .type = NodeType::Cone, .name = "cone", .help = "A tapered round (a countersink, a tapered leg) along Z.",
        .category = NodeCategory::Primitive,
        .fields = {
            {.key = "radius_bottom", .label = "Bottom radius", .help = "Radius at the bottom (z = -height / 2).", .min = 0.0,
             .typicalLow = 0.0, .typicalHigh = 20.0, .number = &number<ConeParams, &ConeParams::radiusBottom>},
            {.key = "radius_top", .label = "Top radius", .help = "Radius at the top (z = +height / 2).", .min = 0.0,
             .typicalLow = 0.0, .typicalHigh = 20.0, .number = &number<ConeParams, &ConeParams::radiusTop>},
            positiveLength<ConeParams, &ConeParams::height>("height", "Height", "Length along Z."),
        },
        .defaults = ConeParams{10.0, 0.0, 20.0},
        .check = [](const NodeParams& p) -> std::optional<FieldRefusal> {
            const auto& c = std::get<ConeParams>(p);
            if (c.radiusBottom == 0.0 && c.radiusTop == 0.0)
                return FieldRefusal{"radius_bottom", "radius_bottom and radius_top cannot both be 0"};
            return std::nullopt;
        },
        .localBounds = [](const NodeParams& p) {
            const auto& c = std::get<ConeParams>(p);
            const double r = std::max(c.radiusBottom, c.radiusTop);
            return Aabb::centered({r, r, 0.5 * c.height});
        },
    });
    t.push_back({
        .type = NodeType::Torus, .name = "torus", .help = "A ring around Z.",
        .category = NodeCategory::Primitive,
        .fields = {positiveLength<TorusParams, &TorusParams::majorRadius>("major_radius", "Major radius",
                                                                          "From the axis to the centre of the ring's section.", 2.0, 20.0),
                   positiveLength<TorusParams, &TorusParams::minorRadius>("minor_radius", "Minor radius",
                                                                          "Radius of the ring's section.", 0.5, 10.0)},
        .defaults = TorusParams{20.0, 5.0},
        .localBounds = [](const NodeParams& p) {
            const auto& c = std::get<TorusParams>(p);
            const double r = c.majorRadius + c.minorRadius;
            return Aabb::centered({r, r, c.minorRadius});
        },
    });
    t.push_back({
        .type = NodeType::Extrude, .name = "extrude", .help = "A profile in XY extruded along Z, centred on z = 0.",
        .category = NodeCategory::Primitive,
        .fields = {
            {.key = "profile", .label = "Profile", .help = "The outline's corners in XY, in order (a simple polygon).",
             .shape = FieldShape::Points, .typicalLow = 3.0, .typicalHigh = 25.0,
             .points = &points<ExtrudeParams, &ExtrudeParams::profile>},
            positiveLength<ExtrudeParams, &ExtrudeParams::height>("height", "Height", "Thickness along Z."),
        },
        .defaults = ExtrudeParams{{{-10.0, -10.0}, {10.0, -10.0}, {10.0, 10.0}, {-10.0, 10.0}}, 20.0},
        .check = [](const NodeParams& p) { return profileDefect(std::get<ExtrudeParams>(p).profile); },
        .localBounds = [](const NodeParams& p) {
            const auto& e = std::get<ExtrudeParams>(p);
            Aabb box = profileBounds(e.profile);
            box.min.z = -0.5 * e.height;
            box.max.z = 0.5 * e.height;
            return box;
        },
    });
    t.push_back({
        .type = NodeType::Revolve, .name = "revolve",
        .help = "A profile in the XZ half-plane turned about Z: a turned leg, a spindle, a knob.",
        .category = NodeCategory::Primitive,
        .fields = {
            {.key = "profile", .label = "Profile",
             .help = "The outline's corners as [r, z]: r the distance from the axis (>= 0), z the height (a simple polygon).",
             .shape = FieldShape::Points, .min = 0.0, .pointAxes = {"r", "z"}, .typicalLow = 3.0, .typicalHigh = 20.0,
             .points = &points<RevolveParams, &RevolveParams::profile>},
        },
        .defaults = RevolveParams{{{0.0, -20.0}, {12.0, -20.0}, {12.0, -15.0}, {8.0, -10.0}, {10.0, 12.0}, {6.0, 20.0}, {0.0, 20.0}}},
        .check = [](const NodeParams& p) { return profileDefect(std::get<RevolveParams>(p).profile); },
        .localBounds = [](const NodeParams& p) {
            const Aabb b = profileBounds(std::get<RevolveParams>(p).profile);
            const double r = std::max(b.max.x, 0.0);
            return Aabb{{-r, -r, b.min.y}, {r, r, b.max.y}};
        },
    });
    t.push_back({
        .type = NodeType::Halfspace, .name = "halfspace",
        .help = "Everything on one side of a plane (unbounded: cut something with it, or set the part's bounds).",
        .category = NodeCategory::Primitive,
        .fields = {
            {.key = "normal", .label = "Normal", .help = "The plane's normal, pointing out of the solid.",
             .shape = FieldShape::Direction, .unit = FieldUnit::Plain,
             .vector = &vector<HalfspaceParams, &HalfspaceParams::normal>},
            {.key = "offset", .label = "Offset", .help = "The plane's distance from the origin along the normal.",
             .alongDirection = true, .typicalLow = -10.0, .typicalHigh = 10.0,
             .number = &number<HalfspaceParams, &HalfspaceParams::offset>},
        },
        .defaults = HalfspaceParams{{0.0, 0.0, 1.0}, 0.0},
        .localBounds = [](const NodeParams& p) {
            // dot(n, p) <= offset is bounded along one axis only when n is axis-aligned.
            const auto& h = std::get<HalfspaceParams>(p);
            Aabb box = Aabb::infinite();
            int axis = -1, nonZero = 0;
            for (int i = 0; i < 3; ++i)
                if (h.normal[i] != 0.0) {
                    axis = i;
                    ++nonZero;
                }
            if (nonZero == 1) {
                if (h.normal[axis] > 0)
                    box.max[axis] = h.offset / h.normal[axis];
                else
                    box.min[axis] = h.offset / h.normal[axis];
            }
            return box;
        },
    });
    // Booleans.
    const FieldSpec blend{.key = "blend", .label = "Blend",
                          .help = "Radius of the smooth fillet where the children meet (0: a sharp edge).", .min = 0.0,
                          .optional = true, .typicalLow = 0.0, .typicalHigh = 20.0,
                          .number = &number<BooleanParams, &BooleanParams::blend>};
    t.push_back({.type = NodeType::Union, .name = "union", .help = "All children together.",
                 .category = NodeCategory::Boolean, .fields = {blend}, .defaults = BooleanParams{0.0}});
    t.push_back({.type = NodeType::Intersection, .name = "intersection", .help = "What all children share.",
                 .category = NodeCategory::Boolean, .fields = {blend}, .defaults = BooleanParams{0.0}});
    t.push_back({.type = NodeType::Difference, .name = "difference",
                 .help = "The first child with every other child cut away.", .category = NodeCategory::Boolean,
                 .fields = {blend}, .defaults = BooleanParams{0.0}});
    // Operations on one child.
    t.push_back({
        .type = NodeType::Offset, .name = "offset", .help = "The child grown (or shrunk, negative) by a distance.",
        .category = NodeCategory::Operation,
        .fields = {{.key = "distance", .label = "Distance", .help = "How far every surface moves outwards (negative: inwards).",
                    .typicalLow = -3.0, .typicalHigh = 8.0, .number = &number<OffsetParams, &OffsetParams::distance>}},
        .defaults = OffsetParams{1.0},
    });
    t.push_back({
        .type = NodeType::Shell, .name = "shell", .help = "A wall of the given thickness inside the child's surface.",
        .category = NodeCategory::Operation,
        .fields = {positiveLength<ShellParams, &ShellParams::thickness>("thickness", "Thickness", "The wall's thickness.", 0.2, 6.0)},
        .defaults = ShellParams{2.0},
    });
    t.push_back({
        .type = NodeType::Array, .name = "array", .help = "Copies of the child on a grid (shelf-pin rows, slats).",
        .category = NodeCategory::Operation,
        .fields = {
            {.key = "count", .label = "Count", .help = "Copies along X, Y and Z (1: no copies along that axis).",
             .shape = FieldShape::Counts, .unit = FieldUnit::Count, .min = 1.0, .typicalLow = 1.0, .typicalHigh = 4.0,
             .counts = &counts<ArrayParams, &ArrayParams::count>},
            {.key = "step", .label = "Step", .help = "From one copy to the next along X, Y and Z.",
             .shape = FieldShape::Vector, .typicalLow = -30.0, .typicalHigh = 30.0,
             .vector = &vector<ArrayParams, &ArrayParams::step>},
        },
        .defaults = ArrayParams{{2, 1, 1}, {50.0, 0.0, 0.0}},
    });
    t.push_back({
        .type = NodeType::Mirror, .name = "mirror", .help = "The child and its mirror image in a plane.",
        .category = NodeCategory::Operation,
        .fields = {
            {.key = "normal", .label = "Normal", .help = "The mirror plane's normal.", .shape = FieldShape::Direction,
             .unit = FieldUnit::Plain, .vector = &vector<MirrorParams, &MirrorParams::normal>},
            {.key = "offset", .label = "Offset", .help = "The plane's distance from the origin along the normal.",
             .optional = true, .alongDirection = true, .typicalLow = -10.0, .typicalHigh = 10.0,
             .number = &number<MirrorParams, &MirrorParams::offset>},
        },
        .defaults = MirrorParams{{1.0, 0.0, 0.0}, 0.0},
    });
    return t;
}

// Indexed by NodeType; the table must name every type once.
const std::vector<NodeTypeSpec>& table()
{
    static const std::vector<NodeTypeSpec> t = buildTable();
    return t;
}

const std::vector<const NodeTypeSpec*>& byType()
{
    static const std::vector<const NodeTypeSpec*> index = [] {
        std::vector<const NodeTypeSpec*> v;
        for (const auto& s : table()) {
            const auto i = static_cast<std::size_t>(s.type);
            if (v.size() <= i) v.resize(i + 1, nullptr);
            v[i] = &s;
        }
        return v;
    }();
    return index;
}

} // namespace

const FieldSpec* NodeTypeSpec::field(std::string_view key) const
{
    for (const auto& f : fields)
        if (f.key == key) return &f;
    return nullptr;
}

std::span<const NodeTypeSpec> nodeTypeSpecs() { return table(); }

const NodeTypeSpec& nodeTypeSpec(NodeType type)
{
    const auto& index = byType();
    const auto i = static_cast<std::size_t>(type);
    // A type missing from the table is a programming error that every test trips over.
    if (i >= index.size() || !index[i]) throw std::logic_error("node type missing from the node type table");
    return *index[i];
}

std::string formatFieldNumber(double v)
{
    std::ostringstream s;
    s.precision(12);
    s << v;
    return s.str();
}

std::string_view nodeTypeName(NodeType type)
{
    const auto& index = byType();
    const auto i = static_cast<std::size_t>(type);
    return i < index.size() && index[i] ? index[i]->name : std::string_view("?");
}

std::optional<NodeType> nodeTypeFromName(std::string_view name)
{
    for (const auto& s : table())
        if (s.name == name) return s.type;
    return std::nullopt;
}

bool isPrimitive(NodeType type) { return nodeTypeSpec(type).category == NodeCategory::Primitive; }

bool isBoolean(NodeType type) { return nodeTypeSpec(type).category == NodeCategory::Boolean; }

Node makeNode(NodeType type, std::string id)
{
    Node n;
    n.id = std::move(id);
    n.type = type;
    n.params = nodeTypeSpec(type).defaults;
    return n;
}

} // namespace kerf
