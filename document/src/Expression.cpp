#include "kerf/document/Expression.hpp"


#include <cctype>
#include <cmath>
#include <functional>
#include <cstdlib>
#include <numbers>
#include <optional>

namespace kerf::expr {

namespace {

bool isNameStart(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool isNameChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }
bool isIdChar(char c) { return isNameChar(c) || c == '-'; }

std::string describe(const Quantity& q)
{
    if (q.bare || q.length == 0) return "a plain number";
    if (q.length == 1) return "a length";
    if (q.length == 2) return "an area";
    if (q.length == 3) return "a volume";
    return "mm^" + std::to_string(q.length);
}

// Millimetres per unit, for the units a literal may carry.
std::optional<double> unitScale(std::string_view u)
{
    if (u == "mm") return 1.0;
    if (u == "cm") return 10.0;
    if (u == "m") return 1000.0;
    if (u == "in" || u == "\"") return 25.4;
    if (u == "ft" || u == "'") return 304.8;
    return std::nullopt;
}

// Recursive descent over the text, evaluating as it goes. With no resolver
// (uses(), renameName()) names and references are only recorded, as 1.
class Parser {
public:
    Parser(std::string_view text, const Resolver* resolver) : s_(text), resolver_(resolver) {}

    Quantity parse()
    {
        if (s_.size() > kMaxLength) throw ExpressionError("is longer than " + std::to_string(kMaxLength) + " characters");
        skipSpace();
        if (at_ >= s_.size()) fail("is empty");
        Quantity q = sum();
        skipSpace();
        if (at_ < s_.size()) fail("has '" + std::string(s_.substr(at_, 1)) + "' where an operator or the end was expected");
        return q;
    }

    Uses uses;
    // Where each plain name was written (for renaming): offset and length.
    std::vector<std::pair<std::size_t, std::size_t>> nameSpans;

private:
    [[noreturn]] void fail(const std::string& what) const
    {
        throw ExpressionError(at_ < s_.size() ? what + " (at character " + std::to_string(at_ + 1) + ")" : what);
    }

    void skipSpace()
    {
        while (at_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[at_]))) ++at_;
    }
    bool eat(char c)
    {
        skipSpace();
        if (at_ < s_.size() && s_[at_] == c) {
            ++at_;
            return true;
        }
        return false;
    }

    // A bare number meeting a length is a length in the resolver's unit
    // for bare lengths (millimetres unless a field is shown in inches).
    double asLength(const Quantity& bare, const Quantity& other) const
    {
        return other.length == 1 && resolver_ ? bare.value * resolver_->bareLengthMm : bare.value;
    }

    /// a (op) b for +, -, min and max: the same dimension on both sides.
    template <typename Op>
    Quantity combineAdditive(const Quantity& a, const Quantity& b, Op op, const char* verb) const
    {
        if (a.bare && b.bare) return {op(a.value, b.value), 0, true};
        if (a.bare) return {op(asLength(a, b), b.value), b.length, false};
        if (b.bare) return {op(a.value, asLength(b, a)), a.length, false};
        if (a.length != b.length)
            throw ExpressionError(std::string("is a unit mismatch: ") + verb + " " + describe(b) + " and " + describe(a));
        return {op(a.value, b.value), a.length, false};
    }

    Quantity sum()
    {
        Quantity q = product();
        for (;;) {
            if (eat('+')) {
                const Quantity r = product();
                q = combineAdditive(q, r, std::plus<>(), "adds");
            } else if (eat('-')) {
                const Quantity r = product();
                q = combineAdditive(q, r, std::minus<>(), "subtracts");
            } else {
                return q;
            }
        }
    }

