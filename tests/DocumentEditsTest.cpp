// Structural edits of the feature tree (document/DocumentEdits.hpp): each
// applies whole or throws and leaves the document untouched; ids stay unique.

#include "kerf/document/AddFeature.hpp"
#include "kerf/document/DocumentEdits.hpp"
#include "kerf/document/DocumentError.hpp"
#include "kerf/document/NodeBounds.hpp"
#include "kerf/document/NodePlacement.hpp"

#include <gtest/gtest.h>

namespace kerf {
namespace {

Document sample()
{
    return Document::parse(R"({"format":"kerf","version":1,"root":{"id":"root","type":"union","children":[
        {"id":"d","type":"difference","children":[
            {"id":"board","type":"box","size":[100,50,18]},
            {"id":"hole","type":"cylinder","radius":4,"height":30}]},
        {"id":"leg-3","type":"box","size":[30,30,400],"name":"Leg"},
        {"id":"m","type":"mirror","normal":[1,0,0],"children":[{"id":"knob","type":"sphere","radius":5}]}]}})",
                           "sample.kerf");
}

std::vector<std::string> childIds(const Node& n)
{
    std::vector<std::string> v;
    for (const auto& c : n.children) v.push_back(c.id);
    return v;
}

// Runs `edit`, expects it to throw, and the document to be as before.
template <class F> void expectRefused(Document& doc, F edit)
{
    const Document before = doc;
    EXPECT_THROW(edit(doc), std::invalid_argument);
    EXPECT_EQ(doc, before);
}

TEST(DocumentEdits, LocateFindsParentAndIndex)
{
    const Document doc = sample();
    EXPECT_EQ(edit::locate(doc, "hole"), (edit::NodeLocation{"d", 1}));
    EXPECT_EQ(edit::locate(doc, "leg-3"), (edit::NodeLocation{"root", 1}));
    EXPECT_FALSE(edit::locate(doc, "root"));
    EXPECT_FALSE(edit::locate(doc, "nothing"));
}

TEST(DocumentEdits, UniqueIdCountsUp)
{
    const Document doc = sample();
    EXPECT_EQ(edit::uniqueId(doc, "box"), "box");
    EXPECT_EQ(edit::uniqueId(doc, "board"), "board-2");
}

TEST(DocumentEdits, InsertRespectsChildLimitsAndIds)
{
    Document doc = sample();
    edit::insertNode(doc, "d", 1, makeNode(NodeType::Sphere, "s"));
    EXPECT_EQ(childIds(doc.root.children[0]), (std::vector<std::string>{"board", "s", "hole"}));
    EXPECT_NO_THROW(doc.validate());
    expectRefused(doc, [](Document& d) { edit::insertNode(d, "m", 0, makeNode(NodeType::Sphere, "s2")); });
    expectRefused(doc, [](Document& d) { edit::insertNode(d, "board", 0, makeNode(NodeType::Sphere, "s3")); });
    expectRefused(doc, [](Document& d) { edit::insertNode(d, "d", 0, makeNode(NodeType::Sphere, "hole")); });
    expectRefused(doc, [](Document& d) { edit::insertNode(d, "nowhere", 0, makeNode(NodeType::Sphere, "s4")); });
}

TEST(DocumentEdits, RemoveAndRefuseTheRoot)
{
    Document doc = sample();
    const Node removed = edit::removeNode(doc, "hole");
    EXPECT_EQ(removed.id, "hole");
    EXPECT_EQ(doc.root.find("hole"), nullptr);
    expectRefused(doc, [](Document& d) { edit::removeNode(d, "root"); });
    expectRefused(doc, [](Document& d) { edit::removeNode(d, "hole"); });
}

TEST(DocumentEdits, MoveReordersAndRegroups)
{
    Document doc = sample();
    // Reorder among siblings: index counts positions before the move.
    edit::moveNode(doc, "d", "root", 2);
    EXPECT_EQ(childIds(doc.root), (std::vector<std::string>{"leg-3", "d", "m"}));
    edit::moveNode(doc, "m", "root", 0);
    EXPECT_EQ(childIds(doc.root), (std::vector<std::string>{"m", "leg-3", "d"}));
    // Regroup under another operation.
    edit::moveNode(doc, "leg-3", "d", 99);
    EXPECT_EQ(childIds(*doc.root.find("d")), (std::vector<std::string>{"board", "hole", "leg-3"}));
    EXPECT_NO_THROW(doc.validate());
    expectRefused(doc, [](Document& d) { edit::moveNode(d, "d", "d", 0); });
    expectRefused(doc, [](Document& d) { edit::moveNode(d, "root", "d", 0); });
    expectRefused(doc, [](Document& d) { edit::moveNode(d, "hole", "m", 0); }); // mirror is full
    expectRefused(doc, [](Document& d) { edit::moveNode(d, "hole", "board", 0); });
}

