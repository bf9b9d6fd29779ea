// Parsing and validation of Kerf documents. Every refusal in the spec's list
// throws a DocumentError naming the file, the node id and the field; nothing
// outside the Document being built is touched, so a refused load changes
// nothing.

#include "kerf/document/Document.hpp"
#include "kerf/document/DocumentError.hpp"
#include "kerf/document/Expansion.hpp"
#include "kerf/document/GroupedNumber.hpp"
#include "kerf/document/Limits.hpp"
#include "kerf/document/NodeBounds.hpp"
#include "kerf/document/NodeTypes.hpp"

#include "BoundedJsonParser.hpp"
#include "DocumentFile.hpp"
#include "JsonMembers.hpp"
#include "ResolveExpressions.hpp"

#include <glm/glm.hpp>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

namespace kerf {

namespace {

// "a box", "an array", "an offset": a type's name with its article.
std::string withArticle(const std::string& typeName)
{
    // By the sound: "an offset", "a union" (a "you" sound).
    const bool vowel = !typeName.empty() && std::string_view("aeiou").find(typeName[0]) != std::string_view::npos &&
                       !typeName.starts_with("uni");
    return (vowel ? "an " : "a ") + typeName;
}

std::string describeKind(const Json& v)
{
    switch (v.type()) {
    case Json::value_t::null: return "null";
    case Json::value_t::boolean: return "a boolean";
    case Json::value_t::string: return "a string";
    case Json::value_t::array: return "an array";
    case Json::value_t::object: return "an object";
    case Json::value_t::number_float: return "a number with a fraction";
    default: return "a number";
    }
}

std::string formatNumber(double v) { return formatFieldNumber(v); }

// What a file that is not JSON looks like, from its first bytes: "is a PNG
// image", "starts with the text 'solid chair'".
std::string describeContent(std::string_view head)
{
    const auto startsWith = [&](std::string_view magic) { return head.starts_with(magic); };
    if (startsWith("\x89PNG")) return "is a PNG image";
    if (startsWith("\xFF\xD8\xFF")) return "is a JPEG image";
    if (startsWith("%PDF")) return "is a PDF document";
    if (startsWith("PK\x03\x04")) return "is a ZIP archive (a 3MF file is one: Kerf reads meshes as reference meshes)";
    if (startsWith("solid"))
        return "looks like an ASCII STL mesh (Kerf shows meshes beside the part: Add > Reference Mesh)";
    // Binary STL: an 80-byte header (any text: Kerf's own says "binary STL
    // file"), a triangle count, 50 bytes a triangle. Its header read as text
    // told a newcomer nothing.
    if (head.size() >= 84) {
        std::uint32_t triangles = 0;
        std::memcpy(&triangles, head.data() + 80, sizeof triangles);
        if (84 + 50 * std::uint64_t(triangles) == head.size())
            return "is a binary STL mesh of " + grouped(triangles) + (triangles == 1 ? " triangle" : " triangles") +
                   " (Kerf shows meshes beside the part: Add > Reference Mesh)";
    }
    std::string shown;
    for (const char c : head.substr(0, 24)) {
        const auto u = static_cast<unsigned char>(c);
        if (u < 0x20 || u >= 0x7F) {
            if (c == '\n' || c == '\r' || c == '\t') break;
            return "holds binary data";
        }
        shown += c;
    }
    return "starts with the text '" + shown + (head.size() > shown.size() ? "...'" : "'");
}

class Reader {
public:
    Reader(std::string file, const ParameterOverrides& overrides) : file_(std::move(file)), overrides_(overrides) {}

