#include "kerf/document/DocumentError.hpp"

namespace kerf {

namespace {
std::string compose(const std::string& file, const std::string& nodeId, const std::string& field,
                    const std::string& reason)
{
    std::string s = file.empty() ? std::string("<document>") : file;
    s += ": ";
    if (!nodeId.empty()) s += "node '" + nodeId + "', ";
    if (!field.empty()) s += "field '" + field + "': ";
    s += reason;
    return s;
}
} // namespace

DocumentError::DocumentError(std::string file, std::string nodeId, std::string field, std::string reason)
    : std::runtime_error(compose(file, nodeId, field, reason)), file_(std::move(file)),
      nodeId_(std::move(nodeId)), field_(std::move(field)), reason_(std::move(reason))
{
}

} // namespace kerf
