#pragma once
// Seeded random feature trees for property tests: every primitive and
// operation type with random parameters and random placements. The types
// and their fields come from the node type table (NodeTypes.hpp): a new
// type is in every property test without a line here.

#include "kerf/document/Document.hpp"
#include "kerf/document/NodeTypes.hpp"

#include <ostream>
#include <random>

namespace kerf {
/// Readable test names and messages for node types.
inline void PrintTo(NodeType t, std::ostream* os) { *os << nodeTypeName(t); }
} // namespace kerf

namespace kerf::test {

class RandomShapes {
public:
    explicit RandomShapes(std::uint64_t seed) : rng_(seed) {}

    double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
    int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
    bool chance(double p) { return uniform(0.0, 1.0) < p; }
    glm::dvec3 vec(double lo, double hi) { return {uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)}; }
    std::mt19937_64& engine() { return rng_; }

    /// A random placement: translation within +-`reach`, any rotation, or an
    /// axis-aligned one half of the time (exact 90 degree multiples).
    Transform transform(double reach);

    /// Every primitive type, every operation type, the bounded primitives.
    static std::vector<NodeType> primitiveTypes();
    static std::vector<NodeType> operationTypes();
    static std::vector<NodeType> boundedPrimitiveTypes();

    /// A primitive of the given type with random, valid parameters (each
    /// field within its typical range, about 1 to 40 mm).
    Node primitive(NodeType type);
    /// A random simple polygon: a star-shaped one (sorted angles).
    std::vector<glm::dvec2> simplePolygon(int points, double radius);

    /// An operation node of the given type over random primitive children.
    Node operation(NodeType type);

    /// A random tree of the given depth mixing every node type (no halfspace).
    Node tree(int depth);

    /// Wraps a node as the root of a valid document.
    static Document document(Node root);

private:
    std::string nextId() { return "n" + std::to_string(counter_++); }
    NodeType randomBoundedPrimitiveType();
    void fill(const FieldSpec& f, Node& n);
    void fillFields(Node& n);

    std::mt19937_64 rng_;
    int counter_ = 0;
};

} // namespace kerf::test