    Document read(std::string_view text)
    {
        if (text.empty()) fail("", "", "the file is empty (a Kerf document is a JSON object)");
        // Something else altogether (an image, a mesh, a note): said so, not
        // as the parser's "syntax error ... last read: '\x89'".
        const std::size_t first = text.find_first_not_of(" \t\r\n", text.starts_with("\xEF\xBB\xBF") ? 3 : 0);
        if (first != std::string_view::npos && text[first] != '{' && text[first] != '[' && text[first] != '"' &&
            !(text[first] >= '0' && text[first] <= '9') && text[first] != '-' && !text.substr(first).starts_with("true") &&
            !text.substr(first).starts_with("false") && !text.substr(first).starts_with("null"))
            fail("", "", "not a Kerf document: a Kerf document is JSON text, '{ \"format\": \"kerf\", ... }', and this " +
                             describeContent(text.substr(first)));
        Json j = parseJson(text);
        if (!j.is_object()) fail("", "", "a Kerf document is a JSON object, this is " + describeKind(j));
        if (markedNumbers_) refuseNonFinite(j);
        // Expressions first: every check below then sees their numbers.
        const detail::ResolvedExpressions resolved = detail::resolveExpressions(j, file_, overrides_);
        try {
            Document doc = readResolved(j);
            doc.parameters = resolved.parameters;
            attachExpressions(doc, resolved.sites);
            return doc;
        } catch (const DocumentError& e) {
            // A value refused for its range names the expression that gave it.
            for (const detail::ExpressionSite& s : resolved.sites)
                if (s.nodeId == e.nodeId() && s.path == e.field())
                    throw DocumentError(e.file(), e.nodeId(), e.field(),
                                        e.reason() + " (the expression \"" + s.text + "\" gives " + formatNumber(s.value) + ")");
            throw;
        }
    }

private:
    Document readResolved(const Json& j)
    {

        Document doc;
        const Json* format = member(j, "format");
        if (!format) fail("", "format", "missing (a Kerf document starts with \"format\": \"kerf\")");
        if (!format->is_string() || format->get<std::string>() != "kerf")
            fail("", "format", "must be the string \"kerf\", not " + format->dump());
        const Json* version = member(j, "version");
        if (!version) fail("", "version", "missing");
        const std::int64_t v = integer(*version, "", "version");
        if (v > kFormatVersion)
            fail("", "version",
                 "version " + std::to_string(v) + " is newer than this Kerf understands (" +
                     std::to_string(kFormatVersion) + "); update Kerf to open it");
        if (v < 1) fail("", "version", "must be 1, not " + std::to_string(v));
        if (const Json* units = member(j, "units")) {
            if (!units->is_string() || units->get<std::string>() != "mm")
                fail("", "units", "only \"mm\" is allowed in version 1, not " + units->dump());
            doc.units = "mm";
        }
        if (const Json* name = member(j, "name")) doc.name = string(*name, "", "name");
        if (const Json* settings = member(j, "settings")) readSettings(*settings, doc.settings);
        const Json* root = member(j, "root");
        if (!root) fail("", "root", "missing (the feature tree)");
        doc.root = readNode(*root, "root");
        if (const Json* meshes = member(j, "meshes")) readMeshes(*meshes, doc.meshes);

        static const std::unordered_set<std::string> known = {"format", "version", "units", "name",
                                                              "settings", "root", "meshes", "parameters"};
        for (auto it = j.begin(); it != j.end(); ++it)
            if (!known.count(it.key())) appendMember(doc.extra, it.key(), it.value());

        checkWholeTree(doc);
        return doc;
    }

    static void attachExpressions(Document& doc, const std::vector<detail::ExpressionSite>& sites)
    {
        if (sites.empty()) return;
        std::unordered_map<std::string, Node*> byId;
        std::vector<Node*> stack{&doc.root};
        while (!stack.empty()) {
            Node* n = stack.back();
            stack.pop_back();
            byId.emplace(n->id, n);
            for (Node& c : n->children) stack.push_back(&c);
        }
        for (const detail::ExpressionSite& s : sites)
            if (const auto it = byId.find(s.nodeId); it != byId.end()) it->second->expressions[s.path] = s.text;
    }

    [[noreturn]] void fail(const std::string& nodeId, const std::string& field, const std::string& reason) const
    {
        throw DocumentError(file_, nodeId, field, reason);
    }

