// Loading, validating and saving documents: every refusal in the spec's list
// names the file, the node id and the field and changes nothing; round trips
// keep every field, unknown ones included; saves are atomic.

#include "kerf/document/Document.hpp"
#include "kerf/document/DocumentError.hpp"
#include "kerf/document/UnknownFields.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace kerf {
namespace {

namespace fs = std::filesystem;

const char* kValid = R"({
  "format": "kerf",
  "version": 1,
  "units": "mm",
  "name": "Test part",
  "settings": { "feature_size": 0.5, "vendor_setting": {"a": 1} },
  "root": { "id": "root", "type": "difference", "color": "#8b5a2b", "x_note": "kept",
    "children": [
      { "id": "board", "type": "box", "size": [100, 50, 18], "round": 2, "transform": { "translate": [0, 0, 9], "x_t": 1 } },
      { "id": "hole", "type": "cylinder", "radius": 4, "height": 40, "name": "Dowel hole" },
      { "id": "holes", "type": "array", "count": [2, 1, 1], "step": [40, 0, 0], "children": [
        { "id": "pin", "type": "cone", "radius_bottom": 2.5, "radius_top": 2, "height": 12 } ] },
      { "id": "cut", "type": "extrude", "profile": [[0,0],[10,0],[10,5],[0,5]], "height": 3, "visible": false },
      { "id": "ring", "type": "torus", "major_radius": 10, "minor_radius": 1 },
      { "id": "m", "type": "mirror", "normal": [0, 3, 0], "offset": 6, "children": [
        { "id": "sh", "type": "shell", "thickness": 1, "children": [
          { "id": "off", "type": "offset", "distance": -0.5, "children": [
            { "id": "ball", "type": "sphere", "radius": 3 } ] } ] } ] },
      { "id": "cap", "type": "intersection", "blend": 1.5, "children": [
        { "id": "s2", "type": "sphere", "radius": 5 },
        { "id": "hs", "type": "halfspace", "normal": [0, 0, 1], "offset": 1 } ] }
    ] },
  "meshes": [ { "id": "hinge", "path": "hinge.stl", "transform": { "translate": [1, 2, 3] }, "color": "#a0a0a0", "x_m": true } ],
  "x_top": [1, 2, 3]
})";

Document valid() { return Document::parse(kValid, "valid.kerf"); }

// Replaces the first occurrence of `from` in the valid document with `to`.
std::string variant(const std::string& from, const std::string& to)
{
    std::string s = kValid;
    const auto pos = s.find(from);
    EXPECT_NE(pos, std::string::npos) << "test bug: '" << from << "' not in the document";
    if (pos != std::string::npos) s.replace(pos, from.size(), to);
    return s;
}

struct Refusal {
    std::string name;
    std::string text;
    std::string nodeId;
    std::string field;
    std::string reasonContains;
};

