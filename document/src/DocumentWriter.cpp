// Serialization of Kerf documents: known fields in a stable order, then every
// unknown field exactly as it was read.

#include "kerf/document/AtomicFile.hpp"
#include "kerf/document/PrintableText.hpp"
#include "kerf/document/Document.hpp"
#include "kerf/document/DocumentError.hpp"
#include "kerf/document/NodeTypes.hpp"

#include "FieldPath.hpp"
#include "JsonMembers.hpp"

#include <unordered_set>

namespace kerf {

namespace {

Json vec3(const glm::dvec3& v) { return Json::array({v.x, v.y, v.z}); }

// Appends the unknown fields after the known ones. The known ones are few;
// the unknown ones may be many, so no lookup per unknown field.
void mergeExtra(Json& out, const Json& extra)
{
    if (extra.empty()) return;
    std::unordered_set<std::string> known;
    for (auto it = out.begin(); it != out.end(); ++it) known.insert(it.key());
    for (auto it = extra.begin(); it != extra.end(); ++it)
        if (!known.count(it.key())) appendMember(out, it.key(), it.value());
}

std::optional<Json> writeTransform(const Transform& t)
{
    if (t.isIdentity() && t.extra.empty()) return std::nullopt;
    Json j = Json::object();
    if (t.translate != glm::dvec3(0.0)) j["translate"] = vec3(t.translate);
    if (t.rotate != glm::dvec3(0.0)) j["rotate"] = vec3(t.rotate);
    mergeExtra(j, t.extra);
    return j;
}

// The node's fields in its type's table order (NodeTypes.hpp); an optional
// field that holds its absent value is left out, as it was read.
void writeParams(const Node& n, Json& j)
{
    for (const FieldSpec& f : nodeTypeSpec(n.type).fields) {
        const std::string key(f.key);
        switch (f.shape) {
        case FieldShape::Number:
            if (!f.optional || f.numberIn(n) != f.absent || n.expressions.count(key)) j[key] = f.numberIn(n);
            break;
        case FieldShape::Vector:
        case FieldShape::Direction: j[key] = vec3(f.vectorIn(n)); break;
        case FieldShape::Counts: {
            const auto& c = f.countsIn(n);
            j[key] = Json::array({c[0], c[1], c[2]});
            break;
        }
        case FieldShape::Points: {
            Json points = Json::array();
            for (const auto& v : f.pointsIn(n)) points.push_back(Json::array({v.x, v.y}));
            j[key] = std::move(points);
            break;
        }
        }
    }
}

Json writeNode(const Node& n)
{
    Json j = Json::object();
    j["id"] = n.id;
    j["type"] = std::string(nodeTypeName(n.type));
    if (n.name) j["name"] = *n.name;
    writeParams(n, j);
    if (auto t = writeTransform(n.transform)) j["transform"] = std::move(*t);
    if (!n.visible) j["visible"] = false;
    // A field driven by an expression is written as the expression (a
    // transform whose expressions give zero is written all the same).
    for (const auto& [path, text] : n.expressions) {
        if (path.rfind("transform.translate", 0) == 0 && !(j.contains("transform") && j["transform"].contains("translate")))
            j["transform"]["translate"] = vec3(n.transform.translate);
        if (path.rfind("transform.rotate", 0) == 0 && !(j.contains("transform") && j["transform"].contains("rotate")))
            j["transform"]["rotate"] = vec3(n.transform.rotate);
    }
    for (const auto& [path, text] : n.expressions)
        if (const auto p = detail::parseFieldPath(path))
            if (Json* v = detail::jsonAt(j, *p)) *v = text;
    if (n.color) j["color"] = formatColor(*n.color);
    if (!isPrimitive(n.type)) {
        Json kids = Json::array();
        for (const auto& c : n.children) kids.push_back(writeNode(c));
        j["children"] = std::move(kids);
    }
    mergeExtra(j, n.extra);
    return j;
}

} // namespace

std::string Document::serialize() const
{
    Json j = Json::object();
    j["format"] = "kerf";
    j["version"] = kFormatVersion;
    if (units) j["units"] = *units;
    if (name) j["name"] = *name;
    Json s = Json::object();
    if (settings.featureSize) s["feature_size"] = *settings.featureSize;
    if (settings.bounds) s["bounds"] = Json::array({vec3(settings.bounds->min), vec3(settings.bounds->max)});
    mergeExtra(s, settings.extra);
    if (!s.empty()) j["settings"] = std::move(s);
    if (!parameters.empty()) {
        Json ps = Json::array();
        for (const Parameter& p : parameters) {
            Json pj = Json::object();
            pj["name"] = p.name;
            pj["expression"] = p.expression;
            if (p.unit) pj["unit"] = *p.unit;
            if (p.comment) pj["comment"] = *p.comment;
            mergeExtra(pj, p.extra);
            ps.push_back(std::move(pj));
        }
        j["parameters"] = std::move(ps);
    }
    j["root"] = writeNode(root);
    if (!meshes.empty()) {
        Json ms = Json::array();
        for (const auto& m : meshes) {
            Json mj = Json::object();
            mj["id"] = m.id;
            mj["path"] = m.path;
            if (auto t = writeTransform(m.transform)) mj["transform"] = std::move(*t);
            if (m.color) mj["color"] = formatColor(*m.color);
            mergeExtra(mj, m.extra);
            ms.push_back(std::move(mj));
        }
        j["meshes"] = std::move(ms);
    }
    mergeExtra(j, extra);
    return j.dump(2) + "\n";
}

void Document::save(const std::filesystem::path& file) const
{
    const std::string text = serialize();
    (void)parse(text, file.string()); // refuse to write what could not be read back
    try {
        writeFileAtomically(file, text);
    } catch (const std::runtime_error& e) {
        // The writer names the file already ("x.kerf: x.kerf: the folder ..."
        // was said to a newcomer): once is enough.
        std::string why = e.what();
        const std::string named = printable(file.string(), 400) + ": ";
        if (why.rfind(named, 0) == 0) why.erase(0, named.size());
        throw DocumentError(file.string(), "", "", why);
    }
}

} // namespace kerf
