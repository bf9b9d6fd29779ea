// Parsing and validation of Kerf documents. Every refusal in the spec's list
// throws a DocumentError naming the file, the node id and the field; nothing
// outside the Document being built is touched, so a refused load changes
// nothing.

#include "kerf/document/Document.hpp"
#include "kerf/document/DocumentError.hpp"
#include "kerf/document/NodeBounds.hpp"
#include "kerf/document/ProfileCheck.hpp"

#include <glm/glm.hpp>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <unordered_set>

namespace kerf {

namespace {

/// Expansion limit: an array of arrays can ask for billions of copies; past
/// this many primitive instances the document is refused instead of
/// exhausting memory while compiling.
constexpr std::uint64_t kMaxPrimitiveInstances = 1'000'000;

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

std::string formatNumber(double v)
{
    std::ostringstream s;
    s.precision(12);
    s << v;
    return s.str();
}

class Reader {
public:
    explicit Reader(std::string file) : file_(std::move(file)) {}

    Document read(std::string_view text)
    {
        const Json j = parseJson(text);
        if (!j.is_object()) fail("", "", "a Kerf document is a JSON object, this is " + describeKind(j));
        refuseNonFinite(j, "", "");

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
                                                              "settings", "root", "meshes"};
        for (auto it = j.begin(); it != j.end(); ++it)
            if (!known.count(it.key())) doc.extra[it.key()] = it.value();

        checkWholeTree(doc);
        return doc;
    }

private:
    [[noreturn]] void fail(const std::string& nodeId, const std::string& field, const std::string& reason) const
    {
        throw DocumentError(file_, nodeId, field, reason);
    }

    // The JSON library refuses numbers that overflow a double (1e999) while
    // parsing, before any node or field is known. Such a number is replaced by
    // a marker string and parsing resumes, so that the refusal can name the
    // node and the field like every other one (see number()).
    Json parseJson(std::string_view original) const
    {
        std::string text(original);
        for (int attempt = 0; attempt < 1000; ++attempt) {
            try {
                return Json::parse(text.begin(), text.end());
            } catch (const Json::parse_error& e) {
                fail("", "", "malformed JSON at " + lineColumn(text, e.byte) + ": " + shortParseMessage(e.what()));
            } catch (const Json::out_of_range& e) {
                const std::string what = e.what();
                const auto open = what.find("parsing '");
                const auto close = what.rfind('\'');
                if (e.id != 406 || open == std::string::npos || close <= open + 9) fail("", "", std::string("malformed JSON: ") + e.what());
                const std::string token = what.substr(open + 9, close - open - 9);
                if (!markNonFinite(text, token)) fail("", "", "malformed JSON: number out of range: " + token);
            }
        }
        fail("", "", "malformed JSON: too many out-of-range numbers");
    }

    static constexpr const char* kNonFiniteMarker = "\x01kerf-non-finite-number:";

    // Replaces each standalone occurrence of the number `token` by a marker string.
    static bool markNonFinite(std::string& text, const std::string& token)
    {
        bool replaced = false;
        auto isDelimiter = [](char c) { return c == ',' || c == ':' || c == '[' || c == ']' || c == '{' || c == '}' || std::isspace(static_cast<unsigned char>(c)); };
        for (std::size_t pos = text.find(token); pos != std::string::npos; pos = text.find(token, pos + 1)) {
            const bool before = pos == 0 || isDelimiter(text[pos - 1]);
            const bool after = pos + token.size() == text.size() || isDelimiter(text[pos + token.size()]);
            if (!before || !after) continue;
            const std::string marker = "\"\\u0001kerf-non-finite-number:" + token + "\""; // JSON-escaped kNonFiniteMarker
            text.replace(pos, token.size(), marker);
            pos += marker.size() - 1;
            replaced = true;
        }
        return replaced;
    }

    // Finds a number marked by parseJson and refuses it, naming the nearest
    // enclosing node (an object with a string id) and the path from there.
    void refuseNonFinite(const Json& j, const std::string& nodeId, const std::string& path) const
    {
        if (j.is_string()) {
            const auto& s = j.get_ref<const std::string&>();
            if (s.rfind(kNonFiniteMarker, 0) == 0)
                fail(nodeId, path, "must be a finite number, not " + s.substr(std::strlen(kNonFiniteMarker)));
        } else if (j.is_array()) {
            for (std::size_t i = 0; i < j.size(); ++i) refuseNonFinite(j[i], nodeId, path + "[" + std::to_string(i) + "]");
        } else if (j.is_object()) {
            const auto id = j.find("id");
            const bool isNode = id != j.end() && id->is_string();
            for (auto it = j.begin(); it != j.end(); ++it) {
                if (isNode) refuseNonFinite(it.value(), id->get<std::string>(), it.key());
                else refuseNonFinite(it.value(), nodeId, path.empty() ? it.key() : path + "." + it.key());
            }
        }
    }