TEST(DocumentEdits, DuplicateGivesFreshIdsAfterTheOriginal)
{
    Document doc = sample();
    const std::string copy = edit::duplicateNode(doc, "leg-3");
    EXPECT_EQ(copy, "leg-4");
    EXPECT_EQ(childIds(doc.root), (std::vector<std::string>{"d", "leg-3", "leg-4", "m"}));
    EXPECT_EQ(doc.root.find("leg-4")->name, "Leg copy");
    const std::string dcopy = edit::duplicateNode(doc, "d");
    const Node* dc = doc.root.find(dcopy);
    ASSERT_NE(dc, nullptr);
    EXPECT_EQ(childIds(*dc), (std::vector<std::string>{"board-2", "hole-2"}));
    EXPECT_NO_THROW(doc.validate());
    expectRefused(doc, [](Document& d) { edit::duplicateNode(d, "knob"); }); // the mirror takes one child
}

TEST(DocumentEdits, WrapPutsSiblingsUnderANewOperation)
{
    Document doc = sample();
    const std::string id = edit::wrapNodes(doc, {"m", "leg-3"}, makeNode(NodeType::Difference, "cut"));
    EXPECT_EQ(id, "cut");
    EXPECT_EQ(childIds(doc.root), (std::vector<std::string>{"d", "cut"}));
    EXPECT_EQ(childIds(*doc.root.find("cut")), (std::vector<std::string>{"leg-3", "m"}));
    EXPECT_NO_THROW(doc.validate());
    expectRefused(doc, [](Document& d) { edit::wrapNodes(d, {"board", "leg-3"}, makeNode(NodeType::Union, "u")); });
    expectRefused(doc, [](Document& d) { edit::wrapNodes(d, {"board", "hole"}, makeNode(NodeType::Shell, "sh")); });
    expectRefused(doc, [](Document& d) { edit::wrapNodes(d, {"board"}, makeNode(NodeType::Box, "b")); });
    // The root alone: the new operation becomes the root.
    edit::wrapNodes(doc, {"root"}, makeNode(NodeType::Offset, "grow"));
    EXPECT_EQ(doc.root.id, "grow");
    EXPECT_EQ(doc.root.children.at(0).id, "root");
}

TEST(DocumentEdits, UpdateKeepsIdTypeAndChildren)
{
    Document doc = sample();
    Node changed = *doc.root.find("d");
    changed.children.clear();
    changed.name = "Board with hole";
    changed.as<BooleanParams>().blend = 2.0;
    edit::updateNode(doc, "d", changed);
    const Node& d = *doc.root.find("d");
    EXPECT_EQ(d.name, "Board with hole");
    EXPECT_EQ(d.as<BooleanParams>().blend, 2.0);
    EXPECT_EQ(d.children.size(), 2u);
    Node wrongType = makeNode(NodeType::Union, "d");
    expectRefused(doc, [&](Document& x) { edit::updateNode(x, "d", wrongType); });
}

// A new document is valid as it is (a file holds an empty part, with its
// parameters), and with its first feature.
TEST(DocumentEdits, AnEmptyDocumentIsValidAndSoIsItWithOneFeature)
{
    Document doc = edit::emptyDocument();
    EXPECT_NO_THROW(doc.validate());
    EXPECT_EQ(Document::parse(doc.serialize(), "new.kerf"), doc);
    edit::insertNode(doc, doc.root.id, 0, makeNode(NodeType::Box, "box"));
    EXPECT_NO_THROW(doc.validate());
}

TEST(DocumentEdits, ADifferenceWithANewBaseIsNamed)
{
    const Document before = Document::parse(R"({"format":"kerf","version":1,"root":{"id":"root","type":"union",
        "children":[{"id":"d","type":"difference","children":[{"id":"board","type":"box","size":[100,50,18]},
            {"id":"a","type":"cylinder","radius":4,"height":30},{"id":"b","type":"sphere","radius":3}]}]}})",
                                            "d.kerf");
    Document tools = before; // the tools reordered: the board still the base
    edit::moveNode(tools, "b", "d", 1);
    EXPECT_EQ(edit::differenceWithNewBase(before, tools), "");
    Document swapped = before; // a tool above the board
    edit::moveNode(swapped, "a", "d", 0);
    EXPECT_EQ(edit::differenceWithNewBase(before, swapped), "d");
    Document moved = before; // the board dragged out
    edit::moveNode(moved, "board", "root", 1);
    EXPECT_EQ(edit::differenceWithNewBase(before, moved), "d");
    EXPECT_EQ(edit::differenceWithNewBase(before, before), "");
}

TEST(DocumentEdits, ADeletionNamesEveryDifferenceThatLosesItsBase)
{
    // Two differences, one inside the other's base: deleting the inner
    // board changes both (the outer one's base loses nothing, the inner's
    // does) and deleting the outer base changes only the outer.
    const Document before = Document::parse(R"({"format":"kerf","version":1,"root":{"id":"root","type":"union",
        "children":[{"id":"outer","type":"difference","children":[
            {"id":"inner","type":"difference","children":[{"id":"board","type":"box","size":[100,50,18]},
                {"id":"a","type":"cylinder","radius":4,"height":30}]},
            {"id":"b","type":"sphere","radius":3}]}]}})",
                                            "d.kerf");
    Document noBoard = before;
    edit::removeNodes(noBoard, {"board"});
    EXPECT_EQ(edit::differencesWithNewBase(before, noBoard), std::vector<std::string>{"inner"});
    Document noInner = before;
    edit::removeNodes(noInner, {"inner", "board"}); // the board went with its parent: skipped
    EXPECT_EQ(edit::differencesWithNewBase(before, noInner), std::vector<std::string>{"outer"});
    Document emptied = before;
    edit::removeNodes(emptied, {"board", "a"});
    EXPECT_EQ(edit::differencesWithNewBase(before, emptied), std::vector<std::string>{"inner"});
    // All or nothing.
    Document refused = before;
    EXPECT_THROW(edit::removeNodes(refused, {"a", "root"}), std::invalid_argument);
    EXPECT_TRUE(refused == before);
}

