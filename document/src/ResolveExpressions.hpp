#pragma once
// The first step of loading a document: every expression in its JSON (the
// named parameters, any numeric field of a node) evaluated in the order its
// references need, and replaced by its number, so that the reader and all
// its checks see numbers as before (Expression.hpp has the language). A
// cycle, an unknown name or node or field, a division by zero or a unit
// mismatch is a DocumentError naming the node, the field and the expression.

#include "kerf/document/Document.hpp"

#include <string>
#include <vector>

namespace kerf::detail {

/// A field that held an expression, and what it gave.
struct ExpressionSite {
    std::string nodeId;
    std::string path; // "size[0]", "transform.translate[2]"
    std::string text;
    double value = 0.0;
};

struct ResolvedExpressions {
    std::vector<Parameter> parameters;
    std::vector<ExpressionSite> sites;
};

/// Resolves `j` (a whole document) in place. Throws DocumentError.
ResolvedExpressions resolveExpressions(Json& j, const std::string& file, const ParameterOverrides& overrides);

} // namespace kerf::detail
