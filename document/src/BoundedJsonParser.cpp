#include "BoundedJsonParser.hpp"

#include "kerf/document/Limits.hpp"

#include <cmath>
#include <cstdlib>
#include <unordered_set>
#include <vector>

namespace kerf::detail {

namespace {

using ObjectBase = Json::object_t::Container; // ordered_map is a vector of pairs

// Replaces every number token that overflows a double by a marker string, in
// one pass over the text (strings are skipped, escapes included).
std::string markNonFiniteNumbers(std::string_view text, bool& marked)
{
    std::string out;
    marked = false;
    bool inString = false;
    std::size_t copiedUpTo = 0;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (c == '\\') ++i;
            else if (c == '"') inString = false;
            continue;
        }
        if (c == '"') {
            inString = true;
            continue;
        }
        if (c != '-' && !(c >= '0' && c <= '9')) continue;
        std::size_t end = i;
        bool exponent = false;
        while (end < text.size()) {
            const char d = text[end];
            if (d == 'e' || d == 'E') exponent = true;
            else if (!((d >= '0' && d <= '9') || d == '-' || d == '+' || d == '.')) break;
            ++end;
        }
        // Only an exponent or more than 308 digits can overflow a double.
        if (exponent || end - i > 300) {
            const std::string token(text.substr(i, end - i));
            char* stop = nullptr;
            const double v = std::strtod(token.c_str(), &stop);
            if (stop == token.c_str() + token.size() && std::isinf(v)) {
                out.append(text.substr(copiedUpTo, i - copiedUpTo));
                out += "\"\\u0001kerf-non-finite-number:"; // kNonFiniteMarker, JSON-escaped
                out += token;
                out += '"';
                copiedUpTo = end;
                marked = true;
            }
        }
        i = end - 1;
    }
    if (!marked) return {};
    out.append(text.substr(copiedUpTo));
    return out;
}

// nlohmann's SAX interface, building the value as json_sax_dom_parser does
// but appending object members (with a hash set per open object to refuse
// repeated keys), and tracking nesting.
class BoundedDomBuilder {
public:
    using number_integer_t = Json::number_integer_t;
    using number_unsigned_t = Json::number_unsigned_t;
    using number_float_t = Json::number_float_t;
    using string_t = Json::string_t;
    using binary_t = Json::binary_t;

    BoundedDomBuilder(Json& root, JsonRefusal& refusal) : root_(root), refusal_(refusal) {}

    bool null() { return value(nullptr); }
    bool boolean(bool v) { return value(v); }
    bool number_integer(number_integer_t v) { return value(v); }
    bool number_unsigned(number_unsigned_t v) { return value(v); }
    bool number_float(number_float_t v, const string_t&) { return value(v); }
    bool binary(binary_t& v) { return value(std::move(v)); }
    bool string(string_t& v)
    {
        // Remember node ids as they go by, to name the node in a refusal.
        if (!frames_.empty() && frames_.back().object && frames_.back().key == "id") frames_.back().id = v;
        return value(v);
    }

    bool start_object(std::size_t) { return open(true); }
    bool start_array(std::size_t) { return open(false); }
    bool end_object() { return close(); }
    bool end_array() { return close(); }

    bool key(string_t& k)
    {
        Frame& f = frames_.back();
        if (!f.keys.insert(k).second) {
            refuse(k, "appears twice in the same object (each field may be given once)", false);
            return false;
        }
        f.key = k;
        return true;
    }

    template <class Exception> bool parse_error(std::size_t byte, const std::string&, const Exception& e)
    {
        errorByte = byte;
        errorMessage = e.what();
        failed = true;
        return false;
    }

    bool failed = false;        // a syntax error (errorByte, errorMessage) or a refusal
    bool refused = false;       // refusal_ is set
    std::size_t errorByte = 0;
    std::string errorMessage;

private:
    struct Frame {
        Json* value;
        bool object;
        bool node = false;           // an object that is a feature-tree node
        bool nodeChildren = false;   // an array that is a node's "children"
        std::string id;              // the object's "id", once seen
        std::string key;             // the object's member being read
        std::unordered_set<std::string> keys;
    };