// A mirror, an array or a group whose every child goes acts on nothing: a
// deletion takes it along, and the group around it where that empties too.
TEST(DocumentEdits, ADeletionTakesAlongWhatItLeavesWithoutAChild)
{
    const Document before = Document::parse(R"({"format":"kerf","version":1,"root":{"id":"root","type":"union",
        "children":[{"id":"top","type":"box","size":[100,100,18]},
            {"id":"legs","type":"union","children":[
                {"id":"m","type":"mirror","normal":[1,0,0],"offset":0,"children":[
                    {"id":"leg","type":"box","size":[10,10,100]}]},
                {"id":"rail","type":"box","size":[80,10,10]}]}]}})",
                                            "d.kerf");
    EXPECT_EQ(edit::emptiedByRemoving(before, {"leg"}), std::vector<std::string>{"m"});
    EXPECT_EQ(edit::emptiedByRemoving(before, {"leg", "rail"}), (std::vector<std::string>{"legs", "m"}));
    EXPECT_TRUE(edit::emptiedByRemoving(before, {"rail"}).empty());
    EXPECT_TRUE(edit::emptiedByRemoving(before, {"m"}).empty());
    // Never the root, even when everything goes.
    EXPECT_EQ(edit::emptiedByRemoving(before, {"top", "leg", "rail"}), (std::vector<std::string>{"legs", "m"}));
    // Taken along, the document is one a file can hold.
    Document after = before;
    std::vector<std::string> ids{"leg"};
    for (const std::string& id : edit::emptiedByRemoving(before, ids)) ids.push_back(id);
    edit::removeNodes(after, ids);
    EXPECT_EQ(after.root.find("m"), nullptr);
    EXPECT_NO_THROW(Document::parse(after.serialize(), "after.kerf"));
}

// ---------------------------------------------------------------------------
// Where an added feature goes (AddFeature.hpp)

TEST(AddFeature, APrimitiveGoesIntoTheSelectedBooleanOrAfterTheSelectedFeature)
{
    Document doc = sample();
    EXPECT_EQ(edit::addFeature(doc, NodeType::Cylinder, {"d"}), "cylinder");
    EXPECT_EQ(childIds(*doc.root.find("d")), (std::vector<std::string>{"board", "hole", "cylinder"}));
    EXPECT_EQ(edit::addFeature(doc, NodeType::Sphere, {"leg-3"}), "sphere");
    EXPECT_EQ(childIds(doc.root), (std::vector<std::string>{"d", "leg-3", "sphere", "m"}));
    EXPECT_EQ(edit::addFeature(doc, NodeType::Box, {}), "box");
    EXPECT_EQ(childIds(doc.root).back(), "box");
    doc.validate();
}

TEST(AddFeature, AnOperationOverASelectedFeatureTakesItAsItsChild)
{
    // Select a leg, press Array: an array of legs, not an array of a box beside it.
    Document doc = sample();
    EXPECT_EQ(edit::addFeature(doc, NodeType::Array, {"leg-3"}), "array");
    EXPECT_EQ(childIds(doc.root), (std::vector<std::string>{"d", "array", "m"}));
    EXPECT_EQ(childIds(*doc.root.find("array")), std::vector<std::string>{"leg-3"});
    EXPECT_EQ(edit::placeholderOf(doc, "array"), "");
    doc.validate();
    // The root selected, or nothing: the operation gets a placeholder box.
    EXPECT_EQ(edit::addFeature(doc, NodeType::Shell, {"root"}), "shell");
    EXPECT_EQ(edit::placeholderOf(doc, "shell"), "shell-box");
    EXPECT_EQ(edit::addFeature(doc, NodeType::Offset, {}), "offset");
    EXPECT_EQ(edit::placeholderOf(doc, "offset"), "offset-box");
    doc.validate();
}

TEST(AddFeature, APrimitiveReplacesAnUntouchedPlaceholder)
{
    Document doc = sample();
    edit::addFeature(doc, NodeType::Mirror, {});
    ASSERT_EQ(edit::placeholderOf(doc, "mirror"), "mirror-box");
    EXPECT_EQ(edit::addFeature(doc, NodeType::Cylinder, {"mirror"}), "cylinder");
    EXPECT_EQ(childIds(*doc.root.find("mirror")), std::vector<std::string>{"cylinder"});
    EXPECT_EQ(doc.root.find("mirror-box"), nullptr);
    doc.validate();
    // A placeholder the user has edited is theirs: the new primitive goes after the operation.
    edit::addFeature(doc, NodeType::Array, {});
    doc.root.find("array-box")->as<BoxParams>().size.x = 77.0;
    EXPECT_EQ(edit::placeholderOf(doc, "array"), "");
    EXPECT_EQ(edit::addFeature(doc, NodeType::Sphere, {"array"}), "sphere");
    EXPECT_EQ(childIds(*doc.root.find("array")), std::vector<std::string>{"array-box"});
    EXPECT_EQ(edit::locate(doc, "sphere")->parentId, "root");
    doc.validate();
}

