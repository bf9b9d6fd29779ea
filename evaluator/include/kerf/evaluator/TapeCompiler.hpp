#pragma once
// Compiles a document's feature tree into a Tape.
//
// - Hidden nodes are absent; an operation with no visible child is empty, and
//   so is an intersection with an empty child or a difference whose first
//   visible child is empty.
// - Exact booleans (blend 0) are associative, so their children are combined
//   as balanced trees: shorter evaluation stacks and better interval pruning
//   than a left fold. Smooth booleans fold left to right, as the spec says.
// - Arrays and mirrors expand into placed copies of their child.
// - settings.bounds intersects the root with that box.

#include "kerf/document/Document.hpp"
#include "kerf/evaluator/Tape.hpp"

#include <string>
#include <unordered_map>
#include <vector>

namespace kerf {

/// Keeps feature indices stable across compilations of successive versions
/// of a document, so that voxel data built for an earlier version still
/// names the right features. Indices are never reused.
struct FeatureRegistry {
    std::unordered_map<std::string, std::uint32_t> index;
    std::vector<std::string> ids;
};

Tape compileTape(const Document& doc, FeatureRegistry* registry = nullptr);

/// Compiles one node (with its own transform) as if it were the root.
Tape compileTape(const Node& node);

} // namespace kerf
