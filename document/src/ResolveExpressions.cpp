#include "ResolveExpressions.hpp"

#include "kerf/document/DocumentError.hpp"
#include "kerf/document/Expression.hpp"
#include "kerf/document/GroupedNumber.hpp"
#include "kerf/document/Limits.hpp"
#include "kerf/document/NodeTypes.hpp"
#include "kerf/document/UnknownFields.hpp"

#include "BoundedJsonParser.hpp"
#include "FieldPath.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace kerf::detail {

namespace {

using expr::ExpressionError;
using expr::Quantity;

enum class Dimension : std::uint8_t { Length, Plain }; // what a field or a declared parameter holds

bool isParameterName(const std::string& s)
{
    if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
    for (char c : s)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
    return true;
}

// What a node's number at `keys` holds (its type's table, its transform):
// its dimension, and whether it is a count (written back as an integer).
struct FieldKind {
    Dimension dimension = Dimension::Plain;
    bool count = false;
};
std::optional<FieldKind> fieldKind(const Json& node, const std::vector<std::string>& keys)
{
    if (keys.size() == 2 && keys[0] == "transform") {
        if (keys[1] == "translate") return FieldKind{Dimension::Length, false};
        if (keys[1] == "rotate") return FieldKind{Dimension::Plain, false};
        return std::nullopt;
    }
    if (keys.size() != 1) return std::nullopt;
    const auto type = node.find("type");
    if (type == node.end() || !type->is_string()) return std::nullopt;
    const std::optional<NodeType> t = nodeTypeFromName(type->get<std::string>());
    if (!t) return std::nullopt;
    for (const FieldSpec& f : nodeTypeSpec(*t).fields)
        if (f.key == keys[0])
            return FieldKind{f.unit == FieldUnit::Length ? Dimension::Length : Dimension::Plain,
                             f.shape == FieldShape::Counts};
    return std::nullopt;
}

// Whether a name and an id read the same, case and spaces aside ("Apron"
// and "apron", "Left stile" and "left_stile").
bool sameWords(std::string_view name, std::string_view id)
{
    auto next = [](std::string_view s, std::size_t& i) {
        while (i < s.size() && (s[i] == ' ' || s[i] == '_' || s[i] == '-')) ++i;
        return i < s.size() ? char(std::tolower(static_cast<unsigned char>(s[i++]))) : '\0';
    };
    std::size_t i = 0, j = 0;
    for (;;) {
        const char a = next(name, i), b = next(id, j);
        if (a != b) return false;
        if (a == '\0') return true;
    }
}

Quantity asField(double v, Dimension d) { return d == Dimension::Length ? Quantity::lengthMm(v) : Quantity{v, 0, false}; }

// The value a field left out of the node has: a position or rotation
// component (0), an optional number (its type's `absent`, a union without
// blend: 0). A feature at the origin has a position to refer to like any other.
std::optional<double> leftOutValue(const Json& node, const FieldPath& path)
{
    if (path.keys.size() == 2 && path.keys[0] == "transform")
        return path.indices.size() == 1 && path.indices[0] < 3 ? std::optional<double>(0.0) : std::nullopt;
    if (path.keys.size() != 1 || !path.indices.empty()) return std::nullopt;
    const auto type = node.find("type");
    if (type == node.end() || !type->is_string()) return std::nullopt;
    const std::optional<NodeType> t = nodeTypeFromName(type->get<std::string>());
    const FieldSpec* f = t ? nodeTypeSpec(*t).field(path.keys[0]) : nullptr;
    return f && f->optional && f->shape == FieldShape::Number ? std::optional<double>(f->absent) : std::nullopt;
}

class Resolution {
public:
    Resolution(Json& doc, std::string file, const ParameterOverrides& overrides) : file_(std::move(file))
    {
        readParameters(doc, overrides);
        if (auto root = doc.find("root"); root != doc.end()) collectNodes(*root);
    }

