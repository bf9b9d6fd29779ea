#pragma once
// How nodes are named to a person: "Box", "Difference", "Seat (box)".

#include "kerf/document/Node.hpp"

#include <QString>

#include <string>
#include <vector>

namespace kerf::ui {

/// The type as a label: "Box", "Smooth union"... (capitalised spec names).
QString nodeTypeLabel(NodeType type);
/// The node's name, else its id.
QString displayName(const Node& n);
/// How messages and undo steps name a feature: its name, or "the cylinder"
/// for an unnamed one (never its internal id).
QString featureName(const Node& n);
/// A field as its row in the property editor names it: "radius" is
/// "Radius", "count[2]" is "Count Z", "translate[0]" is "Position X"; a key
/// the node's type does not list comes back as it is.
QString fieldLabel(const Node& n, const std::string& field);
/// An edit the document refused, in the panels' words: "Radius of Pin hole:
/// must be > 0, not -2.5" for the file's "node 'cylinder', field 'radius'"
/// (a newcomer did not know what 'cylinder' or 'count[2]' was). The node
/// is looked for in `doc`; one it does not hold is named by its id.
QString describeRefusal(const Node& root, const std::string& nodeId, const std::string& field,
                        const std::string& reason);
/// Where an expression is used, as parameterUses gives it ("panel.size[0]",
/// "parameters.depth"), in the panels' words: "Size X of Side panel",
/// "the parameter depth".
QString describeExpressionUse(const Node& root, const std::string& use);
/// Several of them: "Size X of Side panel, Position Z of the cylinder and 3
/// more" (the first five named).
QString describeExpressionUses(const Node& root, const std::vector<std::string>& uses);

} // namespace kerf::ui