    Quantity product()
    {
        Quantity q = power();
        for (;;) {
            if (eat('*')) {
                const Quantity r = power();
                q = {q.value * r.value, q.length + r.length, q.bare && r.bare};
            } else if (eat('/')) {
                const std::size_t where = at_;
                const Quantity r = power();
                if (r.value == 0.0 && resolver_) {
                    at_ = where;
                    fail("divides by zero");
                }
                q = {resolver_ ? q.value / r.value : 1.0, q.length - r.length, q.bare && r.bare};
            } else {
                return q;
            }
        }
    }

    Quantity power()
    {
        const Nest nest(*this);
        const Quantity base = unary();
        if (!eat('^')) return base;
        const Quantity e = power();
        if (!e.bare && e.length != 0) fail("is a unit mismatch: an exponent must be a plain number, not " + describe(e));
        if (base.bare || base.length == 0) return {std::pow(base.value, e.value), 0, base.bare};
        if (e.value != std::round(e.value)) fail("is a unit mismatch: a length to a fractional power");
        if (std::fabs(e.value) > 8.0) fail("raises a length to a power beyond 8");
        return {std::pow(base.value, e.value), base.length * int(e.value), false};
    }

    Quantity unary()
    {
        const Nest nest(*this);
        if (eat('-')) {
            Quantity q = unary();
            q.value = -q.value;
            return q;
        }
        if (eat('+')) return unary();
        return atom();
    }

    // A unit after a number ("18mm", "3/4in", "2'"), if there is one; a
    // unit's name may follow a space ("18 mm", as every field displays a
    // length: a newcomer's "18 mm" typed in the Parameters table was
    // refused). No name can be a unit's (the reader refuses such names).
    std::optional<double> unitHere()
    {
        if (at_ < s_.size() && (s_[at_] == '"' || s_[at_] == '\'')) return unitScale(s_.substr(at_++, 1));
        std::size_t start = at_;
        while (start < s_.size() && s_[start] == ' ') ++start;
        std::size_t end = start;
        while (end < s_.size() && std::isalpha(static_cast<unsigned char>(s_[end]))) ++end;
        if (end == start || (end < s_.size() && isNameChar(s_[end]))) return std::nullopt;
        const std::optional<double> scale = unitScale(s_.substr(start, end - start));
        if (scale) at_ = end;
        return scale;
    }

    std::optional<double> numberHere()
    {
        const char* begin = s_.data() + at_;
        if (at_ >= s_.size() || !(std::isdigit(static_cast<unsigned char>(*begin)) || *begin == '.')) return std::nullopt;
        // strtod needs a terminated string: copy the number's characters.
        std::size_t end = at_;
        while (end < s_.size() && (std::isdigit(static_cast<unsigned char>(s_[end])) || s_[end] == '.')) ++end;
        if (end < s_.size() && (s_[end] == 'e' || s_[end] == 'E') && end + 1 < s_.size() &&
            (std::isdigit(static_cast<unsigned char>(s_[end + 1])) ||
             ((s_[end + 1] == '-' || s_[end + 1] == '+') && end + 2 < s_.size() &&
              std::isdigit(static_cast<unsigned char>(s_[end + 2]))))) {
            end += 2;
            while (end < s_.size() && std::isdigit(static_cast<unsigned char>(s_[end]))) ++end;
        }
        const std::string digits(s_.substr(at_, end - at_));
        char* stop = nullptr;
        const double v = std::strtod(digits.c_str(), &stop);
        if (stop != digits.c_str() + digits.size()) fail("has a malformed number '" + digits + "'");
        at_ = end;
        return v;
    }