std::vector<Refusal> refusals()
{
    return {
        {"MalformedJson", variant(R"("units": "mm",)", R"("units": "mm" "oops",)"), "", "", "malformed JSON at line 4"},
        {"NotAnObject", "[1, 2]", "", "", "JSON object"},
        // Not JSON at all: said what it is, not "syntax error ... last read: '\x89'".
        {"APngImage", "\x89PNG\r\n\x1a\n\0\0\0\rIHDR", "", "", "not a Kerf document: a Kerf document is JSON text"},
        {"APngImageSaysSo", "\x89PNG\r\n", "", "", "this is a PNG image"},
        {"PlainText", "hello, this is a note", "", "", "this starts with the text 'hello, this is a note'"},
        {"AnAsciiStl", "solid leg\n facet normal 0 0 1", "", "", "looks like an ASCII STL mesh"},
        // Kerf's own export, one triangle: its header is text, its size says what it is.
        {"ABinaryStl", "binary STL file from kerf" + std::string(80 - 25, ' ') + std::string("\x01\0\0\0", 4) + std::string(50, '\0'),
         "", "", "this is a binary STL mesh of 1 triangle (Kerf shows meshes beside the part: Add > Reference Mesh)"},
        {"BinaryData", std::string("\x01\x02\x03\xFE", 4), "", "", "this holds binary data"},
        {"MissingFormat", variant(R"("format": "kerf",)", ""), "", "format", "missing"},
        {"WrongFormat", variant(R"("format": "kerf")", R"("format": "stl")"), "", "format", "\"kerf\""},
        {"NewerVersion", variant(R"("version": 1)", R"("version": 2)"), "", "version", "newer"},
        {"FractionalVersion", variant(R"("version": 1)", R"("version": 1.0)"), "", "version", "integer"},
        {"Units", variant(R"("units": "mm")", R"("units": "in")"), "", "units", "only \"mm\""},
        {"UnknownType", variant(R"("type": "torus")", R"("type": "donut")"), "ring", "type", "unknown type 'donut'"},
        {"MissingRequired", variant(R"(, "height": 40)", ""), "hole", "height", "missing"},
        {"MissingId", variant(R"("id": "ring", )", ""), "", "root.children[4].id", "missing"},
        {"WrongKindObject", variant(R"("radius": 4)", R"("radius": {"mm": 4})"), "hole", "radius", "must be a number"},
        // A string is an expression (parameters, issue 16); one that does not read is refused as such.
        {"BadExpression", variant(R"("radius": 4)", R"("radius": "4 +")"), "hole", "radius", "the expression \"4 +\""},
        {"WrongKindArray", variant(R"("size": [100, 50, 18])", R"("size": [100, 50])"), "board", "size", "3 numbers"},
        {"WrongKindBool", variant(R"("visible": false)", R"("visible": 0)"), "cut", "visible", "true or false"},
        {"Infinite", variant(R"("radius": 4)", R"("radius": 1e999)"), "hole", "radius", "finite"},
        {"NegativeInfinite", variant(R"("translate": [0, 0, 9])", R"("translate": [0, -1E+400, 9])"), "board", "transform.translate[1]", "finite"},
        {"NegativeRadius", variant(R"("radius": 4)", R"("radius": -4)"), "hole", "radius", "> 0"},
        {"ZeroSize", variant(R"("size": [100, 50, 18])", R"("size": [100, 0, 18])"), "board", "size[1]", "> 0"},
        {"RoundTooLarge", variant(R"("round": 2)", R"("round": 9.5)"), "board", "round", "half the smallest size"},
        {"ZeroHeight", variant(R"("height": 12)", R"("height": 0)"), "pin", "height", "> 0"},
        {"ConeBothZero", variant(R"("radius_bottom": 2.5, "radius_top": 2)", R"("radius_bottom": 0, "radius_top": 0)"),
         "pin", "radius_bottom", "both be 0"},
        {"NegativeThickness", variant(R"("thickness": 1)", R"("thickness": -1)"), "sh", "thickness", "> 0"},
        {"NegativeBlend", variant(R"("blend": 1.5)", R"("blend": -1)"), "cap", "blend", ">= 0"},
        {"ZeroCount", variant(R"("count": [2, 1, 1])", R"("count": [2, 0, 1])"), "holes", "count[1]", ">= 1"},
        {"FractionalCount", variant(R"("count": [2, 1, 1])", R"("count": [2.5, 1, 1])"), "holes", "count[0]", "integer"},
        {"HugeArray", variant(R"("count": [2, 1, 1])", R"("count": [1000, 1000, 1000])"), "holes", "count",
         "more than"},
        {"ZeroNormal", variant(R"("normal": [0, 3, 0])", R"("normal": [0, 0, 0])"), "m", "normal", "non-zero"},
        {"DuplicateId", variant(R"("id": "ring")", R"("id": "hole")"), "hole", "id", "duplicate"},
        {"DuplicateMeshId", variant(R"("id": "hinge")", R"("id": "board")"), "board", "id", "duplicate"},
        {"SelfIntersectingProfile", variant("[[0,0],[10,0],[10,5],[0,5]]", "[[0,0],[10,5],[10,0],[0,8]]"), "cut",
         "profile", "self-intersecting"},
        {"DegenerateProfile", variant("[[0,0],[10,0],[10,5],[0,5]]", "[[0,0],[5,0],[10,0]]"), "cut", "profile",
         "no area"},
        {"RepeatedPoint", variant("[[0,0],[10,0],[10,5],[0,5]]", "[[0,0],[10,0],[10,5],[0,5],[0,0]]"), "cut",
         "profile", "repeats"},
        {"TwoPointProfile", variant("[[0,0],[10,0],[10,5],[0,5]]", "[[0,0],[10,0]]"), "cut", "profile", "at least 3"},
        {"UnboundedRoot", variant(R"("id": "board", "type": "box",)", R"("id": "board", "type": "halfspace", "normal": [1,0,0], "offset": 0,)"),
         "root", "settings.bounds", "unbounded"},
        {"OperationWithoutChildren", variant(R"("id": "sh", "type": "shell", "thickness": 1, "children": [)",
                                             R"("id": "sh", "type": "shell", "thickness": 1, "kids": [)"),
         "sh", "children", "missing"},
        {"TwoChildrenForOffset", variant(R"({ "id": "ball", "type": "sphere", "radius": 3 })",
                                         R"({ "id": "ball", "type": "sphere", "radius": 3 }, { "id": "b2", "type": "sphere", "radius": 3 })"),
         "off", "children", "exactly 1"},
        {"BadColor", variant(R"("color": "#8b5a2b")", R"("color": "brown")"), "root", "color", "#rrggbb"},
        {"BadBounds", variant(R"("feature_size": 0.5,)", R"("feature_size": 0.5, "bounds": [[0,0,0],[1,-1,1]],)"), "",
         "settings.bounds", "below its maximum"},
        {"ZeroFeatureSize", variant(R"("feature_size": 0.5)", R"("feature_size": 0)"), "", "settings.feature_size",
         "> 0"},
    };
}

void PrintTo(const Refusal& r, std::ostream* os) { *os << r.name; }

class DocumentRefusal : public ::testing::TestWithParam<Refusal> {};

TEST_P(DocumentRefusal, NamesFileNodeAndFieldAndChangesNothing)
{
    const Refusal& r = GetParam();
    Document doc = valid();
    const Document before = doc;
    try {
        doc = Document::parse(r.text, "part.kerf");
        FAIL() << "accepted: " << r.name;
    } catch (const DocumentError& e) {
        EXPECT_EQ(e.file(), "part.kerf");
        EXPECT_EQ(e.nodeId(), r.nodeId) << e.what();
        EXPECT_EQ(e.field(), r.field) << e.what();
        EXPECT_NE(std::string(e.what()).find(r.reasonContains), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "one line";
        EXPECT_EQ(std::string(e.what()).rfind("part.kerf: ", 0), 0u) << e.what();
    }
    EXPECT_EQ(doc, before);
}

INSTANTIATE_TEST_SUITE_P(SpecList, DocumentRefusal, ::testing::ValuesIn(refusals()),
                         [](const auto& p) { return p.param.name; });

// A new part saved before its first feature (a newcomer set up a drawer's
// parameters first, and Save said "an union needs at least 1 child").
TEST(Document, AnEmptyPartWithItsParametersIsAFile)
{
    const std::string text = R"({"format":"kerf","version":1,
        "parameters":[{"name":"width","expression":"500mm"},{"name":"half","expression":"width / 2"}],
        "root":{"id":"root","type":"union","name":"Part","children":[]}})";
    const Document d = Document::parse(text, "drawer.kerf");
    EXPECT_TRUE(d.root.children.empty());
    ASSERT_EQ(d.parameters.size(), 2u);
    EXPECT_DOUBLE_EQ(d.parameters[1].value, 250.0);
    EXPECT_EQ(Document::parse(d.serialize(), "again.kerf"), d);
    EXPECT_NO_THROW(d.validate("drawer.kerf"));
    // Only the root, and only a union: below it, or another operation,
    // still needs its children.
    const auto refusal = [](const std::string& t) {
        try {
            Document::parse(t, "x.kerf");
        } catch (const DocumentError& e) {
            return std::string(e.what());
        }
        return std::string("(accepted)");
    };
    EXPECT_NE(refusal(R"({"format":"kerf","version":1,"root":{"id":"root","type":"union","children":[
        {"id":"g","type":"union","children":[]}]}})").find("a union needs at least 1 child"), std::string::npos);
    EXPECT_NE(refusal(R"({"format":"kerf","version":1,"root":{"id":"root","type":"difference","children":[]}})")
                  .find("a difference needs at least 1 child"),
              std::string::npos);
    // A byte-order mark before the JSON is no "binary data".
    EXPECT_NO_THROW(Document::parse("\xEF\xBB\xBF" + text, "bom.kerf"));
}

