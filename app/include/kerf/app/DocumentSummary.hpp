#pragma once
// What `kerf check` reports about a document: counts, bounds, feature size.

#include "kerf/document/Aabb.hpp"
#include "kerf/document/Document.hpp"
#include "kerf/voxelizer/GridLayout.hpp" // defaultFeatureSize

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
    std::size_t missingMeshes = 0;      // reference meshes whose file is absent or no regular file
};


DocumentSummary summarize(const Document& doc, const std::string& documentFolder);

} // namespace kerf