    Quantity literal(double a)
    {
        const std::size_t afterA = at_;
        // "11 3/4in": a whole number and a fraction with a unit, as a woodworker writes it.
        if (a == std::floor(a) && at_ < s_.size() && s_[at_] == ' ') {
            while (at_ < s_.size() && s_[at_] == ' ') ++at_;
            if (const std::optional<double> b = numberHere(); b && at_ < s_.size() && s_[at_] == '/') {
                ++at_;
                if (const std::optional<double> c = numberHere()) {
                    if (*c == 0.0) fail("divides by zero");
                    if (const std::optional<double> scale = unitHere()) return Quantity::lengthMm((a + *b / *c) * *scale);
                    // "11 3/4" without a unit: a bare number, in the unit of what it meets.
                    return Quantity::number(a + *b / *c);
                }
            }
            at_ = afterA;
        }
        // "3/4in": a fraction with a unit is one length.
        if (at_ < s_.size() && s_[at_] == '/') {
            ++at_;
            if (const std::optional<double> b = numberHere()) {
                if (const std::optional<double> scale = unitHere()) {
                    if (*b == 0.0) fail("divides by zero");
                    return Quantity::lengthMm(a / *b * *scale);
                }
            }
            at_ = afterA; // a plain division: product() takes it
        }
        if (const std::optional<double> scale = unitHere()) return Quantity::lengthMm(a * *scale);
        return Quantity::number(a);
    }

    Quantity function(const std::string& f)
    {
        std::vector<Quantity> args;
        do args.push_back(sum());
        while (eat(','));
        if (!eat(')')) fail("misses ')' after the arguments of " + f);
        auto one = [&] {
            if (args.size() != 1) fail("gives " + f + " " + std::to_string(args.size()) + " arguments (it takes one)");
            return args[0];
        };
        auto angle = [&] {
            const Quantity a = one();
            if (!a.bare && a.length != 0) fail("is a unit mismatch: " + f + " of " + describe(a) + " (it takes degrees)");
            return a.value * std::numbers::pi / 180.0;
        };
        if (f == "min" || f == "max") {
            if (args.size() < 2) fail("gives " + f + " one argument (it takes two or more)");
            Quantity q = args[0];
            for (std::size_t i = 1; i < args.size(); ++i)
                q = combineAdditive(
                    q, args[i], [&](double x, double y) { return f == "min" ? std::min(x, y) : std::max(x, y); },
                    "compares");
            return q;
        }
        if (f == "abs") return {std::fabs(one().value), args[0].length, args[0].bare};
        if (f == "round") return {std::round(one().value), args[0].length, args[0].bare};
        if (f == "floor") return {std::floor(one().value), args[0].length, args[0].bare};
        if (f == "ceil") return {std::ceil(one().value), args[0].length, args[0].bare};
        if (f == "sqrt") {
            const Quantity a = one();
            if (!a.bare && a.length % 2 != 0) fail("is a unit mismatch: the square root of " + describe(a));
            if (a.value < 0.0 && resolver_) fail("takes the square root of a negative number");
            return {std::sqrt(a.value), a.length / 2, a.bare};
        }
        if (f == "sin") return Quantity::number(std::sin(angle()));
        if (f == "cos") return Quantity::number(std::cos(angle()));
        if (f == "tan") return Quantity::number(std::tan(angle()));
        fail("has no function '" + f + "' (min, max, abs, sqrt, sin, cos, tan, round, floor, ceil)");
    }

    Quantity atom()
    {
        skipSpace();
        if (at_ >= s_.size()) fail("ends where a number or a name was expected");
        if (eat('(')) {
            const Quantity q = sum();
            if (!eat(')')) fail("misses a ')'");
            return q;
        }
        if (const std::optional<double> v = numberHere()) return literal(*v);
        if (!isNameStart(s_[at_])) fail("has '" + std::string(s_.substr(at_, 1)) + "' where a number or a name was expected");
        // A node id (which may hold '-') when a '.' and a field name follow
        // it, else a name: `leg-3.height` is a reference, `depth-6.5` is
        // depth minus 6.5 (a field name never starts with a digit; it was
        // read as the node `depth-6` and refused).
        std::size_t idEnd = at_;
        while (idEnd < s_.size() && isIdChar(s_[idEnd])) ++idEnd;
        if (idEnd + 1 < s_.size() && s_[idEnd] == '.' && isNameStart(s_[idEnd + 1])) return reference(idEnd);
        const std::size_t start = at_;
        while (at_ < s_.size() && isNameChar(s_[at_])) ++at_;
        const std::string name(s_.substr(start, at_ - start));
        if (eat('(')) return function(name);
        uses.names.push_back(name);
        nameSpans.emplace_back(start, name.size());
        if (!resolver_) return Quantity::number(1.0);
        return resolver_->name(name);
    }

