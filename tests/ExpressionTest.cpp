// Parametric parts: the expression language (document/Expression.hpp) and
// expressions in documents (named parameters, any numeric field, references
// to other nodes' fields): evaluation, units, every refusal with its words,
// the round trip through save and load, -D overrides, edits.

#include "kerf/document/Document.hpp"
#include "kerf/document/DocumentEdits.hpp"
#include "kerf/document/DocumentError.hpp"
#include "kerf/document/Expression.hpp"
#include "kerf/document/NodePlacement.hpp"
#include "kerf/document/ReferableNumbers.hpp"
#include "kerf/evaluator/CutList.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace kerf {
namespace {

using expr::Quantity;

// Names: a = 2 (bare), t = 18 mm; fields: seat.size[0] = 450 mm.
Quantity eval(const std::string& text)
{
    expr::Resolver r;
    r.name = [](std::string_view n) -> Quantity {
        if (n == "a") return Quantity::number(2.0);
        if (n == "t") return Quantity::lengthMm(18.0);
        throw expr::ExpressionError("uses the unknown name '" + std::string(n) + "'");
    };
    r.field = [](std::string_view id, std::string_view path) -> Quantity {
        if (id == "seat" && path == "size[0]") return Quantity::lengthMm(450.0);
        if (id == "leg-3" && path == "height") return Quantity::lengthMm(400.0);
        throw expr::ExpressionError("no such field");
    };
    return expr::evaluate(text, r);
}

double value(const std::string& text) { return eval(text).value; }

std::string refusal(const std::string& text)
{
    try {
        eval(text);
    } catch (const expr::ExpressionError& e) {
        return e.what();
    }
    return "(accepted)";
}

TEST(Expression, PrecedenceAssociativityAndFunctions)
{
    EXPECT_DOUBLE_EQ(value("1 + 2 * 3"), 7.0);
    EXPECT_DOUBLE_EQ(value("(1 + 2) * 3"), 9.0);
    EXPECT_DOUBLE_EQ(value("2 ^ 3 ^ 2"), 512.0); // right associative
    EXPECT_DOUBLE_EQ(value("-2 ^ 2"), 4.0);      // unary minus binds its operand first
    EXPECT_DOUBLE_EQ(value("10 - 4 - 3"), 3.0);
    EXPECT_DOUBLE_EQ(value("12 / 4 / 3"), 1.0);
    EXPECT_DOUBLE_EQ(value("--3"), 3.0);
    EXPECT_DOUBLE_EQ(value("min(4, 2, 8) + max(1, 5)"), 7.0);
    EXPECT_DOUBLE_EQ(value("abs(-3) + sqrt(16) + round(2.5) + floor(2.7) + ceil(2.1)"), 3 + 4 + 3 + 2 + 3);
    EXPECT_NEAR(value("sin(30) + cos(60) + tan(45)"), 2.0, 1e-12); // degrees
    EXPECT_DOUBLE_EQ(value("1.5e2"), 150.0);
}

TEST(Expression, LengthsCarryTheirUnits)
{
    EXPECT_DOUBLE_EQ(value("18mm"), 18.0);
    EXPECT_DOUBLE_EQ(value("1.8cm"), 18.0);
    EXPECT_DOUBLE_EQ(value("0.5m"), 500.0);
    EXPECT_DOUBLE_EQ(value("3/4in"), 19.05); // a fraction with a unit is one length
    EXPECT_DOUBLE_EQ(value("0.75\""), 19.05);
    EXPECT_DOUBLE_EQ(value("1ft"), 304.8);
    EXPECT_DOUBLE_EQ(value("1'"), 304.8);
    EXPECT_DOUBLE_EQ(value("2 * 3/4in"), 38.1);
    EXPECT_DOUBLE_EQ(value("3/4"), 0.75); // without a unit, a plain division
    EXPECT_DOUBLE_EQ(value("11 3/4in"), 298.45); // a whole number and a fraction
    EXPECT_DOUBLE_EQ(value("2 + 11 3/4in"), 300.45);
    EXPECT_DOUBLE_EQ(value("11 3/4"), 11.75); // without a unit, a bare mixed number
    // As every field shows a length, with a space: a newcomer's "18 mm" in
    // the Parameters table was refused ("has 'm' where an operator ...").
    EXPECT_DOUBLE_EQ(value("18 mm"), 18.0);
    EXPECT_EQ(eval("18 mm").length, 1);
    EXPECT_DOUBLE_EQ(value("3/4 in"), 19.05);
    EXPECT_DOUBLE_EQ(value("11 3/4 in"), 298.45);
    EXPECT_DOUBLE_EQ(value("2 * 9 mm + 1"), 19.0);
    EXPECT_NE(refusal("18 mmm").find("where an operator or the end was expected"), std::string::npos);
    EXPECT_TRUE(eval("11 3/4").bare);
    EXPECT_NE(refusal("11 3/0").find("divides by zero"), std::string::npos);
    EXPECT_NE(refusal("11 3").find("where an operator or the end was expected"), std::string::npos);
    EXPECT_EQ(eval("18mm").length, 1);
    EXPECT_FALSE(eval("18mm").bare);
    EXPECT_TRUE(eval("18").bare);
    EXPECT_EQ(eval("t * 2").length, 1);
    EXPECT_EQ(eval("t * t").length, 2);
    EXPECT_EQ(eval("t / t").length, 0);
    EXPECT_EQ(eval("sqrt(t * t)").length, 1);
    EXPECT_TRUE(eval("t + 2").fits(true));
    EXPECT_FALSE(eval("t * t").fits(true));
    EXPECT_FALSE(eval("t").fits(false));
}

// A field shown in inches: a bare number that meets a length is inches
// there; one that scales a length stays a factor.
TEST(Expression, BareNumbersMeetingLengthsTakeTheResolversUnit)
{
    expr::Resolver inches;
    inches.name = [](std::string_view) -> Quantity { throw expr::ExpressionError("no names"); };
    inches.field = [](std::string_view, std::string_view) -> Quantity { throw expr::ExpressionError("no fields"); };
    inches.bareLengthMm = 25.4;
    auto in = [&](const char* text) { return expr::evaluate(text, inches); };
    EXPECT_DOUBLE_EQ(in("3/4in + 1/8").value, 19.05 + 3.175);
    EXPECT_DOUBLE_EQ(in("1/8 + 3/4in").value, 3.175 + 19.05);
    EXPECT_DOUBLE_EQ(in("3/4in - 1/4").value, 12.7);
    EXPECT_DOUBLE_EQ(in("2 * 3/4in").value, 38.1);
    EXPECT_DOUBLE_EQ(in("min(1, 3/4in)").value, 19.05);
    EXPECT_DOUBLE_EQ(in("max(1, 3/4in)").value, 25.4);
    EXPECT_DOUBLE_EQ(in("18mm + 0").value, 18.0);
    EXPECT_TRUE(in("11 3/4 + 1/4").bare); // all bare: the caller says what it is
    EXPECT_DOUBLE_EQ(in("11 3/4 + 1/4").value, 12.0);
    EXPECT_DOUBLE_EQ(value("t + 2"), 20.0); // documents: bare numbers meeting lengths are millimetres

    // What a field shown in inches warns of before storing an expression.
    EXPECT_TRUE(expr::addsBareNumbersToLengths("depth - 2"));
    EXPECT_TRUE(expr::addsBareNumbersToLengths("max(seat.size[0], 300)"));
    EXPECT_TRUE(expr::addsBareNumbersToLengths("1 1/2 + board"));
    EXPECT_FALSE(expr::addsBareNumbersToLengths("2 * depth"));
    EXPECT_FALSE(expr::addsBareNumbersToLengths("depth / 2 - 3/4in"));
    EXPECT_FALSE(expr::addsBareNumbersToLengths("depth - 2mm"));
    EXPECT_FALSE(expr::addsBareNumbersToLengths("depth - (")); // does not parse: said elsewhere
}

TEST(Expression, NamesAndReferencesToOtherNodesFields)
{
    EXPECT_DOUBLE_EQ(value("t + a"), 20.0);
    EXPECT_DOUBLE_EQ(value("seat.size[0] - 70"), 380.0);
    EXPECT_DOUBLE_EQ(value("leg-3.height / 2"), 200.0); // an id with '-' before a '.'
    // A number with decimals after a name and '-' is a subtraction: no field
    // name starts with a digit (a newcomer's `depth-6.5` was refused as a
    // reference to a node `depth-6`).
    EXPECT_DOUBLE_EQ(value("t-6.5"), 11.5);
    EXPECT_DOUBLE_EQ(value("t-a-0.5mm"), 15.5);
    EXPECT_EQ(expr::uses("t-6.5").names, (std::vector<std::string>{"t"}));
    EXPECT_TRUE(expr::uses("t-6.5").references.empty());
    EXPECT_EQ(expr::uses("seat.size[0] - t * a + leg-3.height").names, (std::vector<std::string>{"t", "a"}));
    EXPECT_EQ(expr::uses("seat.size[0] - t * a + leg-3.height").references,
              (std::vector<std::string>{"seat.size[0]", "leg-3.height"}));
    EXPECT_EQ(expr::renameName("t + 2*t - tt + seat.t[0] + max(t, 1)", "t", "board"),
              "board + 2*board - tt + seat.t[0] + max(board, 1)");
}

TEST(Expression, RefusalsSayWhatIsWrong)
{
    EXPECT_NE(refusal("1 / (a - 2)").find("divides by zero"), std::string::npos);
    EXPECT_NE(refusal("t + t * t").find("unit mismatch"), std::string::npos);
    EXPECT_NE(refusal("sin(t)").find("unit mismatch"), std::string::npos);
    EXPECT_NE(refusal("sqrt(t)").find("unit mismatch"), std::string::npos);
    EXPECT_NE(refusal("t ^ 0.5").find("unit mismatch"), std::string::npos);
    EXPECT_NE(refusal("thikness").find("unknown name 'thikness'"), std::string::npos);
    EXPECT_NE(refusal("1 +").find("ends where a number or a name was expected"), std::string::npos);
    EXPECT_NE(refusal("(1 + 2").find("misses a ')'"), std::string::npos);
    EXPECT_NE(refusal("2 3").find("where an operator or the end was expected"), std::string::npos);
    EXPECT_NE(refusal("frob(2)").find("no function 'frob'"), std::string::npos);
    EXPECT_NE(refusal("min(2)").find("two or more"), std::string::npos);
    EXPECT_NE(refusal("").find("is empty"), std::string::npos);
    EXPECT_NE(refusal("sqrt(-4)").find("negative"), std::string::npos);
    EXPECT_NE(refusal("10 ^ 400").find("infinity"), std::string::npos);
    // Hostile sizes end in a sentence, not a crash.
    EXPECT_NE(refusal(std::string(5000, '1')).find("longer than"), std::string::npos);
    EXPECT_NE(refusal(std::string(1000, '(') + "1" + std::string(1000, ')')).find("nests too deeply"), std::string::npos);
    EXPECT_NE(refusal(std::string(1000, '-') + "1").find("nests too deeply"), std::string::npos);
    std::string tower = "2";
    for (int i = 0; i < 500; ++i) tower += "^2";
    EXPECT_NE(refusal(tower).find("nests too deeply"), std::string::npos);
    // The format's limit, exactly: 32 parentheses are read, 33 refused
    // (it was 31, and the message said "64 levels").
    EXPECT_EQ(refusal(std::string(32, '(') + "1" + std::string(32, ')')), "(accepted)");
    EXPECT_NE(refusal(std::string(33, '(') + "1" + std::string(33, ')')).find("more than 32 parentheses"),
              std::string::npos);
    EXPECT_NE(refusal("t ^ 1e10").find("beyond 8"), std::string::npos);
}

// ---------------------------------------------------------------------------
// In documents

const char* kShelfSide = R"({
  "format": "kerf",
  "version": 1,
  "parameters": [
    {
      "name": "thickness",
      "expression": "18mm",
      "unit": "length",
      "comment": "board stock"
    },
    {
      "name": "height",
      "expression": "720"
    },
    {
      "name": "rows",
      "expression": "round(height / 32) - 4"
    }
  ],
  "root": {
    "id": "side",
    "type": "difference",
    "children": [
      {
        "id": "board",
        "type": "box",
        "size": [
          "thickness",
          300.0,
          "height"
        ]
      },
      {
        "id": "holes",
        "type": "array",
        "count": [
          1,
          1,
          "rows"
        ],
        "step": [
          0.0,
          0.0,
          32.0
        ],
        "children": [
          {
            "id": "hole",
            "type": "cylinder",
            "radius": "board.size[0] / 6",
            "height": 12.0,
            "transform": {
              "translate": [
                0.0,
                0.0,
                "-height / 2 + 64"
              ]
            }
          }
        ]
      }
    ]
  }
}
)";

