#pragma once
// What `kerf check` reports about a document: counts, bounds, feature size.

#include "kerf/document/Aabb.hpp"
#include "kerf/document/Document.hpp"

#include <cstdint>
#include <string>

namespace kerf {

struct DocumentSummary {
    std::size_t nodes = 0;              // every node in the tree, hidden ones included
    std::size_t visibleNodes = 0;
    std::size_t primitives = 0;         // visible primitive nodes
    std::uint64_t primitiveCopies = 0;  // after arrays and mirrors expand
    std::size_t tapeLength = 0;         // compiled instructions
    Aabb bounds;                        // of the solid (empty part: empty)
    double featureSize = 0.0;           // mm, the document's or the default
    bool featureSizeFromDocument = false;
    std::size_t meshes = 0;
    std::size_t missingMeshes = 0;      // reference meshes whose file is absent
};

/// The feature size the program uses when the document sets none: about a
/// thousandth of the part's largest extent, rounded down to 1, 2 or 5 times a
/// power of ten (0.5 mm for a chair).
double defaultFeatureSize(const Aabb& bounds);

DocumentSummary summarize(const Document& doc, const std::string& documentFolder);

} // namespace kerf