    // One pass, bounded in depth, linear in the text (BoundedJsonParser.hpp).
    Json parseJson(std::string_view text)
    {
        detail::JsonRefusal refusal;
        std::optional<Json> j = detail::parseBoundedJson(text, refusal, markedNumbers_);
        if (!j) fail(refusal.nodeId, refusal.field, refusal.reason);
        return std::move(*j);
    }

    // Finds a number marked by the parser and refuses it, naming the nearest
    // enclosing node (an object with a string id) and the path from there.
    // Iterative: the tree's depth is bounded, but nothing here needs to recurse.
    void refuseNonFinite(const Json& top) const
    {
        struct Item {
            const Json* value;
            std::string nodeId, path;
        };
        std::vector<Item> stack{{&top, "", ""}};
        while (!stack.empty()) {
            Item item = std::move(stack.back());
            stack.pop_back();
            const Json& j = *item.value;
            if (j.is_string()) {
                const auto& s = j.get_ref<const std::string&>();
                if (s.rfind(detail::kNonFiniteMarker, 0) == 0)
                    fail(item.nodeId, item.path,
                         "must be a finite number, not " + s.substr(detail::kNonFiniteMarker.size()));
            } else if (j.is_array()) {
                for (std::size_t i = j.size(); i-- > 0;)
                    stack.push_back({&j[i], item.nodeId, item.path + "[" + std::to_string(i) + "]"});
            } else if (j.is_object()) {
                const auto id = j.find("id");
                const bool isNode = id != j.end() && id->is_string();
                std::vector<Item> members;
                for (auto it = j.begin(); it != j.end(); ++it) {
                    if (isNode) members.push_back({&it.value(), id->get<std::string>(), it.key()});
                    else members.push_back({&it.value(), item.nodeId, item.path.empty() ? it.key() : item.path + "." + it.key()});
                }
                // Visit in file order: the first marked number is the one named.
                stack.insert(stack.end(), std::make_move_iterator(members.rbegin()), std::make_move_iterator(members.rend()));
            }
        }
    }

    static const Json* member(const Json& obj, const char* key)
    {
        const auto it = obj.find(key);
        return it == obj.end() ? nullptr : &*it;
    }

    const Json& required(const Json& obj, const char* key, const std::string& nodeId) const
    {
        const Json* v = member(obj, key);
        if (!v) fail(nodeId, key, "missing (required)");
        return *v;
    }

    double number(const Json& v, const std::string& nodeId, const std::string& field) const
    {
        if (!v.is_number()) fail(nodeId, field, "must be a number, not " + describeKind(v));
        const double d = v.get<double>();
        if (!std::isfinite(d)) fail(nodeId, field, "must be a finite number");
        return d;
    }

    std::int64_t integer(const Json& v, const std::string& nodeId, const std::string& field) const
    {
        if (v.is_number_integer()) {
            if (v.is_number_unsigned() && v.get<std::uint64_t>() > static_cast<std::uint64_t>(INT64_MAX))
                fail(nodeId, field, "integer out of range");
            return v.get<std::int64_t>();
        }
        if (v.is_number_float())
            fail(nodeId, field, "must be an integer written without a fraction or exponent, not " + v.dump());
        fail(nodeId, field, "must be an integer, not " + describeKind(v));
    }

    std::string string(const Json& v, const std::string& nodeId, const std::string& field) const
    {
        if (!v.is_string()) fail(nodeId, field, "must be a string, not " + describeKind(v));
        return v.get<std::string>();
    }

    // A length or coordinate in mm: finite and at most limits::kMaxLength
    // in magnitude, so that bounds, grids and estimates stay finite.
    double length(const Json& v, const std::string& nodeId, const std::string& field) const
    {
        const double d = number(v, nodeId, field);
        checkLength(d, nodeId, field);
        return d;
    }

    void checkLength(double d, const std::string& nodeId, const std::string& field) const
    {
        if (std::fabs(d) > limits::kMaxLength)
            fail(nodeId, field,
                 "is " + formatNumber(d) + " mm; lengths and coordinates are limited to " +
                     formatNumber(limits::kMaxLength) + " mm (100 km)");
    }

    enum class Quantity { Length, Angle, Direction };

