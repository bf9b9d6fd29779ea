#include "kerf/document/Node.hpp"

#include <cstdio>

namespace kerf {

namespace {
int hexDigit(char c)
{
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}
} // namespace

std::optional<Color> parseColor(std::string_view text)
{
    if (text.size() != 7 || text[0] != '#') return std::nullopt;
    int v[6];
    for (int i = 0; i < 6; ++i) {
        v[i] = hexDigit(text[static_cast<std::size_t>(i) + 1]);
        if (v[i] < 0) return std::nullopt;
    }
    return Color{static_cast<std::uint8_t>(v[0] * 16 + v[1]), static_cast<std::uint8_t>(v[2] * 16 + v[3]),
                 static_cast<std::uint8_t>(v[4] * 16 + v[5])};
}

std::string formatColor(Color c)
{
    char buf[8];
    std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c.r, c.g, c.b);
    return buf;
}

const Node* Node::find(std::string_view nodeId) const
{
    if (id == nodeId) return this;
    for (const auto& c : children)
        if (const Node* n = c.find(nodeId)) return n;
    return nullptr;
}

Node* Node::find(std::string_view nodeId)
{
    return const_cast<Node*>(static_cast<const Node*>(this)->find(nodeId));
}

std::size_t Node::count() const
{
    std::size_t n = 1;
    for (const auto& c : children) n += c.count();
    return n;
}

} // namespace kerf