Document load(const std::string& text, const ParameterOverrides& o = {}) { return Document::parse(text, "side.kerf", o); }

std::string loadRefusal(const std::string& text, const ParameterOverrides& o = {})
{
    try {
        load(text, o);
    } catch (const DocumentError& e) {
        return e.what();
    }
    return "(accepted)";
}

std::string with(std::string text, const std::string& from, const std::string& to)
{
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return text.replace(at, from.size(), to);
}

TEST(DocumentExpressions, ParametersAndFieldsResolveInTheOrderTheirReferencesNeed)
{
    const Document d = load(kShelfSide);
    ASSERT_EQ(d.parameters.size(), 3u);
    EXPECT_EQ(d.parameters[0].name, "thickness");
    EXPECT_DOUBLE_EQ(d.parameters[0].value, 18.0);
    EXPECT_EQ(d.parameters[0].comment, "board stock");
    EXPECT_DOUBLE_EQ(d.parameters[2].value, 19.0); // round(720 / 32) - 4
    const Node& board = *d.root.find("board");
    EXPECT_EQ(board.as<BoxParams>().size, glm::dvec3(18, 300, 720));
    EXPECT_EQ(board.expressions.at("size[0]"), "thickness");
    const Node& holes = *d.root.find("holes");
    EXPECT_EQ(holes.as<ArrayParams>().count[2], 19);
    const Node& hole = *d.root.find("hole");
    EXPECT_DOUBLE_EQ(hole.as<CylinderParams>().radius, 3.0);
    EXPECT_DOUBLE_EQ(hole.transform.translate.z, -296.0);
    EXPECT_EQ(hole.expressions.at("transform.translate[2]"), "-height / 2 + 64");
}