TEST(Document, LoadsEveryFieldOfTheSpec)
{
    const Document d = valid();
    EXPECT_EQ(d.name, "Test part");
    EXPECT_EQ(d.settings.featureSize, 0.5);
    EXPECT_EQ(d.root.type, NodeType::Difference);
    EXPECT_EQ(formatColor(*d.root.color), "#8b5a2b");
    const Node* board = d.root.find("board");
    ASSERT_NE(board, nullptr);
    EXPECT_EQ(board->as<BoxParams>().size, glm::dvec3(100, 50, 18));
    EXPECT_EQ(board->as<BoxParams>().round, 2.0);
    EXPECT_EQ(board->transform.translate, glm::dvec3(0, 0, 9));
    EXPECT_EQ(d.root.find("hole")->name, "Dowel hole");
    EXPECT_FALSE(d.root.find("cut")->visible);
    EXPECT_EQ(d.root.find("holes")->as<ArrayParams>().count, (std::array<std::int64_t, 3>{2, 1, 1}));
    // Normals are normalised; offsets become distances along the unit normal.
    EXPECT_EQ(d.root.find("m")->as<MirrorParams>().normal, glm::dvec3(0, 1, 0));
    EXPECT_EQ(d.root.find("m")->as<MirrorParams>().offset, 2.0);
    EXPECT_EQ(d.root.find("cap")->as<BooleanParams>().blend, 1.5);
    ASSERT_EQ(d.meshes.size(), 1u);
    EXPECT_EQ(d.meshes[0].path, "hinge.stl");
    EXPECT_EQ(d.meshes[0].transform.translate, glm::dvec3(1, 2, 3));
}