TEST(AddFeature, ANewPrimitiveRestsOnTheGrid)
{
    // Its lowest point on z = 0, centred on the Z axis; a half-space, which
    // has no bottom, stays where makeNode puts it.
    Document doc = edit::emptyDocument();
    for (NodeType type : {NodeType::Box, NodeType::Sphere, NodeType::Cylinder, NodeType::Cone, NodeType::Torus,
                          NodeType::Extrude, NodeType::Revolve}) {
        const std::string id = edit::addFeature(doc, type, {});
        const Aabb b = nodeBounds(*doc.root.find(id));
        EXPECT_DOUBLE_EQ(b.min.z, 0.0) << id;
        EXPECT_GT(b.max.z, 0.0) << id;
        EXPECT_NEAR(b.min.x + b.max.x, 0.0, 1e-9) << id;
        EXPECT_NEAR(b.min.y + b.max.y, 0.0, 1e-9) << id;
    }
    Document cut = edit::emptyDocument();
    const std::string h = edit::addFeature(cut, NodeType::Halfspace, {});
    EXPECT_TRUE(cut.root.find(h)->transform.isIdentity());
    // An operation's placeholder box rests on the grid too, and is still
    // recognised as one; so is one that a file made before this kept at the origin.
    const std::string a = edit::addFeature(doc, NodeType::Array, {});
    EXPECT_DOUBLE_EQ(nodeBounds(doc.root.find(a)->children.front()).min.z, 0.0);
    EXPECT_EQ(edit::placeholderOf(doc, a), a + "-box");
    doc.root.find(a + "-box")->transform.translate = glm::dvec3(0.0);
    EXPECT_EQ(edit::placeholderOf(doc, a), a + "-box");
    doc.validate();
}

TEST(AddFeature, WithNothingSelectedANewPrimitiveIsMaterialBesideThePart)
{
    // The side chair's root keeps it above the floor plane (an
    // intersection): a Box added with nothing selected went to its end and
    // cut the whole chair down to the box.
    for (const char* root : {"intersection", "difference"}) {
        SCOPED_TRACE(root);
        Document doc = Document::parse(std::string(R"({"format":"kerf","version":1,"root":{"id":"root","type":")") +
                                           root + R"(","children":[
            {"id":"seat","type":"box","size":[400,400,20],"transform":{"translate":[0,0,450]}},
            {"id":"floor","type":"halfspace","normal":[0,0,-1],"offset":0}]}})",
                                       "chair.kerf");
        const std::string id = edit::addFeature(doc, NodeType::Box, {});
        ASSERT_EQ(doc.root.type, NodeType::Union);
        EXPECT_EQ(childIds(doc.root), (std::vector<std::string>{"root", id}));
        EXPECT_FALSE(edit::isSubtracted(doc, id));
        doc.validate();
        // The root selected, explicitly: into it.
        Document chosen = Document::parse(doc.serialize(), "chair.kerf");
        const std::string into = edit::addFeature(chosen, NodeType::Sphere, {"root"});
        EXPECT_EQ(edit::locate(chosen, into)->parentId, "root");
    }
}

TEST(AddFeature, AToolAddedToADifferenceCutsTheBodyWhereItIs)
{
    // A newcomer's board lay away from the origin; the hole added into its
    // difference landed on the grid at the origin and cut nothing.
    Document doc = Document::parse(R"({"format":"kerf","version":1,"root":{"id":"root","type":"union","children":[
        {"id":"d","type":"difference","children":[
            {"id":"board","type":"box","size":[300,200,18],"transform":{"translate":[200,100,9]}}]},
        {"id":"u","type":"union","children":[{"id":"rail","type":"box","size":[10,10,10]}]}]}})",
                                   "board.kerf");
    const Aabb board = nodeBounds(*doc.root.find("board"));
    for (const auto& [type, selected] : {std::pair{NodeType::Cylinder, "d"}, std::pair{NodeType::Box, "cylinder"}}) {
        const std::string id = edit::addFeature(doc, type, {selected});
        EXPECT_EQ(edit::locate(doc, id)->parentId, "d") << id;
        const Aabb tool = nodeBounds(*doc.root.find(id));
        // Centred on the board's top face, half above it: the cut shows.
        EXPECT_NEAR(0.5 * (tool.min.x + tool.max.x), 200.0, 1e-9) << id;
        EXPECT_NEAR(0.5 * (tool.min.y + tool.max.y), 100.0, 1e-9) << id;
        EXPECT_NEAR(0.5 * (tool.min.z + tool.max.z), board.max.z, 1e-9) << id;
        EXPECT_TRUE(edit::isSubtracted(doc, id)) << id;
    }
    // Into a union a primitive rests on the grid at the origin as always.
    EXPECT_EQ(edit::addFeature(doc, NodeType::Sphere, {"u"}), "sphere");
    const Aabb sphere = nodeBounds(*doc.root.find("sphere"));
    EXPECT_DOUBLE_EQ(sphere.min.z, 0.0);
    EXPECT_NEAR(sphere.max.x + sphere.min.x, 0.0, 1e-9);
    // A new difference's placeholder box is its body: a tool added to it
    // cuts its top.
    edit::addFeature(doc, NodeType::Difference, {});
    const std::string tool = edit::addFeature(doc, NodeType::Cylinder, {"difference"});
    const Aabb placeholder = nodeBounds(*doc.root.find("difference-box"));
    EXPECT_NEAR(0.5 * (nodeBounds(*doc.root.find(tool)).min.z + nodeBounds(*doc.root.find(tool)).max.z),
                placeholder.max.z, 1e-9);
    doc.validate();
}

