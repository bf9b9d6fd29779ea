#pragma once
// The expressions a document may hold instead of a number (a named
// parameter's value, any numeric field of a node): arithmetic on lengths
// with their units, for parametric furniture ("board + 2 * 6mm",
// "seat.size[0] - 70", "3/4in").
//
//   sum     := product (('+' | '-') product)*
//   product := power (('*' | '/') power)*
//   power   := unary ('^' power)?                 (right associative)
//   unary   := '-' unary | '+' unary | atom
//   atom    := literal | name | reference | function '(' sum (',' sum)* ')' | '(' sum ')'
//   literal := number [unit] | number '/' number unit      ("3/4in" is three quarters of an inch)
//            | integer ' ' number '/' number [unit]         ("11 3/4in"; "11 3/4" is bare)
//   unit    := mm | cm | m | in | " | ft | '
//   reference := node-id '.' key ('.' key)* ('[' integer ']')*   ("seat.size[0]", "leg.transform.translate[2]")
//   function: min, max (two or more), abs, sqrt, sin, cos, tan (degrees), round, floor, ceil
//
// A node id may contain '-' ("leg-3.height"); a name before '-' without a
// '.' after it is a subtraction ("width-18" is width minus 18).
//
// Units: a literal with a unit is a length in millimetres; a bare number
// takes the unit of what it meets (18 in a length field is 18 mm, in an
// angle 18 degrees). Adding a length to an area or to a plain ratio, taking
// the sine of a length or the root of a length are unit mismatches.

#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace kerf::expr {

/// A value and its dimension: millimetres to the power `length` (0: a
/// plain number, 1: a length, 2: an area), or `bare` (a number written
/// without a unit, which takes the dimension of what it meets).
struct Quantity {
    double value = 0.0;
    int length = 0;
    bool bare = true;

    static Quantity number(double v) { return {v, 0, true}; }
    static Quantity lengthMm(double v) { return {v, 1, false}; }
    /// A length, a bare number or a plain number: what a field of `wantLength` accepts.
    bool fits(bool wantLength) const { return bare || length == (wantLength ? 1 : 0); }
};

/// What a name or a reference in an expression means, asked while it is
/// evaluated; throws ExpressionError (or anything else) to refuse.
struct Resolver {
    std::function<Quantity(std::string_view name)> name;
    /// `nodeId`, then the path inside it ("size[0]", "transform.translate[2]").
    std::function<Quantity(std::string_view nodeId, std::string_view path)> field;
    /// The millimetres a bare number stands for where it meets a length
    /// ("thickness + 2"): 1 in documents; 25.4 in a field whose lengths are
    /// shown in inches, where "2" means two inches.
    double bareLengthMm = 1.0;
};

/// A refusal, with a sentence for people ("unknown name 'thikness'").
class ExpressionError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Evaluates `text`. Throws ExpressionError for a syntax error, a division
/// by zero, a unit mismatch, a non-finite result or a refusal of the resolver.
Quantity evaluate(std::string_view text, const Resolver& resolver);

/// The names and references `text` uses, in order (references as
/// "node-id.path"), without evaluating it. Throws ExpressionError for a
/// syntax error.
struct Uses {
    std::vector<std::string> names;
    std::vector<std::string> references; // "seat.size[0]"
};
Uses uses(std::string_view text);

/// Whether `text` adds (subtracts, compares) a number written without a
/// unit to a length, taking every name and reference for a length
/// ("depth - 2": yes; "2 * depth", "depth - 2mm": no). In a document such a
/// number is millimetres, which a person who sees inches may not mean.
/// False for text that does not evaluate.
bool addsBareNumbersToLengths(std::string_view text);

/// `text` with every use of the name `from` spelt `to` (a parameter
/// renamed); everything else as it was written.
std::string renameName(std::string_view text, std::string_view from, std::string_view to);

/// Whether `name` is a unit a number may carry ("mm", "in", "m"...): a
/// parameter so named would read as the unit after a number ("18mm").
bool isUnitName(std::string_view name);

} // namespace kerf::expr
