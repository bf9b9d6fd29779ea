#pragma once
// The edit `kerf bench` times re-voxelization with: a small feature moved by
// a few millimetres, the commonest edit while detailing a part (a dowel hole
// nudged to line up with its dowel).
//
// Which feature, for any document, deterministically: among the visible
// primitives (every ancestor visible too) other than halfspaces, the one
// whose own bounding box (one instance, nodeBounds) has the shortest
// diagonal; ties go to the first in the document (depth-first, in file
// order). It moves by kTypicalEditMm along the x axis of its parent's frame
// (its transform's translate.x), and back.

#include "kerf/document/Document.hpp"

#include <cstdint>
#include <optional>
#include <string>

namespace kerf {

inline constexpr double kTypicalEditMm = 5.0;

struct TypicalEdit {
    std::string nodeId;
    NodeType type = NodeType::Box;
    std::uint64_t instances = 1; // copies the feature has (arrays and mirrors above it multiply it)
    double diagonalMm = 0.0;     // of its own bounding box
};

/// The feature to move; none when the part has no bounded visible primitive.
std::optional<TypicalEdit> chooseTypicalEdit(const Document& doc);

/// `doc` with the edit's feature moved by `offsetMm` along its parent's x axis.
Document applyTypicalEdit(Document doc, const TypicalEdit& edit, double offsetMm);

} // namespace kerf