TEST(AddFeature, APrimitiveRestingOnTheGridStaysThereAsItsHeightChanges)
{
    Document doc = edit::emptyDocument();
    const std::string id = edit::addFeature(doc, NodeType::Box, {});
    const Node before = *doc.root.find(id);
    Node thinner = before;
    thinner.as<BoxParams>().size.z = 18.0;
    edit::keepResting(before, thinner);
    EXPECT_DOUBLE_EQ(nodeBounds(thinner).min.z, 0.0);
    EXPECT_DOUBLE_EQ(nodeBounds(thinner).max.z, 18.0);
    // Moved in the same edit: the user's position, as typed.
    Node moved = before;
    moved.as<BoxParams>().size.z = 18.0;
    moved.transform.translate.x = 5.0;
    edit::keepResting(before, moved);
    EXPECT_DOUBLE_EQ(moved.transform.translate.z, before.transform.translate.z);
    // Not resting (lifted, turned, or placed by an expression): left alone.
    Node lifted = before;
    lifted.transform.translate.z += 1.0;
    Node liftedThinner = lifted;
    liftedThinner.as<BoxParams>().size.z = 18.0;
    edit::keepResting(lifted, liftedThinner);
    EXPECT_DOUBLE_EQ(liftedThinner.transform.translate.z, lifted.transform.translate.z);
    Node turned = before;
    turned.transform.rotate.x = 90.0;
    Node turnedThinner = turned;
    turnedThinner.as<BoxParams>().size.z = 18.0;
    edit::keepResting(turned, turnedThinner);
    EXPECT_DOUBLE_EQ(turnedThinner.transform.translate.z, turned.transform.translate.z);
    Node placed = before;
    placed.expressions["transform.translate[2]"] = "t / 2";
    Node placedThinner = placed;
    placedThinner.as<BoxParams>().size.z = 18.0;
    edit::keepResting(placed, placedThinner);
    EXPECT_DOUBLE_EQ(placedThinner.transform.translate.z, placed.transform.translate.z);
    // A cylinder made taller grows upward from the grid.
    Document d2 = edit::emptyDocument();
    const Node c = *d2.root.find(edit::addFeature(d2, NodeType::Cylinder, {}));
    Node taller = c;
    taller.as<CylinderParams>().height = 40.0;
    edit::keepResting(c, taller);
    EXPECT_DOUBLE_EQ(nodeBounds(taller).min.z, 0.0);
    EXPECT_DOUBLE_EQ(nodeBounds(taller).max.z, 40.0);
}

TEST(AddFeature, APrimitiveRestingOnTheGridLiesOnItWhenTurned)
{
    // A newcomer's leg, turned to lie along the bench, hung above it.
    Document doc = edit::emptyDocument();
    const std::string id = edit::addFeature(doc, NodeType::Box, {});
    Node leg = *doc.root.find(id);
    leg.as<BoxParams>().size = {40.0, 40.0, 400.0};
    leg.transform.translate.z = 200.0;
    ASSERT_DOUBLE_EQ(nodeBounds(leg).min.z, 0.0);
    Node lying = leg;
    lying.transform.rotate.x = 90.0;
    edit::keepResting(leg, lying);
    EXPECT_NEAR(nodeBounds(lying).min.z, 0.0, 1e-9);
    EXPECT_NEAR(nodeBounds(lying).max.z, 40.0, 1e-9);
    EXPECT_DOUBLE_EQ(lying.transform.translate.x, leg.transform.translate.x);
    // Turned back up: standing on the grid again.
    Node standing = lying;
    standing.transform.rotate.x = 0.0;
    edit::keepResting(lying, standing);
    EXPECT_NEAR(nodeBounds(standing).min.z, 0.0, 1e-9);
    EXPECT_NEAR(nodeBounds(standing).max.z, 400.0, 1e-9);
    // A cylinder laid on its side.
    Document d2 = edit::emptyDocument();
    const Node c = *d2.root.find(edit::addFeature(d2, NodeType::Cylinder, {}));
    Node side = c;
    side.transform.rotate.y = 90.0;
    edit::keepResting(c, side);
    EXPECT_NEAR(nodeBounds(side).min.z, 0.0, 1e-9);
    // Not resting (lifted), or turned and moved in one edit: left alone.
    Node lifted = leg;
    lifted.transform.translate.z += 10.0;
    Node liftedTurned = lifted;
    liftedTurned.transform.rotate.x = 90.0;
    edit::keepResting(lifted, liftedTurned);
    EXPECT_DOUBLE_EQ(liftedTurned.transform.translate.z, lifted.transform.translate.z);
    Node turnedAndMoved = leg;
    turnedAndMoved.transform.rotate.x = 90.0;
    turnedAndMoved.transform.translate.x = 5.0;
    edit::keepResting(leg, turnedAndMoved);
    EXPECT_DOUBLE_EQ(turnedAndMoved.transform.translate.z, leg.transform.translate.z);
}