TEST(Document, RoundTripKeepsEverythingIncludingUnknownFields)
{
    const Document d = valid();
    const std::string text = d.serialize();
    const Document again = Document::parse(text, "again.kerf");
    EXPECT_EQ(again, d);
    EXPECT_EQ(again.serialize(), text); // stable
    for (const char* kept : {"\"x_top\"", "\"x_note\"", "\"x_t\"", "\"x_m\"", "\"vendor_setting\""})
        EXPECT_NE(text.find(kept), std::string::npos) << kept;
}

// The format keeps fields it does not know; each is named, where it is, so
// that a misspelt one is not a field the part silently goes without.
TEST(UnknownFieldsOfADocument, AreListedWhereTheyAreInDocumentOrder)
{
    using Owner = UnknownField::Owner;
    const std::vector<UnknownField> expected = {{Owner::Document, "", "x_top", ""},
                                                {Owner::Document, "", "settings.vendor_setting", ""},
                                                {Owner::Feature, "root", "x_note", ""},
                                                {Owner::Feature, "board", "transform.x_t", ""},
                                                {Owner::Mesh, "hinge", "x_m", ""}};
    EXPECT_EQ(unknownFields(valid()), expected);
}

TEST(UnknownFieldsOfADocument, AMisspeltFieldNamesTheOneItIsProbablyAMisspellingOf)
{
    const Document d = Document::parse(R"({"format":"kerf","version":1,"settings":{"featuresize":1},
        "parameters":[{"name":"w","expression":"20","units":"length","comments":"width"}],
        "root":{"id":"top","type":"union","blnd":3,"children":[
          {"id":"board","type":"box","size":[300,200,18],"Round":2},
          {"id":"foot","type":"cone","radius_bottom":10,"radius_top":5,"radius_Top":8,"height":20},
          {"id":"leg","type":"cylinder","radius":15,"height":450,"transfom":{"translate":[0,0,-225]},
           "transform":{"rotate":[0,0,0],"tranlsate":[1,2,3]},"colour":"#ff0000","x":1,"notes":"glue"}]},
        "meshes":[{"id":"scan","path":"s.stl","pth":"t.stl"}]})",
                                       "misspelt.kerf");
    using Owner = UnknownField::Owner;
    const std::vector<UnknownField> expected = {
        {Owner::Document, "", "settings.featuresize", "feature_size"},
        {Owner::Document, "", "parameters.w.units", "unit"},
        {Owner::Document, "", "parameters.w.comments", "comment"},
        {Owner::Feature, "top", "blnd", "blend"},
        {Owner::Feature, "board", "Round", "round"},
        {Owner::Feature, "foot", "radius_Top", "radius_top"},
        {Owner::Feature, "leg", "transfom", "transform"},
        {Owner::Feature, "leg", "colour", "color"},
        {Owner::Feature, "leg", "x", ""},     // a short key is within two edits of any short one
        {Owner::Feature, "leg", "notes", ""}, // a field of the user's own, no known one near
        {Owner::Feature, "leg", "transform.tranlsate", "translate"},
        {Owner::Mesh, "scan", "pth", "path"}};
    EXPECT_EQ(unknownFields(d), expected);
    EXPECT_EQ(describeUnknownField(expected[6]),
              "feature 'leg': field 'transfom' is not one Kerf knows: it is kept when saved but not used "
              "(did you mean 'transform'?)");
    EXPECT_EQ(describeUnknownField(expected[0]),
              "the document: field 'settings.featuresize' is not one Kerf knows: it is kept when saved but not used "
              "(did you mean 'feature_size'?)");
    EXPECT_EQ(describeUnknownField(expected.back()),
              "reference mesh 'scan': field 'pth' is not one Kerf knows: it is kept when saved but not used "
              "(did you mean 'path'?)");
    EXPECT_EQ(describeUnknownField(expected[9]),
              "feature 'leg': field 'notes' is not one Kerf knows: it is kept when saved but not used");
    // The status bar's sentence on opening: the first probable misspelling.
    EXPECT_EQ(summarizeUnknownFields(expected),
              "'settings.featuresize' is no field Kerf knows (did you mean 'feature_size'?), kept but "
              "not used; 11 more such fields (kerf check lists them)");
    EXPECT_EQ(summarizeUnknownFields({expected[9], expected[6]}),
              "'transfom' in feature 'leg' is no field Kerf knows (did you mean 'transform'?), kept but not used; 1 "
              "more such field (kerf check lists them)");
    EXPECT_EQ(summarizeUnknownFields({expected[9]}), "'notes' in feature 'leg' is no field Kerf knows, kept but not used");
    EXPECT_EQ(summarizeUnknownFields({}), "");
}

