#pragma once
// Structural edits of a document's feature tree, as an editor makes them:
// insert, remove, move (reorder and regroup), duplicate, wrap under a new
// operation. Qt-free, so the desktop application's undo commands stay thin
// and the rules are tested on their own.
//
// Contract: every function either applies its whole edit or throws
// std::invalid_argument (with a sentence a person can read) and leaves the
// document untouched. The functions check the tree's shape (an operation
// that takes one child gets no second one, a node never moves into its own
// subtree, ids stay unique); parameter validity is Document::validate()'s
// job, which an editor runs on the result before committing it.

#include "kerf/document/Document.hpp"

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_set>
#include <vector>

namespace kerf::edit {

/// Where a node sits: its parent's id and its index among the parent's
/// children. The root has no location.
struct NodeLocation {
    std::string parentId;
    std::size_t index = 0;
    bool operator==(const NodeLocation&) const = default;
};

std::optional<NodeLocation> locate(const Document& doc, std::string_view id);

/// How many children a node of this type may have: 0 for primitives, 1 for
/// offset, shell, array and mirror, unlimited (SIZE_MAX) for booleans.
std::size_t maxChildren(NodeType type);

/// `base` when no node has that id, else `base-2`, `base-3`, ...
std::string uniqueId(const Document& doc, std::string_view base);

/// Inserts `node` (its ids must be new to the document) as child `index` of
/// `parentId` (index past the end appends).
void insertNode(Document& doc, std::string_view parentId, std::size_t index, Node node);

/// Removes a node and its subtree (not the root); returns what was removed.
Node removeNode(Document& doc, std::string_view id);

/// Removes each of `ids` with its subtree, in order; an id already gone
/// with an earlier one's subtree is skipped. All or nothing.
void removeNodes(Document& doc, const std::vector<std::string>& ids);

/// The features that removing `ids` would leave with no child (a mirror,
/// an array or a group whose only child goes), up the tree, not the root:
/// they act on nothing, and a document does not hold them, so a deletion
/// takes them along. A parent before the features it holds; none of `ids`.
std::vector<std::string> emptiedByRemoving(const Document& doc, const std::vector<std::string>& ids);

/// Moves a node (with its subtree) to child `index` of `newParentId`, index
/// counted in the parent's children as they are before the move. Refuses the
/// root, a move into its own subtree and a parent that has no room.
void moveNode(Document& doc, std::string_view id, std::string_view newParentId, std::size_t index);

/// Copies a node's subtree with fresh ids (names get " copy"), inserted right
/// after the original; returns the copy's id. Refuses the root and a parent
/// with no room for another child.
std::string duplicateNode(Document& doc, std::string_view id);

/// Puts the given sibling nodes (in their order among the siblings) under a
/// new operation node `op`, placed where the first of them was; returns its
/// id. The root can be wrapped alone: the new operation becomes the root.
std::string wrapNodes(Document& doc, const std::vector<std::string>& ids, Node op);

/// Replaces a node's own fields (name, transform, visibility, colour,
/// parameters, unknown fields, expressions) by `updated`'s, keeping its
/// children and its id; a field whose number changed loses its expression
/// (a number typed over it). Refuses a change of type.
void updateNode(Document& doc, std::string_view id, const Node& updated);

/// A profile's points, each coordinate a number or an expression that
/// drives it: `expressions[i][c]` ("-length/2") drives point i's coordinate
/// c, "" leaves it a number. The node's profile expressions are replaced
/// as a whole: a point inserted or removed moves the expressions of the
/// points after it along (updateNode, which compares numbers index by
/// index, would drop them). The numbers of driven coordinates are placeholders
/// until the document is resolved. Refuses a node without a profile.
void setProfile(Document& doc, std::string_view id, std::vector<glm::dvec2> points,
                const std::vector<std::array<std::string, 2>>& expressions);

/// The first difference of `after` whose base (its first child: the body
/// the others are cut from) is not what it was in `before`, or whose only
/// child left is a tool; empty when every difference keeps its base. An
/// editor asks before such a reorder: a tool moved above the base cuts from
/// nothing, and the part empties.
std::string differenceWithNewBase(const Document& before, const Document& after);
/// Every such difference, in tree order (a deletion may change several).
std::vector<std::string> differencesWithNewBase(const Document& before, const Document& after);

/// The ids of a node and of everything below it.
std::unordered_set<std::string> idsInSubtree(const Node& node);

/// The ids of the primitives at or below a node: what a view highlights
/// when the node is selected.
std::unordered_set<std::string> primitiveIdsInSubtree(const Node& node);

/// `ids` in the order of their nodes in the tree (depth first, parents
/// before children), ids not in the document left out: a selection made in
/// any order groups its siblings in the order they had.
std::vector<std::string> inTreeOrder(const Document& doc, const std::vector<std::string>& ids);

/// Adds a reference mesh for `file` to the document and returns its id: the
/// file's stem, numbered when the document has a mesh of that id already
/// ("leg", "leg-2", "leg-3"), "mesh" for a file without a stem. Its path is
/// kept relative to `documentFolder` when the document has a folder (it
/// travels with the document), absolute otherwise. Whether the file reads
/// as a mesh is the caller's question (the core does not read meshes).
std::string addMeshReference(Document& doc, const std::filesystem::path& file,
                             const std::optional<std::filesystem::path>& documentFolder);

/// Parameters (Document::parameters), as the Parameters panel edits them.
/// Each refuses with std::invalid_argument (a sentence) and leaves the
/// document unchanged; the caller then resolves the document
/// (Document::resolved) so that every expression sees the change.
///
/// Adds a parameter named `base` (numbered when taken: "p", "p2") with
/// `expression`; returns its name.
std::string addParameter(Document& doc, const std::string& base, const std::string& expression);
/// Renames a parameter and every use of it in the document's expressions.
/// Refuses a name that is not a name or is taken.
void renameParameter(Document& doc, const std::string& from, const std::string& to);
/// Removes a parameter; refused while an expression uses it (naming where).
void removeParameter(Document& doc, const std::string& name);
/// Where `name` is used: "parameters.rows", "board.size[0]", in document order.
std::vector<std::string> parameterUses(const Document& doc, const std::string& name);
/// The expressions outside the subtrees of `ids` that refer to a field of a
/// node in them ("box.size[2]" for "=extrude.height - 15"), as
/// parameterUses names them: what stops a deletion of `ids`.
std::vector<std::string> nodeUses(const Document& doc, const std::vector<std::string>& ids);

/// A new empty document: a root union with no children, settings default.
/// Not valid on its own (a union needs a child): editors add one first.
Document emptyDocument();

} // namespace kerf::edit
