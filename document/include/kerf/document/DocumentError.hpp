#pragma once
// A refusal to load, validate or save a document. what() is one line:
//   FILE: node 'ID', field 'FIELD': reason
// with the parts that do not apply left out, and every part escaped
// (PrintableText.hpp): the accessors return the raw text.

#include <stdexcept>
#include <string>

namespace kerf {

class DocumentError : public std::runtime_error {
public:
    DocumentError(std::string file, std::string nodeId, std::string field, std::string reason);

    const std::string& file() const { return file_; }
    const std::string& nodeId() const { return nodeId_; }
    const std::string& field() const { return field_; }
    const std::string& reason() const { return reason_; }

private:
    std::string file_, nodeId_, field_, reason_;
};

} // namespace kerf
