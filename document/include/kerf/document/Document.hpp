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

/// A named value the document's expressions use ("thickness" = "18mm").
struct Parameter {
    std::string name;                // a name: letters, digits and _, not starting with a digit
    std::string expression;          // as written (Expression.hpp); a plain number too
    std::optional<std::string> comment;
    std::optional<std::string> unit; // "length", "angle" or "number": what it must give; none: whatever it gives
    double value = 0.0;              // resolved: mm, degrees or a plain number
    Json extra = Json::object();
    bool operator==(const Parameter&) const = default;
};

/// Values for parameters given from outside the file (`kerf -D name=value`):
/// each replaces the parameter's expression before anything is evaluated.
using ParameterOverrides = std::vector<std::pair<std::string, std::string>>;

struct Document {
    std::optional<std::string> name;
    std::optional<std::string> units; // kept as written ("mm" is the only value allowed)
    DocumentSettings settings;
    Node root;
    std::vector<MeshReference> meshes;
    /// Named parameters, in file order; their values and every node field
    /// that holds an expression (Node::expressions) are resolved on load.
    std::vector<Parameter> parameters;
    Json extra = Json::object(); // unknown top-level fields

    bool operator==(const Document&) const = default;

    /// Parses and validates a document. `sourceName` names it in messages.
    /// Expressions are evaluated (with `overrides` for named parameters) and
    /// every field holds its resolved number. Throws DocumentError.
    static Document parse(std::string_view text, const std::string& sourceName, const ParameterOverrides& overrides = {});
    /// Reads and validates a file. Throws DocumentError.
    static Document load(const std::filesystem::path& file, const ParameterOverrides& overrides = {});

    /// Whether any parameter or node field holds an expression.
    bool hasExpressions() const;

    /// This document with its expressions evaluated again (after an edit of
    /// a parameter or of a field that others refer to). Throws DocumentError.
    Document resolved(const std::string& sourceName = "<document>") const;

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