    ResolvedExpressions run()
    {
        for (std::size_t i = 0; i < params_.size(); ++i) parameterValue(i);
        for (const std::string& key : siteOrder_) siteValue(sites_.at(key));
        ResolvedExpressions out;
        for (const Param& p : params_) out.parameters.push_back(p.spec);
        for (const std::string& key : siteOrder_) {
            Site& s = sites_.at(key);
            // The number in the field: an integer where the reader wants one.
            // A count within decimal arithmetic's rounding of a whole number is
            // that number ("(0.1 + 0.2) * 10" gives 3.0000000000000004; a
            // count was refused there, "not 3.0000000000000004 ... gives 3").
            const double whole = std::round(s.value);
            if (s.count && std::fabs(s.value - whole) > kCountRounding * std::max(1.0, std::fabs(whole)))
                fail(s.nodeId, s.path,
                     "is a count, a whole number, and the expression \"" + s.text + "\" gives " +
                         formatFieldNumber(s.value) + " (round(), floor() or ceil() make a whole number of it)");
            if (s.count && std::fabs(whole) >= 9.0e15)
                fail(s.nodeId, s.path,
                     "is a count, and the expression \"" + s.text + "\" gives " + formatFieldNumber(s.value) +
                         (whole > 0.0 ? ", more than the " + grouped(limits::kMaxPrimitiveCopies) +
                                            " primitive copies a document may have"
                                      : ", where a count is 1 or more"));
            if (s.count)
                *s.json = static_cast<std::int64_t>(whole);
            else
                *s.json = s.value;
            out.sites.push_back({s.nodeId, s.path, s.text, s.value});
        }
        return out;
    }

private:
    // How far from a whole number a count's expression may land by rounding
    // alone, relative to the number.
    static constexpr double kCountRounding = 1e-9;
    enum class State : std::uint8_t { Pending, Busy, Done };
    struct Param {
        Parameter spec;
        State state = State::Pending;
        Quantity q;
        std::size_t chain = 0; // the longest chain of references that ends here (1: refers to none)
    };
    struct Site {
        std::string nodeId, path, text;
        Json* json = nullptr;
        Dimension dimension = Dimension::Plain;
        bool count = false;
        State state = State::Pending;
        double value = 0.0;
        std::size_t chain = 0;
    };

    [[noreturn]] void fail(const std::string& nodeId, const std::string& field, const std::string& reason) const
    {
        throw DocumentError(file_, nodeId, field, reason);
    }

    void readParameters(Json& doc, const ParameterOverrides& overrides)
    {
        const auto list = doc.find("parameters");
        if (list != doc.end()) {
            if (!list->is_array()) fail("", "parameters", "must be an array of {\"name\", \"expression\"} objects");
            for (std::size_t i = 0; i < list->size(); ++i) {
                const Json& pj = (*list)[i];
                const std::string where = "parameters[" + std::to_string(i) + "]";
                if (!pj.is_object()) fail("", where, "must be an object with \"name\" and \"expression\"");
                Param p;
                for (auto it = pj.begin(); it != pj.end(); ++it) {
                    const std::string& k = it.key();
                    const Json& v = it.value();
                    if (k == "name") {
                        if (!v.is_string() || !isParameterName(v.get<std::string>()))
                            fail("", where + ".name", "must be a name of letters, digits and _ (not starting with a digit)");
                        p.spec.name = v.get<std::string>();
                    } else if (k == "expression") {
                        if (v.is_string()) p.spec.expression = v.get<std::string>();
                        else if (v.is_number()) p.spec.expression = v.dump();
                        else fail("", where + ".expression", "must be a number or an expression in a string");
                    } else if (k == "comment") {
                        if (!v.is_string()) fail("", where + ".comment", "must be a string");
                        p.spec.comment = v.get<std::string>();
                    } else if (k == "unit") {
                        const std::string u = v.is_string() ? v.get<std::string>() : "";
                        if (u != "length" && u != "angle" && u != "number")
                            fail("", where + ".unit", "must be \"length\", \"angle\" or \"number\"");
                        p.spec.unit = u;
                    } else {
                        p.spec.extra[k] = v;
                    }
                }
                if (p.spec.name.empty()) fail("", where, "has no \"name\"");
                if (!pj.contains("expression")) fail("", "parameters." + p.spec.name, "has no \"expression\"");
                if (byName_.count(p.spec.name)) fail("", "parameters." + p.spec.name, "is defined twice");
                byName_[p.spec.name] = params_.size();
                params_.push_back(std::move(p));
            }
        }
        for (const auto& [name, value] : overrides) {
            const auto it = byName_.find(name);
            if (it == byName_.end()) {
                std::string known;
                for (const Param& p : params_) known += (known.empty() ? "" : ", ") + p.spec.name;
                fail("", "-D " + name, "the document has no parameter '" + name + "'" + didYouMean(name) +
                                           (known.empty() ? " (it has none)" : " (its parameters: " + known + ")"));
            }
            params_[it->second].spec.expression = value;
        }
    }

