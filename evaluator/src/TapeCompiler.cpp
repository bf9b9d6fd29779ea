#include "kerf/evaluator/TapeCompiler.hpp"

#include "kerf/evaluator/Primitives.hpp"

#include "kerf/document/NodeBounds.hpp"

#include <glm/glm.hpp>

#include <functional>
#include <unordered_map>
#include <unordered_set>

namespace kerf {

namespace {

// A blend radius too small to matter is no blend: below a thousandth of the
// smallest feature size the format allows, its fillet (a quarter of the
// radius deep) is far below anything a voxel or a mesh shows, and one of
// 5e-324 mm made 1/k infinite, every value NaN, and an export "empty".
constexpr double kNegligibleBlend = 1e-9; // mm
double effectiveBlend(double k) { return k < kNegligibleBlend ? 0.0 : k; }


class Compiler {
public:
    explicit Compiler(FeatureRegistry* registry = nullptr) : registry_(registry) {}

    Tape compile(const Node& root, const std::optional<Bounds3>& clip, const Aabb& bounds)
    {
        features_ = std::make_shared<std::vector<Feature>>();
        if (registry_) {
            // Every feature ever registered keeps its slot (and its name).
            features_->resize(registry_->ids.size());
            for (std::size_t i = 0; i < registry_->ids.size(); ++i) (*features_)[i].nodeId = registry_->ids[i];
        }
        markSolidSubtrees(root);
        const bool any = emitNode(root, Affine{}, std::nullopt);
        if (any && clip) {
            // The solid is the root's solid intersected with the bounds box.
            Node box;
            box.id = root.id;
            box.type = NodeType::Box;
            box.params = BoxParams{clip->max - clip->min, 0.0};
            box.transform.translate = 0.5 * (clip->min + clip->max);
            emitNode(box, Affine{}, root.color);
            push(Op::Max);
        }
        return Tape::assemble(std::move(code_), std::move(shapes_), features_, glm::dvec3(0.0), bounds);
    }

private:
    void push(Op op, double k = 0.0)
    {
        Instruction ins;
        ins.op = op;
        ins.k = k;
        code_.push_back(ins);
    }

    std::uint32_t featureFor(const Node& n, const std::optional<Color>& color)
    {
        if (registry_) {
            auto [it, added] = registry_->index.emplace(n.id, std::uint32_t(registry_->ids.size()));
            if (added) registry_->ids.push_back(n.id);
            const std::uint32_t idx = it->second;
            if (features_->size() <= idx) {
                const std::size_t old = features_->size();
                features_->resize(idx + 1);
                for (std::size_t i = old; i <= idx; ++i) (*features_)[i].nodeId = registry_->ids[i];
            }
            auto& f = (*features_)[idx];
            f.hasColor = color.has_value();
            if (color) f.color = *color;
            return idx;
        }
        const auto it = featureIndex_.find(n.id);
        if (it != featureIndex_.end()) return it->second;
        Feature f;
        f.nodeId = n.id;
        f.hasColor = color.has_value();
        if (color) f.color = *color;
        features_->push_back(f);
        const auto idx = static_cast<std::uint32_t>(features_->size() - 1);
        featureIndex_[n.id] = idx;
        return idx;
    }

    void emitPrimitive(const Node& n, const Affine& worldFromLocal, const std::optional<Color>& color)
    {
        ShapeInstance s;
        s.feature = featureFor(n, color);
        s.worldToLocal = worldFromLocal.inverseOrthogonal();
        Node self = n;
        self.transform = Transform{};
        s.worldBounds = worldFromLocal.apply(nodeBounds(self));
        packPrimitive(n, s);
        shapes_.push_back(std::move(s));
        Instruction ins;
        ins.op = Op::Primitive;
        ins.shape = static_cast<std::uint32_t>(shapes_.size() - 1);
        code_.push_back(ins);
    }

    // Emits `count` operands combined by an exact, associative op as a
    // balanced tree. emitOne(i) returns false when operand i is empty.
    bool emitBalanced(std::size_t lo, std::size_t hi, Op op, const std::function<bool(std::size_t)>& emitOne)
    {
        if (hi - lo == 1) return emitOne(lo);
        const std::size_t mid = lo + (hi - lo) / 2;
        const bool left = emitBalanced(lo, mid, op, emitOne);
        const bool right = emitBalanced(mid, hi, op, emitOne);
        if (left && right) push(op);
        return left || right;
    }

    // Rolls the tape back to a mark (an intersection with an empty operand).
    struct Mark {
        std::size_t code, shapes;
    };
    Mark mark() const { return {code_.size(), shapes_.size()}; }
    void rollback(Mark m)
    {
        code_.resize(m.code);
        shapes_.resize(m.shapes);
    }

