#include "kerf/document/ReferableNumbers.hpp"

#include "kerf/document/NodeTypes.hpp"

namespace kerf {

namespace {

void collectOwn(const Node& n, std::vector<std::string>& out)
{
    const std::string prefix = n.id + ".";
    for (const FieldSpec& f : nodeTypeSpec(n.type).fields) {
        const std::string key(f.key);
        if (f.shape == FieldShape::Number) {
            out.push_back(prefix + key);
        } else if (f.shape == FieldShape::Vector) {
            for (int i = 0; i < 3; ++i) out.push_back(prefix + key + "[" + std::to_string(i) + "]");
        }
        // Directions are unit vectors, counts whole numbers and profiles
        // long lists: not what a length is measured from.
    }
    for (int i = 0; i < 3; ++i) out.push_back(prefix + "transform.translate[" + std::to_string(i) + "]");
}

void collect(const Node& n, std::vector<std::string>& out)
{
    collectOwn(n, out);
    for (const Node& c : n.children) collect(c, out);
}

} // namespace

std::vector<std::string> referableNumbers(const Node& node)
{
    std::vector<std::string> out;
    collectOwn(node, out);
    return out;
}

std::vector<std::string> referableNumbers(const Document& doc)
{
    std::vector<std::string> out;
    collect(doc.root, out);
    return out;
}

} // namespace kerf
