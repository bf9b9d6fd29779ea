#pragma once
// How nodes are named to a person: "Box", "Difference", "Seat (box)".

#include "kerf/document/Node.hpp"

#include <QString>

namespace kerf::ui {

/// The type as a label: "Box", "Smooth union"... (capitalised spec names).
QString nodeTypeLabel(NodeType type);
/// The node's name, else its id.
QString displayName(const Node& n);
/// How messages and undo steps name a feature: its name, or "the cylinder"
/// for an unnamed one (never its internal id).
QString featureName(const Node& n);

} // namespace kerf::ui