    // Records which nodes have a visible primitive below them, so that
    // emitNode skips whatever holds nothing at once: an array of a million
    // copies of a hidden node costs one step, not a million. Recursion depth
    // is the tree's, which the loader bounds (limits::kMaxNestingDepth).
    bool markSolidSubtrees(const Node& n)
    {
        if (!n.visible) return false;
        bool any = isPrimitive(n.type);
        for (const auto& c : n.children) any = markSolidSubtrees(c) || any;
        if (any) solid_.insert(&n);
        return any;
    }

    // Emits the node's field; returns false (and emits nothing) when empty.
    bool emitNode(const Node& n, const Affine& worldFromParent, std::optional<Color> color)
    {
        if (!n.visible || (!isPrimitive(n.type) && !solid_.count(&n))) return false;
        if (n.color) color = n.color;
        const Affine frame = worldFromParent * Affine::fromTransform(n.transform);
        if (isPrimitive(n.type)) {
            emitPrimitive(n, frame, color);
            return true;
        }
        std::vector<const Node*> kids;
        for (const auto& c : n.children)
            if (c.visible) kids.push_back(&c);
        if (kids.empty()) return false;
        auto emitChild = [&](std::size_t i) { return emitNode(*kids[i], frame, color); };

        switch (n.type) {
        case NodeType::Union: {
            const double k = effectiveBlend(n.as<BooleanParams>().blend);
            if (k == 0.0) return emitBalanced(0, kids.size(), Op::Min, emitChild);
            bool any = false;
            for (std::size_t i = 0; i < kids.size(); ++i) {
                const bool got = emitChild(i);
                if (got && any) push(Op::SmoothMin, k);
                any = any || got;
            }
            return any;
        }
        case NodeType::Intersection: {
            const double k = effectiveBlend(n.as<BooleanParams>().blend);
            const Mark m = mark();
            bool ok = true;
            if (k == 0.0) {
                emitBalanced(0, kids.size(), Op::Max, [&](std::size_t i) {
                    const bool got = ok && emitChild(i);
                    ok = ok && got;
                    return got;
                });
            } else {
                for (std::size_t i = 0; i < kids.size() && ok; ++i) {
                    ok = emitChild(i);
                    if (ok && i > 0) push(Op::SmoothMax, k);
                }
            }
            if (!ok) rollback(m);
            return ok;
        }
        case NodeType::Difference: {
            const double k = effectiveBlend(n.as<BooleanParams>().blend);
            if (!emitChild(0)) return false;
            if (kids.size() == 1) return true;
            if (k == 0.0) {
                // max(a, -b1, -b2, ...) = max(a, -min(b1, b2, ...)).
                if (emitBalanced(1, kids.size(), Op::Min, emitChild)) {
                    push(Op::Negate);
                    push(Op::Max);
                }
                return true;
            }
            for (std::size_t i = 1; i < kids.size(); ++i) {
                if (!emitChild(i)) continue;
                push(Op::Negate);
                push(Op::SmoothMax, k);
            }
            return true;
        }
        case NodeType::Offset:
            if (!emitChild(0)) return false;
            push(Op::Offset, n.as<OffsetParams>().distance);
            return true;
        case NodeType::Shell:
            if (!emitChild(0)) return false;
            push(Op::Shell, n.as<ShellParams>().thickness);
            return true;
        case NodeType::Array: {
            const auto& a = n.as<ArrayParams>();
            const auto nx = static_cast<std::size_t>(a.count[0]), ny = static_cast<std::size_t>(a.count[1]),
                       nz = static_cast<std::size_t>(a.count[2]);
            // Child's own transform, then the copy's offset, then the array's transform.
            return emitBalanced(0, nx * ny * nz, Op::Min, [&](std::size_t idx) {
                const double i = static_cast<double>(idx % nx), j = static_cast<double>((idx / nx) % ny),
                             k = static_cast<double>(idx / (nx * ny));
                const Affine copy = frame * Affine::translate(glm::dvec3(i, j, k) * a.step);
                return emitNode(*kids[0], copy, color);
            });
        }
        case NodeType::Mirror: {
            const auto& m = n.as<MirrorParams>();
            const Affine reflect = Affine::reflection(m.normal, m.offset);
            return emitBalanced(0, 2, Op::Min, [&](std::size_t idx) {
                return emitNode(*kids[0], idx == 0 ? frame : frame * reflect, color);
            });
        }
        default: return false;
        }
    }

    std::vector<Instruction> code_;
    std::vector<ShapeInstance> shapes_;
    std::shared_ptr<std::vector<Feature>> features_;
    std::unordered_map<std::string, std::uint32_t> featureIndex_;
    std::unordered_set<const Node*> solid_;
    FeatureRegistry* registry_ = nullptr;
};

} // namespace

Tape compileTape(const Document& doc, FeatureRegistry* registry)
{
    return Compiler(registry).compile(doc.root, doc.settings.bounds, partBounds(doc));
}

Tape compileTape(const Node& node) { return Compiler().compile(node, std::nullopt, nodeBounds(node)); }

} // namespace kerf