    glm::dvec3 vec3(const Json& v, const std::string& nodeId, const std::string& field,
                    Quantity quantity = Quantity::Length) const
    {
        if (!v.is_array() || v.size() != 3) fail(nodeId, field, "must be an array of 3 numbers");
        glm::dvec3 r;
        for (int i = 0; i < 3; ++i) {
            const std::string f = field + "[" + std::to_string(i) + "]";
            const Json& c = v[static_cast<std::size_t>(i)];
            r[i] = quantity == Quantity::Length ? length(c, nodeId, f) : number(c, nodeId, f);
        }
        return r;
    }

    // The normal made unit length, and the length it had (what offsets
    // along it are divided by). A normal that is already unit length to
    // within rounding is kept exactly as written: normalising it again would
    // move it by an ulp, and a saved document would not load back equal to
    // itself (found by the fuzzer).
    glm::dvec3 unitNormal(const Json& v, const std::string& nodeId, const std::string& field, double& scale) const
    {
        const glm::dvec3 n = vec3(v, nodeId, field, Quantity::Direction);
        const double len = glm::length(n);
        if (!(len > 1e-12)) fail(nodeId, field, "must be a non-zero vector");
        if (!std::isfinite(len)) fail(nodeId, field, "is too large");
        scale = std::fabs(len - 1.0) <= 8.0 * std::numeric_limits<double>::epsilon() ? 1.0 : len;
        return n / scale;
    }

    Transform transform(const Json& v, const std::string& nodeId, const std::string& field) const
    {
        if (!v.is_object()) fail(nodeId, field, "must be an object with \"translate\" and/or \"rotate\"");
        Transform t;
        for (auto it = v.begin(); it != v.end(); ++it) {
            if (it.key() == "translate")
                t.translate = vec3(it.value(), nodeId, field + ".translate");
            else if (it.key() == "rotate")
                t.rotate = vec3(it.value(), nodeId, field + ".rotate", Quantity::Angle);
            else
                appendMember(t.extra, it.key(), it.value());
        }
        return t;
    }

    Color color(const Json& v, const std::string& nodeId) const
    {
        const std::string s = string(v, nodeId, "color");
        const auto c = parseColor(s);
        if (!c) fail(nodeId, "color", "must be \"#rrggbb\", not \"" + s + "\"");
        return *c;
    }

    void readSettings(const Json& s, DocumentSettings& out) const
    {
        if (!s.is_object()) fail("", "settings", "must be an object");
        for (auto it = s.begin(); it != s.end(); ++it) {
            if (it.key() == "feature_size") {
                const double fs = number(it.value(), "", "settings.feature_size");
                if (!(fs > 0.0)) fail("", "settings.feature_size", "must be > 0, not " + formatNumber(fs));
                if (fs < limits::kMinFeatureSize || fs > limits::kMaxFeatureSize)
                    fail("", "settings.feature_size",
                         "must be between " + formatNumber(limits::kMinFeatureSize) + " and " +
                             formatNumber(limits::kMaxFeatureSize) + " mm, not " + formatNumber(fs));
                out.featureSize = fs;
            } else if (it.key() == "bounds") {
                const Json& b = it.value();
                if (!b.is_array() || b.size() != 2)
                    fail("", "settings.bounds", "must be [[xmin,ymin,zmin],[xmax,ymax,zmax]]");
                Bounds3 bounds{vec3(b[0], "", "settings.bounds[0]"), vec3(b[1], "", "settings.bounds[1]")};
                for (int i = 0; i < 3; ++i)
                    if (!(bounds.min[i] < bounds.max[i]))
                        fail("", "settings.bounds", "each minimum must be below its maximum");
                out.bounds = bounds;
            } else {
                appendMember(out.extra, it.key(), it.value());
            }
        }
    }

    void claimId(const std::string& id, const std::string& where) const
    {
        if (id.empty()) fail(where, "id", "must not be empty");
        if (!ids_.insert(id).second) fail(id, "id", "duplicate id: another node or mesh already uses it");
    }

