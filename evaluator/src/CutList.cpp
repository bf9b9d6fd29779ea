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
#include <optional>

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
            const std::size_t first = bodies_.size();
            for (const Node* c : kids) collect(*c, world, scope);
            joinTenons(first, scope.quantity);
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

    std::vector<CutListRow> rows() const
    {
        std::vector<CutListRow> out;
        for (const Body& b : bodies_)
            if (!b.joined) out.push_back(b.row);
        return out;
    }

private:
    // A body as measured: its row, and what a later join needs (its solid
    // in its own frame, where that frame lies, its tight bounds there).
    struct Body {
        CutListRow row;
        Node solid;           // with its cuts and clips, in its own frame
        Affine worldFromLocal;
        Aabb local;           // tight outer bounds in its own frame
        Aabb world;           // a box around it in the world (for the pairing)
        bool joined = false;  // joined to another body's stock (a tenon)
    };

    // Where `b` lies in another body's frame, as a tight box.
    std::optional<Aabb> boundsIn(const Body& b, const Affine& localFromWorld) const
    {
        Node placed = b.solid;
        placed.transform = transformFromAffine(localFromWorld * b.worldFromLocal);
        const auto tb = tightBounds(compileTape(placed), tolerance_);
        if (!tb) return std::nullopt;
        return tb->outer;
    }

    // Whether `tenon` (its tight box `t` in the frame of `board`, whose own
    // box is `a`) is part of board's stock: it touches or overlaps the board
    // along the board's length, reaches beyond one end, and lies within the
    // board's cross-section, filling at least a quarter of its thickness and
    // half of its width. A tenon, a round tenon on a turned leg, a horn; not
    // a dowel (too thin for the board's width), not a leg or apron butted
    // against it (wider than its section), not a shelf in a housing (it
    // leaves the board across its thickness).
    bool isTenonOf(const Aabb& a, const Aabb& t) const
    {
        const glm::dvec3 size = a.size();
        int axes[3] = {0, 1, 2};
        std::sort(axes, axes + 3, [&](int i, int j) { return size[i] > size[j]; });
        const int along = axes[0], across = axes[1], through = axes[2];
        const double slack = std::max(tolerance_, 1e-6 * glm::length(size));
        for (const int s : {across, through})
            if (t.min[s] < a.min[s] - slack || t.max[s] > a.max[s] + slack) return false;
        if (t.size()[through] < 0.25 * size[through] || t.size()[across] < 0.5 * size[across]) return false;
        const bool touches = t.min[along] <= a.max[along] + slack && t.max[along] >= a.min[along] - slack;
        const bool lengthens = t.max[along] > a.max[along] + slack || t.min[along] < a.min[along] - slack;
        return touches && lengthens && t.size()[along] < size[along];
    }

    // Joins tenons to their boards among the bodies from `first` on, those
    // that a union lists as they are (no array or mirror between: their
    // quantity is the union's). A board's row then measures it with its
    // tenons, and names them.
    void joinTenons(std::size_t first, long quantity)
    {
        std::vector<std::size_t> candidates;
        for (std::size_t i = first; i < bodies_.size(); ++i)
            if (!bodies_[i].joined && !bodies_[i].row.unbounded && bodies_[i].row.quantity == quantity)
                candidates.push_back(i);
        // Furniture joins tens of bodies in a union; a union of thousands
        // (a generated grid) is listed body by body rather than paired.
        if (candidates.size() < 2 || candidates.size() > kMostBodiesPaired) return;
        // Largest stock first: a tenon joins the largest board it belongs to.
        auto volume = [&](std::size_t i) {
            const glm::dvec3 s = bodies_[i].local.size();
            return s.x * s.y * s.z;
        };
        std::stable_sort(candidates.begin(), candidates.end(),
                         [&](std::size_t i, std::size_t j) { return volume(i) > volume(j); });
        std::size_t measured = 0;
        for (const std::size_t board : candidates) {
            Body& a = bodies_[board];
            if (a.joined) continue;
            const Affine localFromWorld = a.worldFromLocal.inverseOrthogonal();
            bool grew = false;
            for (const std::size_t other : candidates) {
                Body& b = bodies_[other];
                if (other == board || b.joined || !(volume(other) < volume(board))) continue;
                if (!overlapsWithin(a.world, b.world, tolerance_)) continue;
                if (++measured > kMostPairsMeasured) break; // bounded time, whatever the document
                const std::optional<Aabb> t = boundsIn(b, localFromWorld);
                if (!t || !isTenonOf(a.local, *t)) continue;
                Node joined = makeNode(NodeType::Union, "cut-list:tenons");
                joined.children.push_back(std::move(a.solid));
                Node placed = b.solid;
                placed.transform = transformFromAffine(localFromWorld * b.worldFromLocal);
                joined.children.push_back(std::move(placed));
                a.solid = std::move(joined);
                a.row.joined.push_back(b.row.name);
                a.row.joined.insert(a.row.joined.end(), b.row.joined.begin(), b.row.joined.end());
                b.joined = true;
                grew = true;
            }
            if (grew) {
                setDimensions(a, tightBounds(compileTape(a.solid), tolerance_));
                a.world = a.worldFromLocal.apply(a.local);
            }
            if (measured > kMostPairsMeasured) return;
        }
    }

    static bool overlapsWithin(const Aabb& a, const Aabb& b, double slack)
    {
        for (int k = 0; k < 3; ++k)
            if (a.min[k] > b.max[k] + slack || b.min[k] > a.max[k] + slack) return false;
        return true;
    }

    static void setDimensions(Body& body, const std::optional<TightBounds>& tb)
    {
        if (!tb) return;
        body.local = tb->outer;
        std::array<double, 3> d = {tb->outer.size().x, tb->outer.size().y, tb->outer.size().z};
        std::sort(d.begin(), d.end(), std::greater<>());
        body.row.length = d[0];
        body.row.width = d[1];
        body.row.thickness = d[2];
        body.row.uncertainty = tb->uncertainty();
    }

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
        Body body;
        body.row.nodeId = n.id;
        body.row.name = n.name ? *n.name : scope.labelledBy ? *scope.labelledBy->name : nameOfBase(n);
        body.row.quantity = scope.quantity;
        if (!tape.bounds().isBounded()) {
            body.row.unbounded = true;
            bodies_.push_back(std::move(body));
            return;
        }
        const auto tb = tightBounds(tape, tolerance_);
        if (!tb) return; // empty after its cuts
        setDimensions(body, tb);
        body.worldFromLocal = parentWorld * Affine::fromTransform(n.transform);
        body.world = body.worldFromLocal.apply(body.local);
        body.solid = std::move(solid);
        bodies_.push_back(std::move(body));
    }

    static constexpr std::size_t kMostBodiesPaired = 1000;
    static constexpr std::size_t kMostPairsMeasured = 4000;

    double tolerance_;
    std::vector<Body> bodies_;
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
    return c.rows();
}

std::string cutListName(const CutListRow& row)
{
    if (row.joined.empty()) return row.name;
    std::string s = row.name + (row.joined.size() == 1 ? " (with its tenon: " : " (with its tenons: ");
    for (std::size_t i = 0; i < row.joined.size(); ++i) s += (i ? ", " : "") + row.joined[i];
    return s + ")";
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
        out += csvField(cutListName(r)) + "," + csvField(r.nodeId) + "," + std::to_string(r.quantity) + ",";
        if (r.unbounded)
            out += "unbounded,unbounded,unbounded\r\n";
        else
            out += length(r.length) + "," + length(r.width) + "," + length(r.thickness) + "\r\n";
    }
    return out;
}

} // namespace kerf