    template <class V> Json* place(V&& v)
    {
        if (frames_.empty()) {
            root_ = Json(std::forward<V>(v));
            return &root_;
        }
        Frame& f = frames_.back();
        if (!f.object) {
            f.value->get_ref<Json::array_t&>().emplace_back(std::forward<V>(v));
            return &f.value->get_ref<Json::array_t&>().back();
        }
        // Keys are unique (checked in key()): append without ordered_map's
        // linear search.
        ObjectBase& members = f.value->get_ref<Json::object_t&>();
        members.emplace_back(f.key, Json(std::forward<V>(v)));
        return &members.back().second;
    }

    template <class V> bool value(V&& v)
    {
        place(std::forward<V>(v));
        return true;
    }

    bool open(bool object)
    {
        if (int(frames_.size()) + 1 > limits::kMaxJsonDepth) {
            refuse("", "nested deeper than " + std::to_string(limits::kMaxJsonDepth) +
                           " levels of JSON (the format's limit)", true);
            return false;
        }
        bool node = false, nodeChildren = false;
        if (!frames_.empty()) {
            const Frame& parent = frames_.back();
            if (object) node = (frames_.size() == 1 && parent.key == "root") || (!parent.object && parent.nodeChildren);
            else nodeChildren = parent.node && parent.key == "children";
        }
        if (node && nodeDepth_ + 1 > limits::kMaxNestingDepth) {
            refuse("children", "the feature tree is nested deeper than " + std::to_string(limits::kMaxNestingDepth) +
                                   " levels (the format's limit)", false);
            return false;
        }
        Json* v = place(object ? Json::value_t::object : Json::value_t::array);
        frames_.push_back(Frame{v, object, node, nodeChildren, {}, {}, {}});
        nodeDepth_ += node;
        return true;
    }

    bool close()
    {
        nodeDepth_ -= frames_.back().node;
        frames_.pop_back();
        return true;
    }

    // Names the innermost node whose id is known; `field` empty: the field
    // of that node being read (or the top-level key).
    void refuse(const std::string& field, const std::string& reason, bool fieldFromNode)
    {
        failed = refused = true;
        refusal_.reason = reason;
        refusal_.field = field;
        for (auto it = frames_.rbegin(); it != frames_.rend(); ++it) {
            if (it->node && !it->id.empty()) {
                refusal_.nodeId = it->id;
                if (fieldFromNode) refusal_.field = it->key;
                return;
            }
        }
        if (fieldFromNode && !frames_.empty()) refusal_.field = frames_.front().key;
    }

    Json& root_;
    JsonRefusal& refusal_;
    std::vector<Frame> frames_;
    int nodeDepth_ = 0;
};

std::string lineColumn(std::string_view text, std::size_t byte)
{
    std::size_t line = 1, col = 1;
    for (std::size_t i = 0; i + 1 < byte && i < text.size(); ++i) {
        if (text[i] == '\n') {
            ++line;
            col = 1;
        } else {
            ++col;
        }
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(col);
}

std::string shortParseMessage(const std::string& what)
{
    // nlohmann: "[json.exception.parse_error.101] parse error at line 1, column 5: syntax error ..."
    const auto pos = what.find("syntax error");
    if (pos != std::string::npos) return what.substr(pos);
    const auto bracket = what.find("] ");
    return bracket == std::string::npos ? what : what.substr(bracket + 2);
}

} // namespace

std::optional<Json> parseBoundedJson(std::string_view original, JsonRefusal& refusal, bool& markedNumbers)
{
    const std::string marked = markNonFiniteNumbers(original, markedNumbers);
    const std::string_view text = markedNumbers ? std::string_view(marked) : original;
    Json root;
    BoundedDomBuilder builder(root, refusal);
    const bool ok = Json::sax_parse(text.begin(), text.end(), &builder, nlohmann::detail::input_format_t::json, true,
                                    false);
    if (ok && !builder.failed) return root;
    if (!builder.refused) {
        refusal.nodeId.clear();
        refusal.field.clear();
        refusal.reason = "malformed JSON at " + lineColumn(text, builder.errorByte) + ": " +
                         shortParseMessage(builder.errorMessage);
    }
    return std::nullopt;
}

} // namespace kerf::detail