// Decimal arithmetic lands beside whole numbers: (0.1 + 0.2) * 10 is
// 3.0000000000000004 in binary, and a count written so was refused as "not
// 3.0000000000000004 ... gives 3". Within rounding of a whole number it is
// that number; a count further off is refused.
TEST(DocumentExpressions, ACountWithinRoundingOfAWholeNumberIsThatNumber)
{
    for (const auto& [expression, count] : {std::pair{"(0.1 + 0.2) * 10", 3}, std::pair{"0.1 * 3 * 10", 3},
                                            std::pair{"(0.7 + 0.1) * 10", 8}, std::pair{"rows", 19}}) {
        const Document d = load(with(kShelfSide, "\"rows\"\n", std::string("\"") + expression + "\"\n"));
        EXPECT_EQ(d.root.find("holes")->as<ArrayParams>().count[2], count) << expression;
        EXPECT_EQ(d.root.find("holes")->expressions.at("count[2]"), expression);
    }
    EXPECT_NE(loadRefusal(with(kShelfSide, "\"rows\"\n", "\"3.000001\"\n")).find("gives 3.000001"), std::string::npos);
}

// The application shows features by name; expressions take ids. A newcomer
// typed "=Apron.size[0]" and was told only that no node 'Apron' exists.
TEST(DocumentExpressions, ANameWhereAnIdBelongsIsAnsweredWithTheId)
{
    const std::string r = loadRefusal(R"({"format":"kerf","version":1,"root":{"id":"u","type":"union","children":[
        {"id":"box-3","name":"Apron","type":"box","size":[360,20,80]},
        {"id":"box-4","name":"Tenon","type":"box","size":[25,10,"Apron.size[2] - 20"]}]}})");
    EXPECT_NE(r.find("the expression \"Apron.size[2] - 20\" refers to the node 'Apron', which does not exist: the "
                     "feature named Apron has the id 'box-3' (box-3.size[2])"),
              std::string::npos)
        << r;
}