    void readMeshes(const Json& meshes, std::vector<MeshReference>& out) const
    {
        if (!meshes.is_array()) fail("", "meshes", "must be an array");
        for (std::size_t i = 0; i < meshes.size(); ++i) {
            const Json& m = meshes[i];
            const std::string where = "meshes[" + std::to_string(i) + "]";
            if (!m.is_object()) fail("", where, "must be an object");
            MeshReference ref;
            const Json* id = member(m, "id");
            if (!id) fail("", where + ".id", "missing (required)");
            ref.id = string(*id, "", where + ".id");
            claimId(ref.id, "");
            ref.path = string(required(m, "path", ref.id), ref.id, "path");
            if (ref.path.empty()) fail(ref.id, "path", "must not be empty");
            for (auto it = m.begin(); it != m.end(); ++it) {
                const std::string& k = it.key();
                if (k == "id" || k == "path") continue;
                if (k == "transform")
                    ref.transform = transform(it.value(), ref.id, "transform");
                else if (k == "color")
                    ref.color = color(it.value(), ref.id);
                else
                    appendMember(ref.extra, k, it.value());
            }
            out.push_back(std::move(ref));
        }
    }

    Node readNode(const Json& j, const std::string& where)
    {
        if (!j.is_object()) fail("", where, "a node must be an object, not " + describeKind(j));
        Node n;
        const Json* id = member(j, "id");
        if (!id) fail("", where + ".id", "missing (every node needs a unique id)");
        n.id = string(*id, "", where + ".id");
        claimId(n.id, where);
        const Json* type = member(j, "type");
        if (!type) fail(n.id, "type", "missing (required)");
        const std::string typeName = string(*type, n.id, "type");
        const auto t = nodeTypeFromName(typeName);
        if (!t) fail(n.id, "type", "unknown type '" + typeName + "'");
        n.type = *t;

        std::unordered_set<std::string> used = {"id", "type", "name", "transform", "visible", "color", "children"};
        if (const Json* v = member(j, "name")) n.name = string(*v, n.id, "name");
        if (const Json* v = member(j, "transform")) n.transform = transform(*v, n.id, "transform");
        if (const Json* v = member(j, "visible")) {
            if (!v->is_boolean()) fail(n.id, "visible", "must be true or false, not " + describeKind(*v));
            n.visible = v->get<bool>();
        }
        if (const Json* v = member(j, "color")) n.color = color(*v, n.id);

        readParams(j, n, used);

        const Json* children = member(j, "children");
        if (isPrimitive(n.type)) {
            if (children) fail(n.id, "children", withArticle(typeName) + " is a primitive and has no children");
        } else {
            if (!children) fail(n.id, "children", "missing (required)");
            if (!children->is_array()) fail(n.id, "children", "must be an array of nodes");
            const bool single = !isBoolean(n.type);
            // A union at the root may be empty: a new part, saved before
            // its first feature (with its parameters, say). Anywhere else a
            // feature with nothing to act on is refused.
            const bool emptyPart = where == "root" && n.type == NodeType::Union;
            if (children->empty() && !emptyPart)
                fail(n.id, "children", withArticle(typeName) + " needs at least 1 child");
            if (single && children->size() != 1)
                fail(n.id, "children",
                     withArticle(typeName) + " takes exactly 1 child, not " + std::to_string(children->size()));
            for (std::size_t i = 0; i < children->size(); ++i)
                n.children.push_back(readNode((*children)[i], n.id + ".children[" + std::to_string(i) + "]"));
        }

        for (auto it = j.begin(); it != j.end(); ++it)
            if (!used.count(it.key())) appendMember(n.extra, it.key(), it.value());
        return n;
    }