    // Every node object by id, and every numeric field that holds a string.
    void collectNodes(Json& root)
    {
        std::vector<Json*> stack{&root};
        while (!stack.empty()) {
            Json* n = stack.back();
            stack.pop_back();
            if (!n->is_object()) continue;
            const auto id = n->find("id");
            if (id == n->end() || !id->is_string()) continue; // the reader refuses it
            const std::string nodeId = id->get<std::string>();
            nodes_.emplace(nodeId, n);
            for (auto it = n->begin(); it != n->end(); ++it) {
                if (it.key() == "children" && it->is_array()) {
                    for (auto& c : *it) stack.push_back(&c);
                } else if (it.key() == "transform" && it->is_object()) {
                    for (const char* k : {"translate", "rotate"})
                        if (auto v = it->find(k); v != it->end())
                            collectStrings(*n, nodeId, std::string("transform.") + k, *v, 0);
                } else if (fieldKind(*n, {it.key()})) {
                    collectStrings(*n, nodeId, it.key(), it.value(), 0);
                }
            }
        }
    }

    void collectStrings(const Json& node, const std::string& nodeId, const std::string& path, Json& v, int depth)
    {
        if (v.is_string()) {
            const std::string& text = v.get_ref<const std::string&>();
            if (text.rfind(kNonFiniteMarker, 0) == 0) return; // the reader names it
            const FieldKind kind = *fieldKind(node, parseFieldPath(path)->keys);
            Site s{nodeId, path, text, &v, kind.dimension, kind.count};
            const std::string key = nodeId + "." + path;
            siteOrder_.push_back(key);
            sites_.emplace(key, std::move(s));
        } else if (v.is_array() && depth < 2) {
            for (std::size_t i = 0; i < v.size(); ++i)
                collectStrings(node, nodeId, path + "[" + std::to_string(i) + "]", v[i], depth + 1);
        }
    }

    // ": did you mean 'thickness'?" where a parameter's name is within two
    // edits of the one given (a typo on the command line or in a formula).
    std::string didYouMean(std::string_view name) const
    {
        std::vector<std::string> names;
        for (const Param& p : params_) names.push_back(p.spec.name);
        const std::string closest = closestKnownField(std::string(name), names);
        return closest.empty() ? std::string() : ": did you mean '" + closest + "'?";
    }

    expr::Resolver resolver()
    {
        expr::Resolver r;
        r.name = [this](std::string_view name) {
            const auto it = byName_.find(std::string(name));
            if (it == byName_.end()) {
                std::string known;
                for (const Param& p : params_) known += (known.empty() ? "" : ", ") + p.spec.name;
                throw ExpressionError("uses the unknown name '" + std::string(name) + "'" + didYouMean(name) +
                                      (known.empty() ? " (the document has no parameters)" : " (parameters: " + known + ")"));
            }
            return parameterValue(it->second);
        };
        r.field = [this](std::string_view id, std::string_view path) {
            const auto node = nodes_.find(std::string(id));
            if (node == nodes_.end()) {
                // A feature's name where its id belongs ("=Apron.size[0]"): the
                // application shows names, expressions take ids.
                std::string hint;
                for (const auto& [otherId, other] : nodes_) {
                    const auto name = other->find("name");
                    if (name != other->end() && name->is_string() && sameWords(name->get<std::string>(), id))
                        hint = ": the feature named " + name->get<std::string>() + " has the id '" + otherId +
                               "' (" + otherId + "." + std::string(path) + ")";
                }
                throw ExpressionError("refers to the node '" + std::string(id) + "', which does not exist" + hint);
            }
            const std::optional<FieldPath> fp = parseFieldPath(path);
            const std::optional<FieldKind> kind = fp ? fieldKind(*node->second, fp->keys) : std::nullopt;
            const Json* v = fp && kind ? jsonAt(*node->second, *fp) : nullptr;
            if (!v && fp && kind)
                if (const std::optional<double> left = leftOutValue(*node->second, *fp))
                    return asField(*left, kind->dimension);
            if (!v) throw ExpressionError("refers to '" + std::string(id) + "." + std::string(path) + "', not a number of that node");
            if (const auto s = sites_.find(std::string(id) + "." + std::string(path)); s != sites_.end())
                return asField(siteValue(s->second), kind->dimension);
            if (!v->is_number()) throw ExpressionError("refers to '" + std::string(id) + "." + std::string(path) + "', not a number of that node");
            return asField(v->get<double>(), kind->dimension);
        };
        return r;
    }