TEST(AddFeature, APanelWhoseThicknessIsAParameterStaysOnTheGridWhenItChanges)
{
    // A newcomer's cabinet side: Size Z "=thickness" put the panel's centre
    // at 9 mm as a number; thickness 25 left it at 9 (from -3.5 to 21.5),
    // and the dado, rebate and holes measured from "thickness - ..." came
    // out shallower, without a word.
    Document doc = edit::emptyDocument();
    Parameter thickness;
    thickness.name = "thickness";
    thickness.expression = "18";
    doc.parameters.push_back(thickness);
    const std::string id = edit::addFeature(doc, NodeType::Box, {});
    doc = doc.resolved();
    const Node before = *doc.root.find(id);
    Node driven = before;
    driven.expressions["size[2]"] = "thickness";
    driven.as<BoxParams>().size.z = 18.0;
    edit::keepResting(before, driven);
    EXPECT_EQ(driven.expressions.at("transform.translate[2]"), "thickness/2");
    EXPECT_EQ(edit::restingExpression(driven), "thickness/2");
    edit::updateNode(doc, id, driven);
    doc.root.find(id)->expressions = driven.expressions;
    doc.parameters[0].expression = "25";
    const Document thicker = doc.resolved();
    EXPECT_DOUBLE_EQ(nodeBounds(*thicker.root.find(id)).min.z, 0.0);
    EXPECT_DOUBLE_EQ(nodeBounds(*thicker.root.find(id)).max.z, 25.0);
    // A sum in parentheses; a sphere's radius as it is; a height typed as a
    // number again takes the expression this rule wrote away.
    Node sum = *thicker.root.find(id);
    sum.expressions["size[2]"] = "thickness + 2";
    EXPECT_EQ(edit::restingExpression(sum), "(thickness + 2)/2");
    Node plain = *thicker.root.find(id);
    Node typed = plain;
    typed.expressions.erase("size[2]");
    typed.as<BoxParams>().size.z = 30.0;
    edit::keepResting(plain, typed);
    EXPECT_FALSE(typed.expressions.count("transform.translate[2]"));
    EXPECT_DOUBLE_EQ(nodeBounds(typed).min.z, 0.0);
    // An expression the user wrote is theirs: left as it is.
    Node own = plain;
    own.expressions["transform.translate[2]"] = "thickness";
    Node ownThinner = own;
    ownThinner.as<BoxParams>().size.z = 10.0;
    edit::keepResting(own, ownThinner);
    EXPECT_EQ(ownThinner.expressions.at("transform.translate[2]"), "thickness");
    EXPECT_DOUBLE_EQ(ownThinner.transform.translate.z, own.transform.translate.z);
}

} // namespace
} // namespace kerf

// ---- Placement for direct manipulation (NodePlacement.hpp, MoveSnap.hpp) ----

#include "kerf/document/MoveSnap.hpp"
#include "kerf/document/NodePlacement.hpp"
#include "kerf/document/NodeBounds.hpp"

namespace kerf {
namespace {

// A panel with a hole, inside a group turned 90 degrees about Z and shifted.
Document turnedPanel()
{
    return Document::parse(R"({"format":"kerf","version":1,"root":{"id":"root","type":"union","children":[
        {"id":"group","type":"difference","transform":{"translate":[100,0,0],"rotate":[0,0,90]},"children":[
          {"id":"panel","type":"box","size":[40,20,10]},
          {"id":"holes","type":"array","count":[3,1,1],"step":[10,0,0],"children":[
            {"id":"hole","type":"cylinder","radius":2,"height":20,"transform":{"translate":[-10,0,0]}}]},
          {"id":"plug","type":"difference","children":[{"id":"p1","type":"sphere","radius":1},
                                                      {"id":"p2","type":"sphere","radius":0.5}]}]}]}})",
                           "t.kerf");
}

TEST(NodePlacement, TheParentFrameComposesTheAncestors)
{
    const Document d = turnedPanel();
    const Affine f = edit::parentFrame(d, "hole");
    // The hole's translate (-10, 0, 0) turned 90 degrees about Z is (0, -10, 0), shifted by 100 in X.
    const glm::dvec3 c = f.apply(glm::dvec3(-10, 0, 0));
    EXPECT_NEAR(c.x, 100.0, 1e-12);
    EXPECT_NEAR(c.y, -10.0, 1e-12);
    EXPECT_THROW(edit::parentFrame(d, "nope"), std::invalid_argument);
    const Aabb b = edit::firstInstanceBounds(d, "hole");
    EXPECT_NEAR(b.center().x, 100.0, 1e-12);
    EXPECT_NEAR(b.center().y, -10.0, 1e-12);
}

TEST(NodePlacement, AMoveInTheWorldMovesTheFeatureByExactlyThat)
{
    Document d = turnedPanel();
    const Aabb before = edit::firstInstanceBounds(d, "hole");
    edit::moveNodeInWorld(d, "hole", glm::dvec3(0, 32, 0));
    const Aabb after = edit::firstInstanceBounds(d, "hole");
    EXPECT_NEAR(after.center().x - before.center().x, 0.0, 1e-12);
    EXPECT_NEAR(after.center().y - before.center().y, 32.0, 1e-12);
    // In its own parent's frame (turned 90 degrees) that is +32 along X.
    EXPECT_NEAR(d.root.find("hole")->transform.translate.x, 22.0, 1e-12);
    EXPECT_NEAR(d.root.find("hole")->transform.translate.y, 0.0, 1e-12);
}

