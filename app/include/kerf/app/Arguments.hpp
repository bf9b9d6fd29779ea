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
    const std::vector<std::string>& positional() const { return positional_; }

    /// A positive number of millimetres; throws UsageError naming the option.
    static double parsePositiveMillimetres(const std::string& option, const std::string& text);
    /// WIDTHxHEIGHT in pixels, each in [1, 16384]; throws UsageError naming the option.
    static ImageSize parseImageSize(const std::string& option, const std::string& text);

private:
    std::vector<std::string> flags_;
    std::vector<std::pair<std::string, std::string>> values_;
    std::vector<std::string> positional_;
};

} // namespace kerf
