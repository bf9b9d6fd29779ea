#pragma once
// A feature tree compiled into a flat instruction tape in post-order (a
// stack machine): primitives push a distance, operations pop their operands
// and push the result. Every instruction knows the size of its subtree, so a
// simplifier can drop whole branches by index arithmetic alone.
//
// Coordinates: every evaluator takes points relative to the tape's origin.
// Tapes compiled from a document start at the world origin; rebased() moves
// the origin (for example to a tile's corner), recomputing each primitive's
// placement in double precision, so that float evaluation keeps its precision
// on parts far from the world origin.

#include "kerf/document/Aabb.hpp"
#include "kerf/document/Affine.hpp"
#include "kerf/document/Node.hpp"
#include "kerf/evaluator/PolygonIndex.hpp"
#include "kerf/evaluator/ShapeKinds.h"

#include <glm/vec2.hpp>

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace kerf {

enum class Op : std::uint8_t {
    Primitive, // push distance to shapes[shape]
    Min,       // pop b, a; push min(a, b)
    Max,       // pop b, a; push max(a, b)
    SmoothMin, // polynomial smooth minimum with radius k
    SmoothMax, // -smin(-a, -b) with radius k
    Negate,    // pop a; push -a
    Offset,    // pop a; push a - k
    Shell,     // pop a; push max(a, -(a + k))
};

bool isBinary(Op op);

/// Profile of an extrude or a revolve, shared by every copy of it.
struct Polygon {
    std::vector<glm::dvec2> points;
    std::vector<glm::vec2> pointsF; // the same points in float
    PolygonIndex<glm::dvec2> index; // of points
    PolygonIndex<glm::vec2> indexF; // of pointsF
    glm::dvec2 min{std::numeric_limits<double>::infinity()}, max{-std::numeric_limits<double>::infinity()}; // bounds
};

/// One placed primitive. Parameters are in the primitive's local frame, in
/// millimetres; `worldToLocal` maps world points into that frame.
struct ShapeInstance {
    ShapeKind kind = ShapeKind::Sphere;
    std::uint32_t feature = 0; // index into Tape::features
    /// Kind-specific parameters (see Primitives.hpp for their meaning).
    std::array<double, 6> param{};
    std::array<float, 6> paramF{};
    std::shared_ptr<const Polygon> polygon; // extrude and revolve only
    Affine worldToLocal;
    /// Maps tape-relative points into the local frame: local = m * p + t.
    /// Derived from worldToLocal and the tape's origin in double.
    std::array<double, 12> frame{}; // m (row-major 3x3) then t
    std::array<float, 12> frameF{};
    Aabb worldBounds;
};

struct Instruction {
    Op op = Op::Primitive;
    std::uint32_t span = 1;      // instructions in this subtree, itself included
    std::uint32_t rightSpan = 0; // binary ops: instructions in the right operand's subtree
    std::uint32_t shape = 0;     // Primitive: index into Tape::shapes
    double k = 0.0;              // SmoothMin/SmoothMax: blend; Offset: distance; Shell: thickness
};

/// What a pickable, colourable feature is: one primitive node of the document.
struct Feature {
    std::string nodeId;
    bool hasColor = false;
    Color color; // the node's or its nearest coloured ancestor's
};

class Tape {
public:
    Tape() = default;

    const std::vector<Instruction>& code() const { return code_; }
    const std::vector<ShapeInstance>& shapes() const { return shapes_; }
    const std::vector<Feature>& features() const { return *features_; }
    std::shared_ptr<const std::vector<Feature>> sharedFeatures() const { return features_; }
    /// Deepest evaluation stack the tape needs.
    std::uint32_t maxStack() const { return maxStack_; }
    /// An empty tape is an empty solid: every evaluator returns +infinity.
    bool empty() const { return code_.empty(); }
    std::size_t size() const { return code_.size(); }
    const glm::dvec3& origin() const { return origin_; }
    /// World bounds of the solid the tape describes (empty for an empty tape).
    const Aabb& bounds() const { return bounds_; }

    /// The same field with points measured from `origin` (world coordinates).
    Tape rebased(const glm::dvec3& origin) const;

    /// Builds a tape from instructions in post-order; spans are recomputed and
    /// checked. Used by the compiler and the simplifier.
    static Tape assemble(std::vector<Instruction> code, std::vector<ShapeInstance> shapes,
                         std::shared_ptr<const std::vector<Feature>> features, const glm::dvec3& origin,
                         const Aabb& bounds);

private:
    void computeFrames();

    std::vector<Instruction> code_;
    std::vector<ShapeInstance> shapes_;
    std::shared_ptr<const std::vector<Feature>> features_ = std::make_shared<std::vector<Feature>>();
    std::uint32_t maxStack_ = 0;
    glm::dvec3 origin_{0.0};
    Aabb bounds_;
};

} // namespace kerf