TEST(NodePlacement, ToolsOfADifferenceAreSubtractedAndAToolsToolIsMaterialAgain)
{
    const Document d = turnedPanel();
    EXPECT_FALSE(edit::isSubtracted(d, "panel"));
    EXPECT_TRUE(edit::isSubtracted(d, "hole"));
    EXPECT_TRUE(edit::isSubtracted(d, "holes"));
    EXPECT_TRUE(edit::isSubtracted(d, "p1"));
    EXPECT_FALSE(edit::isSubtracted(d, "p2"));
    EXPECT_FALSE(edit::isSubtracted(d, "root"));
    Document hiddenBase = d;
    hiddenBase.root.find("panel")->visible = false; // the array is the base now
    EXPECT_FALSE(edit::isSubtracted(hiddenBase, "hole"));
}

TEST(NodePlacement, TheNodeAloneKeepsItsPlacementAndItsCopies)
{
    const Document d = turnedPanel();
    const Document alone = edit::documentOfNodeAlone(d, "hole");
    EXPECT_NO_THROW(alone.validate());
    EXPECT_EQ(alone.root.find("panel"), nullptr);
    EXPECT_EQ(alone.root.find("plug"), nullptr);
    ASSERT_NE(alone.root.find("holes"), nullptr);
    EXPECT_EQ(alone.root.find("holes")->type, NodeType::Array); // three holes still
    EXPECT_EQ(alone.root.find("group")->type, NodeType::Union);
    // The same place in the world as in the part.
    const auto inPart = worldBoundsOfNodes(d), inAlone = worldBoundsOfNodes(alone);
    EXPECT_EQ(inPart.at("hole").min, inAlone.at("hole").min);
    EXPECT_EQ(inPart.at("hole").max, inAlone.at("hole").max);
}

TEST(MoveSnap, GridStepsAreRoundAndAFewPixelsWide)
{
    EXPECT_EQ(gridStepFor(0.1), 1.0);   // 10 px per mm
    EXPECT_EQ(gridStepFor(0.2), 5.0);   // 1 mm would be 5 px
    EXPECT_EQ(gridStepFor(0.01), 0.1);
    EXPECT_EQ(gridStepFor(3.0), 50.0);
    EXPECT_EQ(gridStepFor(0.0), 1.0);
    // In inches: halvings of the inch, then inches and feet.
    EXPECT_DOUBLE_EQ(gridStepFor(0.1, LengthUnit::Inches), 25.4 / 32); // 1/64" would be 4 px
    EXPECT_DOUBLE_EQ(gridStepFor(0.5, LengthUnit::Inches), 25.4 / 8);
    EXPECT_DOUBLE_EQ(gridStepFor(5.0, LengthUnit::Inches), 25.4 * 6);
    EXPECT_DOUBLE_EQ(gridStepFor(100.0, LengthUnit::Inches), 304.8 * 2);
}

TEST(MoveSnap, AlignsWithANeighbourWithinReachElseRoundsToTheGrid)
{
    const Aabb hole{glm::dvec3(-2.5, -2.5, 157.5), glm::dvec3(2.5, 2.5, 162.5)};
    const std::vector<SnapTarget> holes{{"hole 2", Aabb{glm::dvec3(-2.5, -2.5, 189.5), glm::dvec3(2.5, 2.5, 194.5)}}};
    // Dragged 31.7 mm: the centre lands on the next hole's centre.
    AxisSnap s = snapAxisMove(hole, 2, 31.7, holes, 0.8, 1.0);
    EXPECT_EQ(s.delta, 32.0);
    EXPECT_EQ(s.reason, "centre on the centre of hole 2");
    // Out of reach of any alignment: the nearest millimetre.
    s = snapAxisMove(hole, 2, 12.4, holes, 0.8, 1.0);
    EXPECT_EQ(s.delta, 12.0);
    EXPECT_EQ(s.reason, "on the 1 mm grid");
    s = snapAxisMove(hole, 2, -0.2, {}, 0.8, 1.0);
    EXPECT_EQ(s.delta, 0.0);
    EXPECT_FALSE(std::signbit(s.delta));
    // No grid and nothing near: the move as dragged.
    EXPECT_EQ(snapAxisMove(hole, 0, 3.3, holes, 0.1, 0.0).delta, 3.3);
    // Lengths shown in inches: a grid of sixteenths, named so.
    s = snapAxisMove(hole, 2, 12.4, holes, 0.8, 25.4 / 16, LengthUnit::Inches);
    EXPECT_DOUBLE_EQ(s.delta, 8 * 25.4 / 16);
    EXPECT_EQ(s.reason, "on the 1/16\" grid");
}

} // namespace
} // namespace kerf