    // The node's fields as its type's table row describes them
    // (NodeTypes.hpp): each field's own rules, then the rules across fields.
    void readParams(const Json& j, Node& n, std::unordered_set<std::string>& used) const
    {
        const std::string& id = n.id;
        const NodeTypeSpec& spec = nodeTypeSpec(n.type);
        n.params = spec.defaults;
        double directionLength = 1.0;
        for (const FieldSpec& f : spec.fields) {
            const std::string key(f.key);
            used.insert(key);
            const Json* v = member(j, key.c_str());
            if (!v) {
                if (f.optional) {
                    f.numberIn(n) = f.absent;
                    continue;
                }
                fail(id, key, "missing (required)");
            }
            switch (f.shape) {
            case FieldShape::Number: f.numberIn(n) = bounded(f, *v, id, key); break;
            case FieldShape::Vector: {
                if (!v->is_array() || v->size() != 3) fail(id, key, "must be an array of 3 numbers");
                for (int i = 0; i < 3; ++i)
                    f.vectorIn(n)[i] = bounded(f, (*v)[std::size_t(i)], id, key + "[" + std::to_string(i) + "]");
                break;
            }
            case FieldShape::Direction: f.vectorIn(n) = unitNormal(*v, id, key, directionLength); break;
            case FieldShape::Counts: {
                if (!v->is_array() || v->size() != 3) fail(id, key, "must be an array of 3 integers");
                for (std::size_t i = 0; i < 3; ++i) {
                    const std::string c = key + "[" + std::to_string(i) + "]";
                    const std::int64_t count = integer((*v)[i], id, c);
                    if (double(count) < f.min) fail(id, c, "must be >= " + formatNumber(f.min) + ", not " + std::to_string(count));
                    f.countsIn(n)[i] = count;
                }
                break;
            }
            case FieldShape::Points: f.pointsIn(n) = profile(f, *v, id, key); break;
            }
        }
        // A length along a direction written at another length scales with it.
        for (const FieldSpec& f : spec.fields)
            if (f.alongDirection) {
                f.numberIn(n) /= directionLength;
                checkLength(f.numberIn(n), id, std::string(f.key));
            }
        if (spec.check)
            if (const auto refusal = spec.check(n.params)) fail(id, refusal->field, refusal->reason);
    }

    // One number of a field: a length (or a plain number), at least the field's minimum.
    double bounded(const FieldSpec& f, const Json& v, const std::string& id, const std::string& field) const
    {
        const double d = f.unit == FieldUnit::Length ? length(v, id, field) : number(v, id, field);
        if (f.minExclusive ? !(d > f.min) : d < f.min)
            fail(id, field, std::string(f.minExclusive ? "must be > " : "must be >= ") + formatNumber(f.min) + ", not " +
                                formatNumber(d));
        return d;
    }

    // A profile's points: lengths, the first coordinate at least the field's minimum.
    std::vector<glm::dvec2> profile(const FieldSpec& f, const Json& prof, const std::string& id, const std::string& key) const
    {
        const std::string a(f.pointAxes[0]), b(f.pointAxes[1]);
        if (!prof.is_array()) fail(id, key, "must be an array of [" + a + ", " + b + "] points");
        if (prof.size() > limits::kMaxProfilePoints)
            fail(id, key,
                 "has " + std::to_string(prof.size()) + " points; a profile may have at most " +
                     std::to_string(limits::kMaxProfilePoints));
        std::vector<glm::dvec2> points;
        points.reserve(prof.size());
        for (std::size_t i = 0; i < prof.size(); ++i) {
            const std::string p = key + "[" + std::to_string(i) + "]";
            if (!prof[i].is_array() || prof[i].size() != 2) fail(id, p, "must be an [" + a + ", " + b + "] point");
            const double first = length(prof[i][0], id, p + "[0]");
            if (first < f.min)
                fail(id, p + "[0]",
                     a + " must be >= " + formatNumber(f.min) + " (the profile lies on one side of the axis), not " +
                         formatNumber(first));
            points.emplace_back(first, length(prof[i][1], id, p + "[1]"));
        }
        return points;
    }

    // What the tree expands to and where it lies, checked on the whole tree
    // once every node is read. Hidden nodes count: hiding and showing a node
    // must never turn a valid document into a refused one.
    void checkWholeTree(const Document& doc) const
    {
        checkExpansion(doc.root);
        checkExtent(doc.root);
        if (!nodeBounds(doc.root).isBounded() && !doc.settings.bounds)
            fail(doc.root.id, "settings.bounds",
                 "the part is unbounded (it contains a halfspace that nothing bounds); add settings.bounds");
    }

