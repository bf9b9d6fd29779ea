#include "RandomShapes.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

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

Node RandomShapes::primitive(NodeType type)
{
    Node n = makeNode(type, nextId());
    switch (type) {
    case NodeType::Box: {
        BoxParams p;
        p.size = vec(1.0, 40.0);
        p.round = chance(0.5) ? 0.0 : uniform(0.0, 0.5 * std::min({p.size.x, p.size.y, p.size.z}));
        n.params = p;
        break;
    }
    case NodeType::Sphere: n.params = SphereParams{uniform(0.5, 25.0)}; break;
    case NodeType::Cylinder: n.params = CylinderParams{uniform(0.5, 20.0), uniform(1.0, 40.0)}; break;
    case NodeType::Cone: {
        ConeParams p{uniform(0.0, 20.0), uniform(0.0, 20.0), uniform(1.0, 40.0)};
        if (chance(0.2)) p.radiusTop = 0.0;
        if (p.radiusBottom == 0.0 && p.radiusTop == 0.0) p.radiusBottom = 5.0;
        n.params = p;
        break;
    }
    case NodeType::Torus: n.params = TorusParams{uniform(2.0, 20.0), uniform(0.5, 10.0)}; break;
    case NodeType::Extrude: {
        const double radius = uniform(3.0, 25.0); // before the count: GCC's order (see transform())
        const int points = integer(3, 12);
        n.params = ExtrudeParams{simplePolygon(points, radius), uniform(1.0, 40.0)};
        break;
    }
    case NodeType::Halfspace: {
        glm::dvec3 normal = vec(-1.0, 1.0);
        if (glm::length(normal) < 0.1) normal = {0, 0, 1};
        n.params = HalfspaceParams{glm::normalize(normal), uniform(-10.0, 10.0)};
        break;
    }
    default: break;
    }
    n.transform = transform(15.0);
    return n;
}

NodeType RandomShapes::randomBoundedPrimitiveType()
{
    static const NodeType kinds[] = {NodeType::Box, NodeType::Sphere, NodeType::Cylinder,
                                     NodeType::Cone, NodeType::Torus, NodeType::Extrude};
    return kinds[integer(0, 5)];
}

Node RandomShapes::operation(NodeType type)
{
    Node n = makeNode(type, nextId());
    const int children = isBoolean(type) ? integer(1, 3) : 1;
    for (int i = 0; i < children; ++i) n.children.push_back(primitive(randomBoundedPrimitiveType()));
    switch (type) {
    case NodeType::Union:
    case NodeType::Intersection:
    case NodeType::Difference: {
        // Exact booleans, tiny blends and large ones.
        const int which = integer(0, 3);
        const double blend = which == 0 ? 0.0 : which == 1 ? uniform(1e-6, 1e-2) : uniform(0.5, 20.0);
        n.params = BooleanParams{blend};
        break;
    }
    case NodeType::Offset: n.params = OffsetParams{uniform(-3.0, 8.0)}; break;
    case NodeType::Shell: n.params = ShellParams{uniform(0.2, 6.0)}; break;
    case NodeType::Array:
        n.params = ArrayParams{{integer(1, 4), integer(1, 3), integer(1, 2)}, vec(-30.0, 30.0)};
        break;
    case NodeType::Mirror: {
        glm::dvec3 normal = vec(-1.0, 1.0);
        if (glm::length(normal) < 0.1) normal = {1, 0, 0};
        n.params = MirrorParams{glm::normalize(normal), uniform(-10.0, 10.0)};
        break;
    }
    default: break;
    }
    n.transform = transform(10.0);
    return n;
}

Node RandomShapes::tree(int depth)
{
    if (depth <= 0 || chance(0.25)) return primitive(randomBoundedPrimitiveType());
    static const NodeType ops[] = {NodeType::Union, NodeType::Intersection, NodeType::Difference, NodeType::Offset,
                                   NodeType::Shell, NodeType::Array, NodeType::Mirror};
    const NodeType type = ops[integer(0, 6)];
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
