#pragma once
// A Kerf document: one part as a feature tree, plus settings and reference
// meshes. Loading validates everything the spec lists and refuses with a
// DocumentError that names the file, the node id and the field; a refused
// load changes nothing. Saving is atomic.

#include "kerf/document/Node.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace kerf {

inline constexpr int kFormatVersion = 1;

/// A reference triangle mesh drawn beside the part (never part of the CSG).
struct MeshReference {
    std::string id;
    std::string path; // relative to the document's folder
    Transform transform;
    std::optional<Color> color;
    Json extra = Json::object();
    bool operator==(const MeshReference&) const = default;
};

struct Bounds3 {
    glm::dvec3 min{0.0};
    glm::dvec3 max{0.0};
    bool operator==(const Bounds3&) const = default;
};

struct DocumentSettings {
    std::optional<double> featureSize;   // mm
    std::optional<Bounds3> bounds;       // clips the root's solid
    Json extra = Json::object();
    bool operator==(const DocumentSettings&) const = default;
};

struct Document {
    std::optional<std::string> name;
    std::optional<std::string> units; // kept as written ("mm" is the only value allowed)
    DocumentSettings settings;
    Node root;
    std::vector<MeshReference> meshes;
    Json extra = Json::object(); // unknown top-level fields

    bool operator==(const Document&) const = default;

    /// Parses and validates a document. `sourceName` names it in messages.
    /// Throws DocumentError.
    static Document parse(std::string_view text, const std::string& sourceName);
    /// Reads and validates a file. Throws DocumentError.
    static Document load(const std::filesystem::path& file);

    /// The document as JSON text (2-space indent, trailing newline).
    std::string serialize() const;
    /// Validates, then writes atomically (temporary file + rename): the old
    /// file stays intact if anything fails. Throws DocumentError.
    void save(const std::filesystem::path& file) const;

    /// Runs every check that load runs on this in-memory document (editors
    /// call it before committing an edit). Throws DocumentError.
    void validate(const std::string& sourceName = "<document>") const;
};

} // namespace kerf
