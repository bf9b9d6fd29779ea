#pragma once
// One fuzzer input's work (FuzzDocument.cpp says what counts as a finding).

#include <optional>
#include <string>
#include <string_view>

namespace kerf::fuzz {

/// Loads `bytes` as a document and, when it loads, exercises it. Returns the
/// finding, if any (sanitizer reports and crashes are findings too, reported
/// by the sanitizers themselves). Exceptions other than a document's refusal
/// propagate: an exception escaping is a finding as well.
std::optional<std::string> fuzzDocument(std::string_view bytes);

} // namespace kerf::fuzz