TEST(DocumentExpressions, ExpressionsSurviveSaveAndLoadAsWritten)
{
    const Document d = load(kShelfSide);
    EXPECT_EQ(d.serialize(), kShelfSide);
    EXPECT_EQ(load(d.serialize()), d);
}

TEST(DocumentExpressions, DefinesFromTheCommandLineReplaceParameters)
{
    const Document d = load(kShelfSide, {{"thickness", "3/4in"}, {"height", "900"}});
    EXPECT_DOUBLE_EQ(d.root.find("board")->as<BoxParams>().size.x, 19.05);
    EXPECT_DOUBLE_EQ(d.root.find("board")->as<BoxParams>().size.z, 900.0);
    EXPECT_DOUBLE_EQ(d.root.find("hole")->as<CylinderParams>().radius, 19.05 / 6);
    EXPECT_EQ(d.root.find("holes")->as<ArrayParams>().count[2], 24);
    const std::string r = loadRefusal(kShelfSide, {{"thicknes", "19"}});
    EXPECT_NE(r.find("no parameter 'thicknes'"), std::string::npos) << r;
    EXPECT_NE(r.find("thickness, height, rows"), std::string::npos) << r;
}

TEST(DocumentExpressions, EveryRefusalNamesTheNodeTheFieldAndTheExpression)
{
    struct Case {
        std::string from, to, expect;
    };
    const Case cases[] = {
        {"\"round(height / 32) - 4\"", "\"rows + 1\"", "field 'parameters.rows': the expression \"rows + 1\" refers back to itself"},
        {"\"thickness\",\n          300", "\"thikness\",\n          300",
         "node 'board', field 'size[0]': the expression \"thikness\" uses the unknown name 'thikness': did you mean 'thickness'? (parameters: thickness, height, rows)"},
        {"\"board.size[0] / 6\"", "\"board.size[0] / (height - 720)\"", "node 'hole', field 'radius': the expression \"board.size[0] / (height - 720)\" divides by zero"},
        {"\"board.size[0] / 6\"", "\"thickness * thickness\"", "node 'hole', field 'radius': the expression \"thickness * thickness\" is a unit mismatch"},
        {"\"board.size[0] / 6\"", "\"thickness - 20\"",
         "node 'hole', field 'radius': must be > 0, not -2 (the expression \"thickness - 20\" gives -2)"},
        {"\"board.size[0] / 6\"", "\"seat.size[0]\"", "the expression \"seat.size[0]\" refers to the node 'seat', which does not exist"},
        {"\"board.size[0] / 6\"", "\"board.sise[0]\"", "refers to 'board.sise[0]', not a number of that node"},
        {"\"board.size[0] / 6\"", "\"hole.radius\"", "node 'hole', field 'radius': the expression \"hole.radius\" refers back to itself"},
        {"\"rows\"\n", "\"rows / 2\"\n",
         "node 'holes', field 'count[2]': is a count, a whole number, and the expression \"rows / 2\" gives 9.5 "
         "(round(), floor() or ceil() make a whole number of it)"},
        {"\"rows\"\n", "\"rows * 1e18\"\n",
         "node 'holes', field 'count[2]': is a count, and the expression \"rows * 1e18\" gives 1.9e+19, more than the "
         "20,000 primitive copies a document may have"},
        {"\"18mm\"", "\"18mm * 2mm\"", "field 'parameters.thickness': the expression \"18mm * 2mm\" gives a value of another unit where the parameter's unit is length"},
        {"\"expression\": \"720\"", "\"expression\": \"7 20\"", "field 'parameters.height': the expression \"7 20\" has '2' where an operator or the end was expected"},
        {"\"name\": \"height\"", "\"name\": \"thickness\"", "field 'parameters.thickness': is defined twice"},
        {"\"name\": \"height\"", "\"name\": \"2high\"", "field 'parameters[1].name': must be a name"},
    };
    for (const Case& c : cases) {
        const std::string r = loadRefusal(with(kShelfSide, c.from, c.to));
        EXPECT_NE(r.find(c.expect), std::string::npos) << "got: " << r << "\nwanted: " << c.expect;
        EXPECT_EQ(r.rfind("side.kerf: ", 0), 0u) << r;
    }
}

