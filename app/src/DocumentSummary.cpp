#include "kerf/app/DocumentSummary.hpp"

#include "kerf/document/Expansion.hpp"
#include "kerf/document/NodeBounds.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"

#include <cmath>
#include <filesystem>

namespace kerf {

namespace {
void countNodes(const Node& n, bool visible, DocumentSummary& s)
{
    ++s.nodes;
    visible = visible && n.visible;
    if (visible) {
        ++s.visibleNodes;
        if (isPrimitive(n.type)) ++s.primitives;
    }
    for (const auto& c : n.children) countNodes(c, visible, s);
}
} // namespace

DocumentSummary summarize(const Document& doc, const std::string& documentFolder)
{
    DocumentSummary s;
    countNodes(doc.root, true, s);
    s.primitiveCopies = expansionOf(doc.root, false).primitiveCopies;
    s.tapeLength = compileTape(doc).size();
    s.bounds = partBounds(doc);
    s.featureSizeFromDocument = doc.settings.featureSize.has_value();
    s.featureSize = doc.settings.featureSize.value_or(defaultFeatureSize(s.bounds));
    s.meshes = doc.meshes.size();
    for (const auto& m : doc.meshes) {
        // A FIFO or a folder where a mesh file should be is as good as absent
        // (the application refuses to read it).
        std::error_code ec;
        if (!std::filesystem::is_regular_file(std::filesystem::path(documentFolder) / m.path, ec)) ++s.missingMeshes;
    }
    return s;
}

} // namespace kerf
