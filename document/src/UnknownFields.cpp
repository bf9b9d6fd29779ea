#include "kerf/document/UnknownFields.hpp"

#include "kerf/document/NodeTypes.hpp"
#include "kerf/document/PrintableText.hpp"

#include <algorithm>
#include <cctype>

namespace kerf {

namespace {

std::string lowered(const std::string& s)
{
    std::string out = s;
    for (char& c : out)
        c = char(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

// Optimal string alignment distance: insertions, deletions, substitutions
// and swaps of neighbouring characters, each one edit.
std::size_t editDistance(const std::string& a, const std::string& b)
{
    const std::size_t n = a.size(), m = b.size();
    std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1));
    for (std::size_t i = 0; i <= n; ++i)
        d[i][0] = i;
    for (std::size_t j = 0; j <= m; ++j)
        d[0][j] = j;
    for (std::size_t i = 1; i <= n; ++i)
        for (std::size_t j = 1; j <= m; ++j) {
            const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    return d[n][m];
}

class Finder {
public:
    std::vector<UnknownField> found;

    void visit(const Json& extra, UnknownField::Owner owner, const std::string& id, const std::string& prefix,
               const std::vector<std::string>& known)
    {
        for (auto it = extra.begin(); it != extra.end(); ++it)
            found.push_back({owner, id, prefix + it.key(), closestKnownField(it.key(), known)});
    }

    void visitTransform(const Transform& t, UnknownField::Owner owner, const std::string& id)
    {
        visit(t.extra, owner, id, "transform.", {"translate", "rotate"});
    }

    void visitNode(const Node& n)
    {
        std::vector<std::string> known = {"id", "type", "name", "transform", "visible", "color"};
        if (!isPrimitive(n.type)) known.push_back("children");
        for (const FieldSpec& f : nodeTypeSpec(n.type).fields)
            known.emplace_back(f.key);
        visit(n.extra, UnknownField::Owner::Feature, n.id, "", known);
        visitTransform(n.transform, UnknownField::Owner::Feature, n.id);
        for (const Node& c : n.children)
            visitNode(c);
    }
};

} // namespace

std::string closestKnownField(const std::string& key, const std::vector<std::string>& known)
{
    const std::string k = lowered(key);
    std::string best;
    std::size_t bestDistance = 3;
    for (const std::string& candidate : known) {
        // The distance is at least the difference in length: a key of a
        // megabyte is not compared letter by letter.
        const std::size_t longer = std::max(k.size(), candidate.size());
        if (longer - std::min(k.size(), candidate.size()) >= bestDistance) continue;
        const std::size_t d = editDistance(k, lowered(candidate));
        // Short keys are within two edits of everything ("x" of "id").
        if (d < bestDistance && 3 * d < longer) {
            best = candidate;
            bestDistance = d;
        }
    }
    return best;
}

std::vector<UnknownField> unknownFields(const Document& doc)
{
    Finder f;
    using Owner = UnknownField::Owner;
    f.visit(doc.extra, Owner::Document, "", "",
            {"format", "version", "units", "name", "settings", "root", "meshes", "parameters"});
    f.visit(doc.settings.extra, Owner::Document, "", "settings.", {"feature_size", "bounds"});
    for (const Parameter& p : doc.parameters)
        f.visit(p.extra, Owner::Document, "", "parameters." + p.name + ".", {"name", "expression", "comment", "unit"});
    f.visitNode(doc.root);
    for (const MeshReference& m : doc.meshes) {
        f.visit(m.extra, Owner::Mesh, m.id, "", {"id", "path", "transform", "color"});
        f.visitTransform(m.transform, Owner::Mesh, m.id);
    }
    return std::move(f.found);
}

namespace {

std::string owner(const UnknownField& field)
{
    return field.owner == UnknownField::Owner::Feature ? "feature '" + printable(field.id) + "'"
           : field.owner == UnknownField::Owner::Mesh  ? "reference mesh '" + printable(field.id) + "'"
                                                       : std::string("the document");
}

} // namespace

std::string summarizeUnknownFields(const std::vector<UnknownField>& fields)
{
    if (fields.empty()) return {};
    const auto misspelt =
        std::find_if(fields.begin(), fields.end(), [](const UnknownField& f) { return !f.suggestion.empty(); });
    const UnknownField& first = misspelt != fields.end() ? *misspelt : fields.front();
    std::string text = "'" + printable(first.field) + "'" +
                       (first.owner == UnknownField::Owner::Document ? "" : " in " + owner(first)) +
                       " is no field Kerf knows";
    if (!first.suggestion.empty()) text += " (did you mean '" + first.suggestion + "'?)";
    text += ", kept but not used";
    if (fields.size() > 1)
        text += "; " + std::to_string(fields.size() - 1) + " more such field" + (fields.size() > 2 ? "s" : "") +
                " (kerf check lists them)";
    return text;
}

std::string describeUnknownField(const UnknownField& field)
{
    std::string text = owner(field) + ": field '" + printable(field.field) +
                       "' is not one Kerf knows: it is kept when saved but not used";
    if (!field.suggestion.empty()) text += " (did you mean '" + field.suggestion + "'?)";
    return text;
}

} // namespace kerf