TEST(UnknownFieldsOfADocument, TheClosestKnownFieldIsWithinTwoEditsAndAThirdOfItsLength)
{
    EXPECT_EQ(closestKnownField("raduis", {"radius", "height"}), "radius"); // neighbours swapped: one edit
    EXPECT_EQ(closestKnownField("HEIGHT", {"radius", "height"}), "height");
    EXPECT_EQ(closestKnownField("hieghts", {"radius", "height"}), "height"); // two edits
    EXPECT_EQ(closestKnownField("hgihts", {"radius", "height"}), "");       // three
    EXPECT_EQ(closestKnownField("idx", {"id", "type"}), "");                // one edit, but a third of three letters
    EXPECT_EQ(closestKnownField("radius_tp", {"radius_top", "radius_bottom"}), "radius_top");
}

class TempDir : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir = fs::temp_directory_path() / ("kerf-doc-test-" + std::to_string(::getpid()) + "-" +
                                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }
    static std::string read(const fs::path& p)
    {
        std::ifstream in(p);
        std::stringstream s;
        s << in.rdbuf();
        return s.str();
    }
    fs::path dir;
};

TEST_F(TempDir, SaveAndLoadRoundTrip)
{
    const Document d = valid();
    d.save(dir / "part.kerf");
    EXPECT_EQ(Document::load(dir / "part.kerf"), d);
    // Only the file itself: no temporary left behind.
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST_F(TempDir, RefusedSaveLeavesTheOldFileIntact)
{
    const Document d = valid();
    d.save(dir / "part.kerf");
    const std::string before = read(dir / "part.kerf");
    Document broken = d;
    broken.root.find("hole")->as<CylinderParams>().radius = -1.0;
    EXPECT_THROW(broken.save(dir / "part.kerf"), DocumentError);
    EXPECT_EQ(read(dir / "part.kerf"), before);
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST_F(TempDir, SaveIntoAMissingFolderFailsCleanly)
{
    try {
        valid().save(dir / "no-such-folder" / "part.kerf");
        FAIL();
    } catch (const DocumentError& e) {
        EXPECT_NE(std::string(e.what()).find("part.kerf"), std::string::npos);
    }
}

TEST_F(TempDir, MissingFileIsAClearError)
{
    try {
        Document::load(dir / "absent.kerf");
        FAIL();
    } catch (const DocumentError& e) {
        EXPECT_NE(std::string(e.what()).find("absent.kerf: cannot open"), std::string::npos) << e.what();
    }
}

TEST(Document, ValidateRunsTheLoadChecksOnAnEditedDocument)
{
    Document d = valid();
    EXPECT_NO_THROW(d.validate());
    d.root.find("board")->as<BoxParams>().size.x = std::nan("");
    EXPECT_THROW(d.validate(), DocumentError);
}

TEST(Document, HiddenChildrenStillCountForChildrenChecks)
{
    // A difference with only hidden children loads (an empty part).
    const Document d = Document::parse(R"({"format":"kerf","version":1,"root":{"id":"d","type":"difference",
        "children":[{"id":"a","type":"sphere","radius":1,"visible":false}]}})",
                                       "t");
    EXPECT_EQ(d.root.children.size(), 1u);
}

TEST(Examples, EveryBundledExampleLoadsAndRoundTrips)
{
    int count = 0;
    for (const auto& entry : fs::directory_iterator(KERF_EXAMPLES_DIR)) {
        if (entry.path().extension() != ".kerf") continue;
        ++count;
        SCOPED_TRACE(entry.path().string());
        const Document d = Document::load(entry.path());
        EXPECT_EQ(Document::parse(d.serialize(), "again"), d);
        EXPECT_TRUE(unknownFields(d).empty());
    }
    EXPECT_GE(count, 5);
}

} // namespace
} // namespace kerf
