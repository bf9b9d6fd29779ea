#include "kerf/evaluator/CutList.hpp"

#include "kerf/document/Affine.hpp"
#include "kerf/document/Expansion.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/evaluator/TightBounds.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>

namespace kerf {

namespace {

// A node that cuts or clips the bodies below it, with the world placement of
// the frame its own transform is relative to.
struct Operand {
    const Node* node;
    Affine parentWorld;
};

struct Scope {
    std::vector<Operand> cuts;  // subtracted (other children of a difference)
    std::vector<Operand> clips; // intersected (other children of an intersection)
    long quantity = 1;
    // A difference or intersection whose first child this is: the body's
    // label when the body itself has no name ("Side panel, drilled").
    const Node* labelledBy = nullptr;
};

std::vector<const Node*> visibleChildren(const Node& n)
{
    std::vector<const Node*> v;
    for (const auto& c : n.children)
        if (c.visible) v.push_back(&c);
    return v;
}

// An unnamed body's name: the first name on the way down through first
// children (an unnamed offset of a difference of the named board is the
// board, as the woodworker calls it), else its id.
std::string nameOfBase(const Node& body)
{
    for (const Node* n = &body;;) {
        if (n->name) return *n->name;
        const std::vector<const Node*> kids = visibleChildren(*n);
        if (kids.empty()) return body.id;
        n = kids.front();
    }
}

class Collector {
public:
    explicit Collector(double tolerance) : tolerance_(tolerance) {}

    void collect(const Node& n, const Affine& parentWorld, Scope scope)
    {
        if (!n.visible) return;
        const Affine world = parentWorld * Affine::fromTransform(n.transform);
        const std::vector<const Node*> kids = visibleChildren(n);
        // Every boolean reads as an assembly, smooth ones too: the fillet a
        // blend adds is shaping and glue, not stock.
        const bool boolean = isBoolean(n.type);
        if (boolean && !kids.empty() && n.type == NodeType::Union) {
            scope.labelledBy = nullptr; // each child is a body of its own
            for (const Node* c : kids) collect(*c, world, scope);
            return;
        }
        if (boolean && !kids.empty() && n.type != NodeType::Union) {
            auto& into = n.type == NodeType::Difference ? scope.cuts : scope.clips;
            for (std::size_t i = 1; i < kids.size(); ++i) into.push_back({kids[i], world});
            if (n.name) scope.labelledBy = &n;
            collect(*kids.front(), world, scope);
            return;
        }
        if (n.type == NodeType::Array && !kids.empty()) {
            // Saturating: the loader bounds the copies, but no count may wrap.
            const std::uint64_t copies =
                saturatingMultiply(std::uint64_t(scope.quantity), arrayCopies(n.as<ArrayParams>()));
            scope.quantity = long(std::min<std::uint64_t>(copies, std::numeric_limits<long>::max()));
            collect(*kids.front(), world, scope);
            return;
        }
        if (n.type == NodeType::Mirror && !kids.empty()) {
            scope.quantity = long(std::min<std::uint64_t>(saturatingMultiply(std::uint64_t(scope.quantity), 2),
                                                          std::numeric_limits<long>::max()));
            collect(*kids.front(), world, scope);
            return;
        }
        measure(n, parentWorld, scope);
    }

    std::vector<CutListRow> rows;

private:
    // The body `n` with its cuts and clips, in n's local frame.
    void measure(const Node& n, const Affine& parentWorld, const Scope& scope)
    {
        const Affine localFromWorld = (parentWorld * Affine::fromTransform(n.transform)).inverseOrthogonal();
        auto placed = [&](const Operand& o) {
            Node copy = *o.node;
            copy.transform = transformFromAffine(localFromWorld * o.parentWorld * Affine::fromTransform(o.node->transform));
            return copy;
        };
        Node solid = n;
        solid.transform = Transform{};
        if (!scope.clips.empty()) {
            Node clip = makeNode(NodeType::Intersection, "cut-list:clip");
            clip.children.push_back(std::move(solid));
            for (const Operand& o : scope.clips) clip.children.push_back(placed(o));
            solid = std::move(clip);
        }
        if (!scope.cuts.empty()) {
            Node cut = makeNode(NodeType::Difference, "cut-list:cut");
            cut.children.push_back(std::move(solid));
            for (const Operand& o : scope.cuts) cut.children.push_back(placed(o));
            solid = std::move(cut);
        }
        const Tape tape = compileTape(solid);
        if (tape.empty() || tape.bounds().isEmpty()) return;
        CutListRow row;
        row.nodeId = n.id;
        row.name = n.name ? *n.name : scope.labelledBy ? *scope.labelledBy->name : nameOfBase(n);
        row.quantity = scope.quantity;
        if (!tape.bounds().isBounded()) {
            row.unbounded = true;
            rows.push_back(row);
            return;
        }
        const auto tb = tightBounds(tape, tolerance_);
        if (!tb) return; // empty after its cuts
        std::array<double, 3> d = {tb->outer.size().x, tb->outer.size().y, tb->outer.size().z};
        std::sort(d.begin(), d.end(), std::greater<>());
        row.length = d[0];
        row.width = d[1];
        row.thickness = d[2];
        row.uncertainty = tb->uncertainty();
        rows.push_back(row);
    }

    double tolerance_;
};

std::string csvField(const std::string& s)
{
    if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) {
        if (c == '"') q += '"';
        q += c;
    }
    return q + "\"";
}

std::string millimetres(double v)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", v);
    return buf;
}

} // namespace

std::vector<CutListRow> cutList(const Document& doc, double tolerance)
{
    Collector c(tolerance);
    Scope scope;
    // settings.bounds clips every body, as it clips the part.
    Node box;
    if (doc.settings.bounds) {
        const Bounds3& b = *doc.settings.bounds;
        box = makeNode(NodeType::Box, "cut-list:bounds");
        box.as<BoxParams>().size = b.max - b.min;
        box.transform.translate = 0.5 * (b.min + b.max);
        scope.clips.push_back({&box, Affine{}});
    }
    c.collect(doc.root, Affine{}, scope);
    return std::move(c.rows);
}

std::string cutListCsv(const std::vector<CutListRow>& rows, LengthUnit unit)
{
    const bool inches = unit == LengthUnit::Inches;
    auto length = [&](double mm) {
        if (!inches) return millimetres(mm);
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.4f", mm / 25.4);
        return std::string(buf);
    };
    std::string out = inches ? "Part,Id,Quantity,Length (in),Width (in),Thickness (in)\r\n"
                             : "Part,Id,Quantity,Length (mm),Width (mm),Thickness (mm)\r\n";
    for (const auto& r : rows) {
        out += csvField(r.name) + "," + csvField(r.nodeId) + "," + std::to_string(r.quantity) + ",";
        if (r.unbounded)
            out += "unbounded,unbounded,unbounded\r\n";
        else
            out += length(r.length) + "," + length(r.width) + "," + length(r.thickness) + "\r\n";
    }
    return out;
}

} // namespace kerf