    Quantity parameterValue(std::size_t i)
    {
        Param& p = params_[i];
        if (p.state == State::Done) return used(p.chain), p.q;
        const std::string field = "parameters." + p.spec.name;
        if (p.state == State::Busy) fail("", field, "the expression \"" + p.spec.expression + "\" refers back to itself" + chain());
        p.state = State::Busy;
        enter(field);
        trail_.push_back(p.spec.name);
        longest_.push_back(0);
        try {
            Quantity q = expr::evaluate(p.spec.expression, resolver());
            if (p.spec.unit) {
                const bool wantLength = *p.spec.unit == "length";
                if (!q.fits(wantLength))
                    throw ExpressionError(std::string("gives ") + (q.length == 1 ? "a length" : "a value of another unit") +
                                          " where the parameter's unit is " + *p.spec.unit);
                q = wantLength ? Quantity::lengthMm(q.value) : Quantity{q.value, 0, false};
            }
            p.q = q;
        } catch (const ExpressionError& e) {
            fail("", field, "the expression \"" + p.spec.expression + "\" " + e.what());
        }
        p.chain = finishChain("", field);
        trail_.pop_back();
        p.spec.value = p.q.value;
        p.state = State::Done;
        return used(p.chain), p.q;
    }

    double siteValue(Site& s)
    {
        if (s.state == State::Done) return used(s.chain), s.value;
        if (s.state == State::Busy) fail(s.nodeId, s.path, "the expression \"" + s.text + "\" refers back to itself" + chain());
        s.state = State::Busy;
        enter(s.path, s.nodeId);
        trail_.push_back(s.nodeId + "." + s.path);
        longest_.push_back(0);
        try {
            const Quantity q = expr::evaluate(s.text, resolver());
            if (!q.fits(s.dimension == Dimension::Length))
                throw ExpressionError(std::string("is a unit mismatch: it gives ") + (q.length == 1 ? "a length" : q.length == 0 ? "a plain number" : "mm^" + std::to_string(q.length)) +
                                      " where " + (s.dimension == Dimension::Length ? "a length" : "a plain number or angle") + " belongs");
            s.value = q.value;
        } catch (const ExpressionError& e) {
            fail(s.nodeId, s.path, "the expression \"" + s.text + "\" " + e.what());
        }
        s.chain = finishChain(s.nodeId, s.path);
        trail_.pop_back();
        s.state = State::Done;
        return used(s.chain), s.value;
    }

    // References nest as deep as the chain of values they pass through: a
    // bound keeps a hostile file from exhausting the stack.
    void enter(const std::string& field, const std::string& nodeId = "") const
    {
        if (trail_.size() >= kMaxReferenceDepth)
            fail(nodeId, field, "is reached through more than " + std::to_string(kMaxReferenceDepth) +
                                    " references, one through the next, from '" + trail_.front() + "'");
    }
    static constexpr std::size_t kMaxReferenceDepth = 200;

    // The longest chain of references, whatever the order they are met in:
    // the trail above bounds the recursion, but a chain of 300 written in
    // order was resolved one step at a time and passed, and the same chain
    // written backwards was refused. Each value's chain is 1 + the longest
    // of those it uses (longest_: one entry per value being evaluated).
    void used(std::size_t chain)
    {
        if (!longest_.empty()) longest_.back() = std::max(longest_.back(), chain);
    }
    std::size_t finishChain(const std::string& nodeId, const std::string& field)
    {
        const std::size_t chain = longest_.back() + 1;
        longest_.pop_back();
        if (chain > kMaxReferenceDepth)
            fail(nodeId, field, "is reached through more than " + std::to_string(kMaxReferenceDepth) +
                                    " references, one through the next");
        return chain;
    }
    std::vector<std::size_t> longest_;

    std::string chain() const
    {
        std::string c;
        for (const std::string& t : trail_) c += t + " -> ";
        return trail_.empty() ? std::string() : " (" + c + "...)";
    }

    std::string file_;
    std::vector<Param> params_;
    std::unordered_map<std::string, std::size_t> byName_;
    std::unordered_map<std::string, Json*> nodes_;
    std::unordered_map<std::string, Site> sites_;
    std::vector<std::string> siteOrder_;
    std::vector<std::string> trail_;
};

} // namespace

ResolvedExpressions resolveExpressions(Json& j, const std::string& file, const ParameterOverrides& overrides)
{
    return Resolution(j, file, overrides).run();
}

} // namespace kerf::detail