namespace kerf {
namespace {

// kerf export --feature takes an id, or a name only one feature has.
TEST(DocumentEdits, AFeatureIsFoundByItsIdOrAUniqueName)
{
    const Document d = Document::parse(R"({"format":"kerf","version":1,"root":{"id":"root","type":"union",
        "children":[{"id":"top","type":"box","name":"Top","size":[100,100,18]},
            {"id":"a","type":"box","name":"Leg","size":[10,10,100]},
            {"id":"b","type":"box","name":"Leg","size":[10,10,100]}]}})",
                                       "d.kerf");
    EXPECT_EQ(edit::featureNamed(d, "top"), "top");
    EXPECT_EQ(edit::featureNamed(d, "Top"), "top");
    EXPECT_EQ(edit::featureNamed(d, "a"), "a");
    try {
        edit::featureNamed(d, "Leg");
        ADD_FAILURE() << "a shared name was taken";
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()), "2 features are named 'Leg': give one of their ids (a, b)");
    }
    EXPECT_THROW(edit::featureNamed(d, "Shelf"), std::invalid_argument);
}

// An export of one feature says what the file holds: the copies a mirror
// above it makes, and a cutter's shape as a solid (a newcomer's "Pin hole
// alone" was forty solid pins, without a word).
TEST(DocumentEdits, AFeatureAloneIsDescribedWithItsCopiesAndWhatItIs)
{
    const Document d = Document::parse(R"({"format":"kerf","version":1,"root":{"id":"root","type":"union",
        "children":[{"id":"top","type":"box","name":"Top","size":[100,100,18]},
            {"id":"sides","type":"mirror","normal":[1,0,0],"offset":0,"children":[
                {"id":"side","type":"difference","name":"Side","children":[
                    {"id":"board","type":"box","size":[18,100,300],"transform":{"translate":[60,0,150]}},
                    {"id":"holes","type":"array","count":[1,1,5],"step":[0,0,32],"children":[
                        {"id":"pin","type":"cylinder","name":"Pin hole","radius":2.5,"height":12,
                         "transform":{"translate":[52,0,60],"rotate":[0,90,0]}}]}]}]}]}})",
                                       "d.kerf");
    EXPECT_EQ(edit::describeFeatureAlone(d, "top"), "Top alone");
    EXPECT_EQ(edit::describeFeatureAlone(d, "side"), "Side alone, with every copy of the mirror above it");
    EXPECT_EQ(edit::describeFeatureAlone(d, "pin"),
              "Pin hole alone, with every copy of the mirror and array above it, as a solid: it is a cutter (the part "
              "has its shape cut away)");
    // The board a difference cuts, alone, has none of its cuts: said, with
    // what to select instead (a newcomer's CNC file was a plain box).
    EXPECT_EQ(edit::describeFeatureAlone(d, "board"),
              "board alone, with every copy of the mirror above it, without the cuts of Side (holes): select Side for "
              "the board as cut");
}

TEST(DocumentEdits, IdsInSubtreeNameTheNodeAndEverythingBelow)
{
    const Document d = turnedPanel();
    EXPECT_EQ(edit::idsInSubtree(*d.root.find("holes")), (std::unordered_set<std::string>{"holes", "hole"}));
    EXPECT_EQ(edit::idsInSubtree(*d.root.find("p2")), (std::unordered_set<std::string>{"p2"}));
    EXPECT_EQ(edit::idsInSubtree(d.root).size(), d.root.count());
}

TEST(DocumentEdits, PrimitiveIdsInSubtreeAreWhatASelectionHighlights)
{
    const Document d = sample();
    EXPECT_EQ(edit::primitiveIdsInSubtree(*d.root.find("d")), (std::unordered_set<std::string>{"board", "hole"}));
    EXPECT_EQ(edit::primitiveIdsInSubtree(*d.root.find("leg-3")), (std::unordered_set<std::string>{"leg-3"}));
    EXPECT_EQ(edit::primitiveIdsInSubtree(d.root),
              (std::unordered_set<std::string>{"board", "hole", "leg-3", "knob"}));
}

TEST(DocumentEdits, ASelectionComesBackInTreeOrderWithoutIdsThatAreGone)
{
    const Document d = sample();
    EXPECT_EQ(edit::inTreeOrder(d, {"knob", "hole", "gone", "d", "leg-3"}),
              (std::vector<std::string>{"d", "hole", "leg-3", "knob"}));
    EXPECT_TRUE(edit::inTreeOrder(d, {}).empty());
}

TEST(DocumentEdits, AReferenceMeshGetsAUniqueIdAndAPathThatTravelsWithTheDocument)
{
    Document d = sample();
    EXPECT_EQ(edit::addMeshReference(d, "/work/parts/leg.stl", std::filesystem::path("/work/doc")), "leg");
    EXPECT_EQ(edit::addMeshReference(d, "/work/parts/leg.stl", std::filesystem::path("/work/doc")), "leg-2");
    EXPECT_EQ(edit::addMeshReference(d, "/elsewhere/leg.obj", std::nullopt), "leg-3");
    EXPECT_EQ(edit::addMeshReference(d, "/work/doc/.stl", std::filesystem::path("/work/doc")), ".stl");
    ASSERT_EQ(d.meshes.size(), 4u);
    EXPECT_EQ(d.meshes[0].path, "../parts/leg.stl"); // relative to the document's folder
    EXPECT_EQ(d.meshes[2].path, "/elsewhere/leg.obj"); // an untitled document keeps it absolute
    EXPECT_EQ(d.meshes[3].path, ".stl");
}

} // namespace
} // namespace kerf