    static std::string lineColumn(std::string_view text, std::size_t byte)
    {
        std::size_t line = 1, col = 1;
        for (std::size_t i = 0; i + 1 < byte && i < text.size(); ++i) {
            if (text[i] == '\n') {
                ++line;
                col = 1;
            } else {
                ++col;
            }
        }
        return "line " + std::to_string(line) + ", column " + std::to_string(col);
    }

    static std::string shortParseMessage(const std::string& what)
    {
        // nlohmann: "[json.exception.parse_error.101] parse error at line 1, column 5: syntax error ..."
        const auto pos = what.find("syntax error");
        return pos == std::string::npos ? what : what.substr(pos);
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

    glm::dvec3 vec3(const Json& v, const std::string& nodeId, const std::string& field) const
    {
        if (!v.is_array() || v.size() != 3) fail(nodeId, field, "must be an array of 3 numbers");
        glm::dvec3 r;
        for (int i = 0; i < 3; ++i)
            r[i] = number(v[static_cast<std::size_t>(i)], nodeId, field + "[" + std::to_string(i) + "]");
        return r;
    }

    glm::dvec3 unitNormal(const Json& v, const std::string& nodeId, const std::string& field) const
    {
        const glm::dvec3 n = vec3(v, nodeId, field);
        const double len = glm::length(n);
        if (!(len > 1e-12)) fail(nodeId, field, "must be a non-zero vector");
        if (!std::isfinite(len)) fail(nodeId, field, "is too large");
        return n / len;
    }

    double positive(const Json& obj, const char* key, const std::string& nodeId) const
    {
        const double v = number(required(obj, key, nodeId), nodeId, key);
        if (!(v > 0.0)) fail(nodeId, key, "must be > 0, not " + formatNumber(v));
        return v;
    }

    double nonNegative(const Json& obj, const char* key, const std::string& nodeId, std::optional<double> dflt) const
    {
        const Json* j = member(obj, key);
        if (!j) {
            if (dflt) return *dflt;
            fail(nodeId, key, "missing (required)");
        }
        const double v = number(*j, nodeId, key);
        if (v < 0.0) fail(nodeId, key, "must be >= 0, not " + formatNumber(v));
        return v;
    }

    Transform transform(const Json& v, const std::string& nodeId, const std::string& field) const
    {
        if (!v.is_object()) fail(nodeId, field, "must be an object with \"translate\" and/or \"rotate\"");
        Transform t;
        for (auto it = v.begin(); it != v.end(); ++it) {
            if (it.key() == "translate")
                t.translate = vec3(it.value(), nodeId, field + ".translate");
            else if (it.key() == "rotate")
                t.rotate = vec3(it.value(), nodeId, field + ".rotate");
            else
                t.extra[it.key()] = it.value();
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
                out.extra[it.key()] = it.value();
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
                    ref.extra[k] = it.value();
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
            if (children) fail(n.id, "children", "a " + typeName + " is a primitive and has no children");
        } else {
            if (!children) fail(n.id, "children", "missing (required)");
            if (!children->is_array()) fail(n.id, "children", "must be an array of nodes");
            const bool single = !isBoolean(n.type);
            if (children->empty()) fail(n.id, "children", "a " + typeName + " needs at least 1 child");
            if (single && children->size() != 1)
                fail(n.id, "children",
                     "a " + typeName + " takes exactly 1 child, not " + std::to_string(children->size()));
            for (std::size_t i = 0; i < children->size(); ++i)
                n.children.push_back(readNode((*children)[i], n.id + ".children[" + std::to_string(i) + "]"));
        }

        for (auto it = j.begin(); it != j.end(); ++it)
            if (!used.count(it.key())) n.extra[it.key()] = it.value();
        return n;
    }

    void readParams(const Json& j, Node& n, std::unordered_set<std::string>& used) const
    {
        const std::string& id = n.id;
        auto use = [&](std::initializer_list<const char*> keys) {
            for (const char* k : keys) used.insert(k);
        };
        switch (n.type) {
        case NodeType::Box: {
            use({"size", "round"});
            BoxParams p;
            p.size = vec3(required(j, "size", id), id, "size");
            for (int i = 0; i < 3; ++i)
                if (!(p.size[i] > 0.0))
                    fail(id, "size[" + std::to_string(i) + "]", "must be > 0, not " + formatNumber(p.size[i]));
            p.round = nonNegative(j, "round", id, 0.0);
            const double limit = 0.5 * std::min({p.size.x, p.size.y, p.size.z});
            if (p.round > limit)
                fail(id, "round",
                     "must be <= half the smallest size (" + formatNumber(limit) + "), not " + formatNumber(p.round));
            n.params = p;
            break;
        }
        case NodeType::Sphere:
            use({"radius"});
            n.params = SphereParams{positive(j, "radius", id)};
            break;
        case NodeType::Cylinder:
            use({"radius", "height"});
            n.params = CylinderParams{positive(j, "radius", id), positive(j, "height", id)};
            break;
        case NodeType::Cone: {
            use({"radius_bottom", "radius_top", "height"});
            ConeParams p;
            p.radiusBottom = nonNegative(j, "radius_bottom", id, std::nullopt);
            p.radiusTop = nonNegative(j, "radius_top", id, std::nullopt);
            if (p.radiusBottom == 0.0 && p.radiusTop == 0.0)
                fail(id, "radius_bottom", "radius_bottom and radius_top cannot both be 0");
            p.height = positive(j, "height", id);
            n.params = p;
            break;
        }
        case NodeType::Torus:
            use({"major_radius", "minor_radius"});
            n.params = TorusParams{positive(j, "major_radius", id), positive(j, "minor_radius", id)};
            break;
        case NodeType::Extrude: {
            use({"profile", "height"});
            ExtrudeParams p;
            const Json& prof = required(j, "profile", id);
            if (!prof.is_array()) fail(id, "profile", "must be an array of [x, y] points");
            for (std::size_t i = 0; i < prof.size(); ++i) {
                const std::string f = "profile[" + std::to_string(i) + "]";
                if (!prof[i].is_array() || prof[i].size() != 2) fail(id, f, "must be an [x, y] point");
                p.profile.emplace_back(number(prof[i][0], id, f + "[0]"), number(prof[i][1], id, f + "[1]"));
            }
            if (const auto defect = findProfileDefect(p.profile)) fail(id, "profile", *defect);
            p.height = positive(j, "height", id);
            n.params = std::move(p);
            break;
        }
        case NodeType::Halfspace: {
            use({"normal", "offset"});
            HalfspaceParams p;
            p.normal = unitNormal(required(j, "normal", id), id, "normal");
            // The offset is the plane's distance along the unit normal; a
            // non-unit normal in the file scales it the same way.
            const double len = glm::length(vec3(required(j, "normal", id), id, "normal"));
            p.offset = number(required(j, "offset", id), id, "offset") / len;
            n.params = p;
            break;
        }
        case NodeType::Union:
        case NodeType::Intersection:
        case NodeType::Difference:
            use({"blend"});
            n.params = BooleanParams{nonNegative(j, "blend", id, 0.0)};
            break;
        case NodeType::Offset:
            use({"distance"});
            n.params = OffsetParams{number(required(j, "distance", id), id, "distance")};
            break;
        case NodeType::Shell:
            use({"thickness"});
            n.params = ShellParams{positive(j, "thickness", id)};
            break;
        case NodeType::Array: {
            use({"count", "step"});
            ArrayParams p;
            const Json& c = required(j, "count", id);
            if (!c.is_array() || c.size() != 3) fail(id, "count", "must be an array of 3 integers");
            for (std::size_t i = 0; i < 3; ++i) {
                const std::string f = "count[" + std::to_string(i) + "]";
                p.count[i] = integer(c[i], id, f);
                if (p.count[i] < 1) fail(id, f, "must be >= 1, not " + std::to_string(p.count[i]));
            }
            p.step = vec3(required(j, "step", id), id, "step");
            n.params = p;
            break;
        }
        case NodeType::Mirror: {
            use({"normal", "offset"});
            MirrorParams p;
            p.normal = unitNormal(required(j, "normal", id), id, "normal");
            const double len = glm::length(vec3(required(j, "normal", id), id, "normal"));
            if (const Json* o = member(j, "offset")) p.offset = number(*o, id, "offset") / len;
            n.params = p;
            break;
        }
        }
    }

    void checkWholeTree(const Document& doc) const
    {
        checkInstances(doc.root);
        if (!nodeBounds(doc.root).isBounded() && !doc.settings.bounds)
            fail(doc.root.id, "settings.bounds",
                 "the part is unbounded (it contains a halfspace that nothing bounds); add settings.bounds");
    }

    void checkInstances(const Node& n) const
    {
        if (primitiveInstanceCount(n, kMaxPrimitiveInstances) <= kMaxPrimitiveInstances) return;
        // Blame the deepest node that is over the limit on its own.
        for (const auto& c : n.children)
            if (primitiveInstanceCount(c, kMaxPrimitiveInstances) > kMaxPrimitiveInstances) return checkInstances(c);
        fail(n.id, n.type == NodeType::Array ? "count" : "children",
             "expands to more than " + std::to_string(kMaxPrimitiveInstances) + " primitive copies");
    }

    std::string file_;
    mutable std::unordered_set<std::string> ids_;
};

} // namespace

Document Document::parse(std::string_view text, const std::string& sourceName)
{
    return Reader(sourceName).read(text);
}

Document Document::load(const std::filesystem::path& file)
{
    std::ifstream in(file, std::ios::binary);
    if (!in) throw DocumentError(file.string(), "", "", "cannot open the file: " + std::string(std::strerror(errno)));
    std::ostringstream s;
    s << in.rdbuf();
    if (in.bad()) throw DocumentError(file.string(), "", "", "cannot read the file");
    return parse(s.str(), file.string());
}

void Document::validate(const std::string& sourceName) const
{
    // The in-memory document goes through exactly the checks a file does.
    (void)parse(serialize(), sourceName);
}

} // namespace kerf
