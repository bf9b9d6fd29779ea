#pragma once
// A small command-line reader for kerf's subcommands: positional arguments,
// flags and options with values (`--size 800x600` or `--size=800x600`).
// Unknown options are usage errors (exit 2), reported by UsageError.

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace kerf {

class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A request that cannot be met, refused before any work (exit 2): an output
/// that is not a regular file or cannot be written, a feature size or
/// picture the machine cannot afford. what() is the whole line after
/// "kerf COMMAND: ".
class RefusedRequest : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Throws RefusedRequest when writing `output` would replace `other`: the
/// same file under one name, through a link, or a hard link to it (the
/// document being read, or another output of the same command). `role`
/// says what `other` is ("the document being read").
void refuseOverwriting(const std::string& output, const std::string& other, const std::string& role);

struct ImageSize {
    int width = 1280, height = 960;
};

class Arguments {
public:
    /// `valueOptions` take a value; `flags` do not. Throws UsageError.
    Arguments(const std::vector<std::string>& args, const std::vector<std::string>& valueOptions,
              const std::vector<std::string>& flags);

    bool has(const std::string& flag) const;
    std::optional<std::string> value(const std::string& option) const;
    /// Every value of an option given more than once, in order.
    std::vector<std::string> values(const std::string& option) const;
    /// The `-D NAME=VALUE` (or `-DNAME=VALUE`) definitions, for the
    /// document's parameters; throws UsageError for one without '='.
    std::vector<std::pair<std::string, std::string>> defines() const;
    const std::vector<std::string>& positional() const { return positional_; }

    /// A positive number of millimetres; throws UsageError naming the option.
    static double parsePositiveMillimetres(const std::string& option, const std::string& text);
    /// A feature size: positive millimetres within limits::kMinFeatureSize
    /// and kMaxFeatureSize; throws UsageError naming the option.
    static double parseFeatureSize(const std::string& option, const std::string& text);
    /// A tolerance: 0 (none) or millimetres within the feature size's
    /// limits; throws UsageError naming the option.
    static double parseTolerance(const std::string& option, const std::string& text);
    /// WIDTHxHEIGHT in pixels, each in [1, 16384], at most kMaxImagePixels in
    /// all; throws UsageError naming the option.
    static ImageSize parseImageSize(const std::string& option, const std::string& text);

    /// The most pixels a picture may have: 8192 x 8192 (about 5 GB while
    /// traced on lavapipe).
    static constexpr long kMaxImagePixels = 8192L * 8192L;

private:
    std::vector<std::string> flags_;
    std::vector<std::pair<std::string, std::string>> values_;
    std::vector<std::string> positional_;
};

} // namespace kerf