TEST(DocumentExpressions, AChainOfReferencesLongerThanTheBoundIsRefusedNotFollowed)
{
    // p0 = p1 + 1, p1 = p2 + 1, ...: the first needs all the others.
    std::string params;
    for (int i = 0; i < 5000; ++i)
        params += "{\"name\":\"p" + std::to_string(i) + "\",\"expression\":\"p" + std::to_string(i + 1) + " + 1\"},";
    const std::string text = R"({"format":"kerf","version":1,"parameters":[)" + params +
                             R"({"name":"p5000","expression":"1"}],"root":{"id":"s","type":"sphere","radius":"p0"}})";
    const std::string r = loadRefusal(text);
    EXPECT_NE(r.find("field 'parameters.p200': is reached through more than 200 references, one through the next, from 'p0'"),
              std::string::npos)
        << r;
    // The same chain written the other way round (each parameter refers to
    // the one before it) is as long: refused too. It was resolved one step
    // at a time and passed, 5000 long.
    std::string forward = R"({"name":"p0","expression":"1"})";
    for (int i = 1; i <= 300; ++i)
        forward += ",{\"name\":\"p" + std::to_string(i) + "\",\"expression\":\"p" + std::to_string(i - 1) + " + 1\"}";
    const std::string f = loadRefusal(R"({"format":"kerf","version":1,"parameters":[)" + forward +
                                      R"(],"root":{"id":"s","type":"sphere","radius":"p300"}})");
    EXPECT_NE(f.find("field 'parameters.p200': is reached through more than 200 references"), std::string::npos) << f;
    // 200 values in a row (the radius and 199 parameters) are read.
    std::string fits = R"({"name":"p0","expression":"1"})";
    for (int i = 1; i < 199; ++i)
        fits += ",{\"name\":\"p" + std::to_string(i) + "\",\"expression\":\"p" + std::to_string(i - 1) + " + 1\"}";
    EXPECT_NO_THROW(Document::parse(R"({"format":"kerf","version":1,"parameters":[)" + fits +
                                        R"(],"root":{"id":"s","type":"sphere","radius":"p198"}})",
                                    "fits.kerf"));
}