    Quantity reference(std::size_t idEnd)
    {
        const std::string id(s_.substr(at_, idEnd - at_));
        at_ = idEnd;
        std::string path;
        while (at_ < s_.size() && s_[at_] == '.') {
            ++at_;
            const std::size_t k = at_;
            while (at_ < s_.size() && isNameChar(s_[at_])) ++at_;
            if (k == at_) fail("has a '.' without a field name after '" + id + "'");
            if (!path.empty()) path += '.';
            path += s_.substr(k, at_ - k);
        }
        while (at_ < s_.size() && s_[at_] == '[') {
            const std::size_t k = ++at_;
            while (at_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[at_]))) ++at_;
            if (k == at_ || at_ >= s_.size() || s_[at_] != ']') fail("has an index that is not a whole number in []");
            path += "[" + std::string(s_.substr(k, at_ - k)) + "]";
            ++at_;
        }
        uses.references.push_back(id + "." + path);
        if (!resolver_) return Quantity::number(1.0);
        return resolver_->field(id, path);
    }

    // Bounds that keep a hostile file's expression from exhausting the stack.
    static constexpr std::size_t kMaxLength = 4096;
    // The format's limit is 32 parentheses; each level of them is two of
    // the parser's (a power and a sign), and the top level two more.
    static constexpr int kMaxParentheses = 32;
    static constexpr int kMaxNesting = 2 * kMaxParentheses + 2;
    struct Nest {
        Parser& p;
        explicit Nest(Parser& parser) : p(parser)
        {
            if (++p.nesting_ > kMaxNesting)
                p.fail("nests too deeply: more than " + std::to_string(kMaxParentheses) + " parentheses (or signs)");
        }
        ~Nest() { --p.nesting_; }
    };
    int nesting_ = 0;

    std::string_view s_;
    std::size_t at_ = 0;
    const Resolver* resolver_;
};

} // namespace

Quantity evaluate(std::string_view text, const Resolver& resolver)
{
    Parser p(text, &resolver);
    const Quantity q = p.parse();
    if (!std::isfinite(q.value)) throw ExpressionError("gives " + std::string(std::isnan(q.value) ? "no number" : "infinity"));
    return q;
}

Uses uses(std::string_view text)
{
    Parser p(text, nullptr);
    p.parse();
    return p.uses;
}

bool addsBareNumbersToLengths(std::string_view text)
{
    // Evaluated twice, a bare number meeting a length worth 1 mm and then
    // 2 mm: only a number that meets a length changes the result.
    Resolver r;
    r.name = [](std::string_view) { return Quantity::lengthMm(1.0); };
    r.field = [](std::string_view, std::string_view) { return Quantity::lengthMm(1.0); };
    try {
        const double once = evaluate(text, r).value;
        r.bareLengthMm = 2.0;
        return evaluate(text, r).value != once;
    } catch (const ExpressionError&) {
        return false;
    }
}

bool isUnitName(std::string_view name) { return unitScale(name).has_value(); }

std::string renameName(std::string_view text, std::string_view from, std::string_view to)
{
    Parser p(text, nullptr);
    p.parse();
    std::string out(text);
    // Back to front, so that earlier offsets stay valid.
    for (auto it = p.nameSpans.rbegin(); it != p.nameSpans.rend(); ++it)
        if (text.substr(it->first, it->second) == from) out.replace(it->first, it->second, to);
    return out;
}

} // namespace kerf::expr
