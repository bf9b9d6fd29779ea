#include "FieldPath.hpp"

#include "kerf/document/NodeTypes.hpp"

#include <cctype>
#include <charconv>
#include <utility>

namespace kerf::detail {

std::optional<FieldPath> parseFieldPath(std::string_view path)
{
    FieldPath p;
    std::size_t at = 0;
    while (at < path.size() && path[at] != '[') {
        const std::size_t dot = path.find_first_of(".[", at);
        const std::size_t end = dot == std::string_view::npos ? path.size() : dot;
        if (end == at) return std::nullopt;
        p.keys.emplace_back(path.substr(at, end - at));
        at = end;
        if (at < path.size() && path[at] == '.') ++at;
    }
    while (at < path.size()) {
        if (path[at] != '[') return std::nullopt;
        const std::size_t close = path.find(']', at);
        if (close == std::string_view::npos || close == at + 1) return std::nullopt;
        std::size_t index = 0;
        const auto [ptr, ec] = std::from_chars(path.data() + at + 1, path.data() + close, index);
        if (ec != std::errc() || ptr != path.data() + close) return std::nullopt;
        p.indices.push_back(index);
        at = close + 1;
    }
    if (p.keys.empty()) return std::nullopt;
    return p;
}

std::optional<double> numberAt(const Node& n, std::string_view path)
{
    const std::optional<FieldPath> p = parseFieldPath(path);
    if (!p) return std::nullopt;
    const auto& ix = p->indices;
    if (p->keys.size() == 2 && p->keys[0] == "transform" && ix.size() == 1 && ix[0] < 3) {
        if (p->keys[1] == "translate") return n.transform.translate[int(ix[0])];
        if (p->keys[1] == "rotate") return n.transform.rotate[int(ix[0])];
        return std::nullopt;
    }
    if (p->keys.size() != 1) return std::nullopt;
    for (const FieldSpec& f : nodeTypeSpec(n.type).fields) {
        if (f.key != p->keys[0]) continue;
        switch (f.shape) {
        case FieldShape::Number: return ix.empty() ? std::optional(f.numberIn(n)) : std::nullopt;
        case FieldShape::Vector:
        case FieldShape::Direction:
            return ix.size() == 1 && ix[0] < 3 ? std::optional(f.vectorIn(n)[int(ix[0])]) : std::nullopt;
        case FieldShape::Counts:
            return ix.size() == 1 && ix[0] < 3 ? std::optional(double(f.countsIn(n)[ix[0]])) : std::nullopt;
        case FieldShape::Points: {
            const auto& pts = f.pointsIn(n);
            return ix.size() == 2 && ix[0] < pts.size() && ix[1] < 2 ? std::optional(pts[ix[0]][int(ix[1])]) : std::nullopt;
        }
        }
    }
    return std::nullopt;
}

const Json* jsonAt(const Json& node, const FieldPath& path)
{
    const Json* j = &node;
    for (const std::string& k : path.keys) {
        if (!j->is_object()) return nullptr;
        const auto it = j->find(k);
        if (it == j->end()) return nullptr;
        j = &*it;
    }
    for (const std::size_t i : path.indices) {
        if (!j->is_array() || i >= j->size()) return nullptr;
        j = &(*j)[i];
    }
    return j;
}

Json* jsonAt(Json& node, const FieldPath& path) { return const_cast<Json*>(jsonAt(std::as_const(node), path)); }

} // namespace kerf::detail