TEST(DocumentExpressions, AnEditFollowsThroughTheExpressionsThatReferToIt)
{
    Document d = load(kShelfSide);
    // A parameter changed: everything that uses it follows once resolved.
    d.parameters[0].expression = "19";
    const Document after = d.resolved();
    EXPECT_DOUBLE_EQ(after.root.find("board")->as<BoxParams>().size.x, 19.0);
    EXPECT_DOUBLE_EQ(after.root.find("hole")->as<CylinderParams>().radius, 19.0 / 6);
    EXPECT_TRUE(after.hasExpressions());

    // A number typed over a driven field replaces its expression; the others stay.
    Node board = *after.root.find("board");
    board.as<BoxParams>().size.x = 25.0;
    Document typed = after;
    edit::updateNode(typed, "board", board);
    EXPECT_FALSE(typed.root.find("board")->expressions.count("size[0]"));
    EXPECT_TRUE(typed.root.find("board")->expressions.count("size[2]"));
    EXPECT_DOUBLE_EQ(typed.resolved().root.find("hole")->as<CylinderParams>().radius, 25.0 / 6);

    // An edit that keeps the driven number keeps the expression.
    Node hole = *after.root.find("hole");
    hole.name = "Shelf pin";
    Document renamed = after;
    edit::updateNode(renamed, "hole", hole);
    EXPECT_EQ(renamed.root.find("hole")->expressions.size(), 2u);
}

// What stops a deletion: the expressions elsewhere that refer to a field of
// what goes (the hole's radius is the board's thickness over 6). What goes
// along (the hole under its array) does not count.
TEST(DocumentExpressions, TheUsesOfANodesFieldsAreFoundBeforeItGoes)
{
    const Document d = load(kShelfSide);
    EXPECT_EQ(edit::nodeUses(d, {"board"}), std::vector<std::string>{"hole.radius"});
    EXPECT_TRUE(edit::nodeUses(d, {"hole"}).empty());
    EXPECT_TRUE(edit::nodeUses(d, {"board", "holes"}).empty()); // the hole goes with its array
    EXPECT_TRUE(edit::nodeUses(d, {"absent"}).empty());
}