    static bool tooManyCopies(const Expansion& e)
    {
        return e.primitiveCopies > limits::kMaxPrimitiveCopies ||
               e.profilePointCopies > limits::kMaxProfilePointCopies;
    }

    // Blames the deepest node that is over a limit on its own: the array
    // whose counts multiply past it, not the root above it.
    void checkExpansion(const Node& top) const
    {
        if (!tooManyCopies(expansionOf(top, true))) return;
        const Node* n = &top;
        for (bool descended = true; descended;) {
            descended = false;
            for (const auto& c : n->children)
                if (tooManyCopies(expansionOf(c, true))) {
                    n = &c;
                    descended = true;
                    break;
                }
        }
        const Expansion e = expansionOf(*n, true);
        const std::string field = n->type == NodeType::Array ? "count" : "children";
        auto count = [](std::uint64_t v) {
            return v == UINT64_MAX ? std::string("more than 18 billion billion") : grouped(v);
        };
        if (e.primitiveCopies > limits::kMaxPrimitiveCopies)
            fail(n->id, field,
                 "expands to " + count(e.primitiveCopies) + " primitive copies (hidden ones included), more than the " +
                     grouped(limits::kMaxPrimitiveCopies) + " a document may have");
        fail(n->id, field,
             "expands to " + count(e.profilePointCopies) + " profile points (extrude, revolve) over all copies, more than the " +
                 grouped(limits::kMaxProfilePointCopies) + " a document may have");
    }

    static bool beyondExtent(const Aabb& b)
    {
        if (b.isEmpty()) return false;
        for (int i = 0; i < 3; ++i)
            for (const double v : {b.min[i], b.max[i]})
                if (std::isfinite(v) ? std::fabs(v) > limits::kMaxExtent : std::isnan(v)) return true;
        return false;
    }

    // Each length is limited on its own; arrays, mirrors and nested
    // transforms can still carry the part far away. Blames the deepest node
    // whose bounds reach past the limit while its children's do not.
    void checkExtent(const Node& top) const
    {
        if (!beyondExtent(nodeBounds(top, 0.0))) return;
        const Node* n = &top;
        for (bool descended = true; descended;) {
            descended = false;
            for (const auto& c : n->children)
                if (c.visible && beyondExtent(nodeBounds(c, 0.0))) {
                    n = &c;
                    descended = true;
                    break;
                }
        }
        const char* field = n->type == NodeType::Array      ? "step"
                             : n->type == NodeType::Mirror  ? "offset"
                             : n->type == NodeType::Offset  ? "distance"
                             : n->type == NodeType::Union   ? "blend"
                                                            : "transform";
        fail(n->id, field,
             "places the part more than " + formatNumber(limits::kMaxExtent) +
                 " mm (1000 km) from the origin, the format's limit");
    }

    std::string file_;
    const ParameterOverrides& overrides_;
    bool markedNumbers_ = false;
    mutable std::unordered_set<std::string> ids_;
};

} // namespace

Document Document::parse(std::string_view text, const std::string& sourceName, const ParameterOverrides& overrides)
{
    return Reader(sourceName, overrides).read(text);
}

Document Document::load(const std::filesystem::path& file, const ParameterOverrides& overrides)
{
    return parse(detail::readDocumentFile(file), file.string(), overrides);
}

Document Document::resolved(const std::string& sourceName) const { return parse(serialize(), sourceName); }

bool Document::hasExpressions() const
{
    if (!parameters.empty()) return true;
    std::vector<const Node*> stack{&root};
    while (!stack.empty()) {
        const Node* n = stack.back();
        stack.pop_back();
        if (!n->expressions.empty()) return true;
        for (const Node& c : n->children) stack.push_back(&c);
    }
    return false;
}

void Document::validate(const std::string& sourceName) const
{
    // The in-memory document goes through exactly the checks a file does.
    (void)parse(serialize(), sourceName);
}

} // namespace kerf
