#include "kerf/document/DocumentError.hpp"

#include "kerf/document/PrintableText.hpp"

namespace kerf {

namespace {
std::string compose(const std::string& file, const std::string& nodeId, const std::string& field,
                    const std::string& reason)
{
    // Ids, fields (unknown keys are user text too) and reasons (which quote
    // values) are escaped: the message stays one line that cannot drive the
    // terminal.
    std::string s = file.empty() ? std::string("<document>") : printable(file, 400);
    s += ": ";
    if (!nodeId.empty()) s += "node '" + printable(nodeId) + "', ";
    if (!field.empty()) s += "field '" + printable(field) + "': ";
    s += printable(reason, 600);
    return s;
}
} // namespace

DocumentError::DocumentError(std::string file, std::string nodeId, std::string field, std::string reason)
    : std::runtime_error(compose(file, nodeId, field, reason)), file_(std::move(file)),
      nodeId_(std::move(nodeId)), field_(std::move(field)), reason_(std::move(reason))
{
}

} // namespace kerf