TEST(DocumentExpressions, ParametersAreAddedRenamedWithTheirUsesAndRemovedOnlyWhenUnused)
{
    Document d = load(kShelfSide);
    EXPECT_EQ(edit::addParameter(d, "width", "600"), "width");
    EXPECT_EQ(edit::addParameter(d, "width", "700"), "width2");
    EXPECT_THROW(edit::addParameter(d, "2wide", "1"), std::invalid_argument);

    EXPECT_EQ(edit::parameterUses(d, "height"),
              (std::vector<std::string>{"parameters.rows", "board.size[2]", "hole.transform.translate[2]"}));
    edit::renameParameter(d, "height", "tall");
    EXPECT_EQ(d.parameters[1].name, "tall");
    EXPECT_EQ(d.parameters[2].expression, "round(tall / 32) - 4");
    EXPECT_EQ(d.root.find("board")->expressions.at("size[2]"), "tall");
    EXPECT_EQ(d.root.find("hole")->expressions.at("transform.translate[2]"), "-tall / 2 + 64");
    const Document again = d.resolved();
    EXPECT_DOUBLE_EQ(again.root.find("board")->as<BoxParams>().size.z, 720.0);

    const Document before = d;
    EXPECT_THROW(edit::renameParameter(d, "tall", "thickness"), std::invalid_argument); // taken
    EXPECT_THROW(edit::renameParameter(d, "tall", "no good"), std::invalid_argument);
    EXPECT_THROW(edit::renameParameter(d, "absent", "x"), std::invalid_argument);
    // A unit's name would read as the unit after a number ("18mm").
    for (const char* unit : {"mm", "in", "m", "cm", "ft"}) {
        EXPECT_THROW(edit::renameParameter(d, "width2", unit), std::invalid_argument) << unit;
        EXPECT_THROW(edit::addParameter(d, unit, "1"), std::invalid_argument) << unit;
    }
    EXPECT_EQ(d, before);
    try {
        edit::removeParameter(d, "thickness");
        ADD_FAILURE() << "removed a parameter in use";
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()), "'thickness' is used by board.size[0]");
    }
    EXPECT_EQ(d, before);
    edit::removeParameter(d, "width2");
    EXPECT_EQ(d.parameters.size(), 4u);
}

TEST(DocumentExpressions, AFeatureDraggedAlongOneAxisKeepsTheExpressionsOfTheOthers)
{
    Document d = load(kShelfSide);
    d.root.find("hole")->expressions["transform.translate[0]"] = "thickness / 6";
    d = d.resolved();
    edit::moveNodeInWorld(d, "hole", {0.0, 0.0, 10.0});
    const Document after = d.resolved();
    EXPECT_DOUBLE_EQ(after.root.find("hole")->transform.translate.z, -286.0); // dragged, not put back
    EXPECT_FALSE(after.root.find("hole")->expressions.count("transform.translate[2]"));
    EXPECT_EQ(after.root.find("hole")->expressions.at("transform.translate[0]"), "thickness / 6");
}

// A drag of the move gizmo moves the coordinates the drag changes, except
// those set by an expression: the hole's z here ("-height / 2 + 64"). A
// newcomer's drag replaced such an expression without a word.
TEST(DocumentExpressions, ADragMovesOnlyTheCoordinatesNotSetByExpressions)
{
    Document d = load(kShelfSide);
    std::vector<int> held;
    EXPECT_EQ(edit::moveKeepingExpressions(d, "hole", {3.0, -2.0, 10.0}, &held), glm::dvec3(3.0, -2.0, 0.0));
    EXPECT_EQ(held, std::vector<int>{2});
    held.clear();
    EXPECT_EQ(edit::moveKeepingExpressions(d, "hole", {3.0, 0.0, 0.0}, &held), glm::dvec3(3.0, 0.0, 0.0));
    EXPECT_TRUE(held.empty());
    edit::moveNodeInWorld(d, "hole", edit::moveKeepingExpressions(d, "hole", {3.0, -2.0, 10.0}));
    const Document after = d.resolved();
    EXPECT_EQ(after.root.find("hole")->expressions.at("transform.translate[2]"), "-height / 2 + 64");
    EXPECT_DOUBLE_EQ(after.root.find("hole")->transform.translate.z, -296.0);
    EXPECT_DOUBLE_EQ(after.root.find("hole")->transform.translate.x, 3.0);

    // Under a turned parent the coordinate held is the node's own: with the
    // array turned a quarter about Y, the hole's z runs along world X.
    d.root.find("holes")->transform.rotate = {0.0, 90.0, 0.0};
    held.clear();
    EXPECT_LT(glm::length(edit::moveKeepingExpressions(d, "hole", {5.0, 0.0, 0.0}, &held)), 1e-9);
    EXPECT_EQ(held, std::vector<int>{2});
    held.clear();
    const glm::dvec3 along = edit::moveKeepingExpressions(d, "hole", {0.0, 0.0, 5.0}, &held);
    EXPECT_LT(glm::length(along - glm::dvec3(0.0, 0.0, 5.0)), 1e-9);
    EXPECT_TRUE(held.empty());
}

