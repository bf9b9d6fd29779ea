#pragma once
// The fields of a document that Kerf does not know. The format keeps them
// (a newer version's fields survive a save by this one), so a load does not
// refuse them; but a misspelt field ("transfom", "radius_Top") is one the
// part silently goes without: the feature stands at the origin, the cone
// takes its default. `kerf check` and the application name each one, with
// the known field it is probably a misspelling of.

#include "kerf/document/Document.hpp"

#include <string>
#include <vector>

namespace kerf {

struct UnknownField {
    enum class Owner { Document, Feature, Mesh };
    /// Document: the document's own fields, its settings and its parameters.
    Owner owner = Owner::Document;
    /// The feature's or the reference mesh's id; empty for the document.
    std::string id;
    /// Where it is: "transfom", "transform.scale", "settings.featuresize",
    /// "parameters.width.units", "meshes[scan].colour".
    std::string field;
    /// A field known in that place that this one is a misspelling of (two
    /// edits at most, case ignored); empty when none is that close.
    std::string suggestion;
    bool operator==(const UnknownField&) const = default;
};

/// In document order: the document's fields, its settings, its parameters,
/// the feature tree depth first, then the reference meshes.
std::vector<UnknownField> unknownFields(const Document& doc);

/// One line: "feature 'leg': field 'transfom' is not one Kerf knows: it is
/// kept when saved but not used (did you mean 'transform'?)".
std::string describeUnknownField(const UnknownField& field);

/// One short sentence for a status bar on opening: the first field that is
/// probably a misspelling (else the first field), then how many more.
/// "'transfom' in feature 'leg' is no field Kerf knows (did you mean
/// 'transform'?), kept but not used; 3 more such fields (kerf check lists
/// them)". Empty when there are none.
std::string summarizeUnknownFields(const std::vector<UnknownField>& fields);

/// The known field `key` is probably a misspelling of, among `known`; empty
/// when none is within two edits (an insertion, deletion, substitution or
/// swap of neighbours; case ignored) and closer than a third of its length.
std::string closestKnownField(const std::string& key, const std::vector<std::string>& known);

} // namespace kerf
