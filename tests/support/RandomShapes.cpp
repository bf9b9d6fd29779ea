#include "RandomShapes.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace kerf::test {

Transform RandomShapes::transform(double reach)
{
    Transform t;
    t.translate = vec(-reach, reach);
    if (chance(0.5)) {
        t.rotate = vec(-180.0, 180.0);
    } else {
        // One draw per statement: a constructor's arguments are evaluated in
        // an unspecified order (GCC right to left, clang left to right), and
        // the trees must be the same whichever compiler built the tests.
        // This is GCC's order, so the trees stay as they were.
        const double rz = 90.0 * integer(-2, 2), ry = 90.0 * integer(-2, 2), rx = 90.0 * integer(-2, 2);
        t.rotate = glm::dvec3(rx, ry, rz);
    }
    return t;
}

std::vector<glm::dvec2> RandomShapes::simplePolygon(int points, double radius)
{
    std::vector<double> angles;
    for (int i = 0; i < points; ++i) angles.push_back(uniform(0.0, 2.0 * 3.14159265358979));
    std::sort(angles.begin(), angles.end());
    // Reject near-duplicate angles by spreading them evenly with jitter.
    std::vector<glm::dvec2> poly;
    for (int i = 0; i < points; ++i) {
        const double a = (i + uniform(0.1, 0.9)) * 2.0 * 3.14159265358979 / points;
        const double r = radius * uniform(0.3, 1.0);
        poly.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    if (chance(0.5)) std::reverse(poly.begin(), poly.end()); // either winding
    return poly;
}

std::vector<NodeType> RandomShapes::primitiveTypes()
{
    std::vector<NodeType> types;
    for (const NodeTypeSpec& spec : nodeTypeSpecs())
        if (spec.category == NodeCategory::Primitive) types.push_back(spec.type);
    return types;
}

std::vector<NodeType> RandomShapes::operationTypes()
{
    std::vector<NodeType> types;
    for (const NodeTypeSpec& spec : nodeTypeSpecs())
        if (spec.category != NodeCategory::Primitive) types.push_back(spec.type);
    return types;
}

std::vector<NodeType> RandomShapes::boundedPrimitiveTypes()
{
    std::vector<NodeType> types;
    for (const NodeType t : primitiveTypes())
        if (nodeTypeSpec(t).localBounds(nodeTypeSpec(t).defaults).isBounded()) types.push_back(t);
    return types;
}

// One field drawn from its typical range (NodeTypes.hpp), within its rules.
void RandomShapes::fill(const FieldSpec& f, Node& n)
{
    const double low = std::max(f.typicalLow, f.min), high = f.typicalHigh;
    switch (f.shape) {
    case FieldShape::Number:
        if (f.optional) {
            // Absent, tiny (numerically delicate) or typical.
            const int which = integer(0, 3);
            f.numberIn(n) = which == 0 ? f.absent : which == 1 ? uniform(1e-6, 1e-2) : uniform(low, high);
        } else {
            f.numberIn(n) = uniform(low, high);
        }
        break;
    case FieldShape::Vector: f.vectorIn(n) = vec(low, high); break;
    case FieldShape::Direction: {
        glm::dvec3 d = vec(-1.0, 1.0);
        if (glm::length(d) < 0.1) d = {0, 0, 1};
        f.vectorIn(n) = glm::normalize(d);
        break;
    }
    case FieldShape::Counts:
        for (auto& c : f.countsIn(n)) c = integer(int(low), int(high));
        break;
    case FieldShape::Points: {
        const double radius = uniform(low, high);
        auto points = simplePolygon(integer(3, 12), radius);
        if (std::isfinite(f.min)) {
            // A first coordinate bounded below (a revolve's r >= 0): the
            // polygon moved to that side, sometimes pressed onto the axis.
            const bool onAxis = chance(0.5);
            for (auto& v : points) {
                v.x += f.min + (onAxis ? 0.5 : 1.05) * radius;
                if (onAxis) v.x = std::max(v.x, f.min);
            }
        }
        f.pointsIn(n) = std::move(points);
        break;
    }
    }
}

void RandomShapes::fillFields(Node& n)
{
    const NodeTypeSpec& spec = nodeTypeSpec(n.type);
    for (int attempt = 0;; ++attempt) {
        for (const FieldSpec& f : spec.fields) fill(f, n);
        if (!spec.check || !spec.check(n.params)) return;
        if (attempt == 1000) throw std::logic_error("no valid random " + std::string(spec.name));
    }
}

Node RandomShapes::primitive(NodeType type)
{
    Node n = makeNode(type, nextId());
    fillFields(n);
    n.transform = transform(15.0);
    return n;
}

NodeType RandomShapes::randomBoundedPrimitiveType()
{
    static const std::vector<NodeType> kinds = boundedPrimitiveTypes();
    return kinds[std::size_t(integer(0, int(kinds.size()) - 1))];
}

Node RandomShapes::operation(NodeType type)
{
    Node n = makeNode(type, nextId());
    const int children = isBoolean(type) ? integer(1, 3) : 1;
    for (int i = 0; i < children; ++i) n.children.push_back(primitive(randomBoundedPrimitiveType()));
    fillFields(n);
    n.transform = transform(10.0);
    return n;
}

Node RandomShapes::tree(int depth)
{
    if (depth <= 0 || chance(0.25)) return primitive(randomBoundedPrimitiveType());
    static const std::vector<NodeType> ops = operationTypes();
    const NodeType type = ops[std::size_t(integer(0, int(ops.size()) - 1))];
    Node n = operation(type);
    for (auto& c : n.children)
        if (chance(0.6)) c = tree(depth - 1);
    if (chance(0.1) && n.children.size() > 1) n.children[1].visible = false;
    return n;
}

Document RandomShapes::document(Node root)
{
    Document d;
    d.root = std::move(root);
    return d;
}

} // namespace kerf::test