TEST(DocumentExpressions, ADocumentWithoutExpressionsHasNone)
{
    const Document d = load(R"({"format":"kerf","version":1,"root":{"id":"s","type":"sphere","radius":5}})");
    EXPECT_FALSE(d.hasExpressions());
    EXPECT_TRUE(d.parameters.empty());
}

} // namespace
} // namespace kerf

namespace kerf {
namespace {

// The parametric bookshelf side at its parameters' values is the plain one.
void expectSameGeometry(const Node& a, const Node& b)
{
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(a.type, b.type) << a.id;
    EXPECT_EQ(a.params, b.params) << a.id;
    EXPECT_EQ(a.transform.translate, b.transform.translate) << a.id;
    EXPECT_EQ(a.transform.rotate, b.transform.rotate) << a.id;
    ASSERT_EQ(a.children.size(), b.children.size()) << a.id;
    for (std::size_t i = 0; i < a.children.size(); ++i) expectSameGeometry(a.children[i], b.children[i]);
}

const std::string kExamples = KERF_EXAMPLES_DIR;

TEST(ParametricExample, TheBookshelfSideAtItsDefaultsIsTheBundledOne)
{
    const Document plain = Document::load(kExamples + "/bookshelf-side.kerf");
    const Document parametric = Document::load(kExamples + "/bookshelf-side-parametric.kerf");
    ASSERT_EQ(parametric.parameters.size(), 6u);
    EXPECT_DOUBLE_EQ(parametric.parameters[5].value, 47.0); // pin rows
    expectSameGeometry(parametric.root, plain.root);
}

TEST(ParametricExample, ThicknessHeightAndRowsFollowTheirParametersIntoTheCutList)
{
    const Document thicker = Document::load(kExamples + "/bookshelf-side-parametric.kerf",
                                            {{"thickness", "3/4in"}, {"height", "2000"}});
    const Node& panel = *thicker.root.find("panel");
    EXPECT_DOUBLE_EQ(panel.as<BoxParams>().size.x, 19.05);
    EXPECT_DOUBLE_EQ(panel.as<BoxParams>().size.z, 2000.0);
    EXPECT_DOUBLE_EQ(panel.transform.translate.z, 1000.0);
    // The top dado and the pin rows move with the height; the joinery keeps its depth from the face.
    EXPECT_DOUBLE_EQ(thicker.root.find("dado-top")->transform.translate.z, 1962.0);
    EXPECT_EQ(thicker.root.find("shelf-pin-holes")->as<ArrayParams>().count[2], 53);
    EXPECT_DOUBLE_EQ(thicker.root.find("dado-bottom")->transform.translate.x, 19.05 / 2 - 8 + 4.5);
    // The cut list shows the new board.
    const std::vector<CutListRow> rows = cutList(thicker);
    ASSERT_FALSE(rows.empty());
    EXPECT_NEAR(rows.front().thickness, 19.05, rows.front().uncertainty + 1e-6);
    EXPECT_NEAR(rows.front().length, 2000.0, rows.front().uncertainty + 1e-6);
}

// What the property fields offer while a reference is typed: every one of
// them resolves, to the number the feature holds.
TEST(ParametricExample, EveryReferableNumberOfEveryExampleResolves)
{
    for (const char* name : {"door-frame", "side-chair", "stool", "table-top", "turned-leg", "bookshelf-side"}) {
        Document d = Document::load(kExamples + "/" + name + ".kerf");
        const std::vector<std::string> refs = referableNumbers(d);
        ASSERT_GT(refs.size(), 10u) << name;
        const std::size_t before = d.parameters.size();
        for (std::size_t i = 0; i < refs.size(); ++i) {
            Parameter p;
            p.name = "ref" + std::to_string(i);
            p.expression = refs[i];
            d.parameters.push_back(p);
        }
        const Document resolved = Document::parse(d.serialize(), name);
        for (std::size_t i = 0; i < refs.size(); ++i)
            EXPECT_TRUE(std::isfinite(resolved.parameters[before + i].value)) << name << ": " << refs[i];
    }
    const Document door = Document::load(kExamples + "/door-frame.kerf");
    const std::vector<std::string> refs = referableNumbers(door);
    for (const char* ref : {"panel-tongue.size[2]", "hinge-cup.transform.translate[0]", "panel-field.distance"})
        EXPECT_NE(std::find(refs.begin(), refs.end(), ref), refs.end()) << ref;
}

} // namespace
} // namespace kerf
