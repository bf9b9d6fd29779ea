#include "kerf/app/UnknownFieldWarnings.hpp"

#include "kerf/document/UnknownFields.hpp"

namespace kerf {

void warnOfUnknownFields(const Document& doc, const std::string& command, std::ostream& err)
{
    // A file a newer Kerf wrote may hold many; the first ten say enough.
    constexpr std::size_t kShown = 10;
    const std::vector<UnknownField> fields = unknownFields(doc);
    for (std::size_t i = 0; i < fields.size() && i < kShown; ++i)
        err << command << ": warning: " << describeUnknownField(fields[i]) << "\n";
    if (fields.size() > kShown)
        err << command << ": warning: and " << fields.size() - kShown << " more fields Kerf does not know\n";
}

} // namespace kerf
