// The node type table (NodeTypes.hpp) drives the reader, the writer,
// makeNode, the property editor and the random shapes: every type is in it
// once, its defaults are valid documents, random nodes of every type go
// through save and load unchanged, and the refusals of its rules name the
// node and the field.

#include "kerf/document/Document.hpp"
#include "kerf/document/DocumentError.hpp"
#include "kerf/document/NodeBounds.hpp"
#include "kerf/document/NodeTypes.hpp"
#include "support/RandomShapes.hpp"

#include <gtest/gtest.h>

#include <set>

namespace kerf {
namespace {

// A valid document around one node (a halfspace needs bounds).
Document around(Node n)
{
    Document d;
    d.root = std::move(n);
    d.settings.bounds = Bounds3{glm::dvec3(-100.0), glm::dvec3(100.0)};
    return d;
}

TEST(NodeTypes, EveryTypeIsInTheTableOnceWithItsOwnName)
{
    std::set<std::string_view> names;
    std::set<NodeType> types;
    for (const NodeTypeSpec& spec : nodeTypeSpecs()) {
        EXPECT_TRUE(names.insert(spec.name).second) << spec.name;
        EXPECT_TRUE(types.insert(spec.type).second) << spec.name;
        EXPECT_EQ(nodeTypeFromName(spec.name), spec.type);
        EXPECT_EQ(nodeTypeName(spec.type), spec.name);
        EXPECT_EQ(&nodeTypeSpec(spec.type), &spec);
        std::set<std::string_view> keys;
        for (const FieldSpec& f : spec.fields) {
            EXPECT_TRUE(keys.insert(f.key).second) << spec.name << "." << f.key;
            EXPECT_FALSE(f.label.empty()) << spec.name << "." << f.key;
            EXPECT_FALSE(f.help.empty()) << spec.name << "." << f.key;
            // The accessor that matches the field's shape, and only that one.
            const bool number = f.number != nullptr, vector = f.vector != nullptr, counts = f.counts != nullptr,
                       points = f.points != nullptr;
            EXPECT_EQ(number + vector + counts + points, 1) << spec.name << "." << f.key;
            EXPECT_EQ(number, f.shape == FieldShape::Number) << spec.name << "." << f.key;
            EXPECT_EQ(points, f.shape == FieldShape::Points) << spec.name << "." << f.key;
        }
        EXPECT_EQ(spec.localBounds != nullptr, spec.category == NodeCategory::Primitive) << spec.name;
    }
    // NodeType's last enumerator: every value below it is in the table.
    for (int t = 0; t <= int(NodeType::Mirror); ++t) EXPECT_TRUE(types.count(NodeType(t))) << "type " << t;
}

TEST(NodeTypes, DefaultsOfEveryTypeAreAValidDocument)
{
    for (const NodeTypeSpec& spec : nodeTypeSpecs()) {
        Node n = makeNode(spec.type, "n");
        if (spec.category != NodeCategory::Primitive) n.children.push_back(makeNode(NodeType::Sphere, "child"));
        EXPECT_NO_THROW(around(n).validate("defaults")) << spec.name;
        if (spec.category == NodeCategory::Primitive && spec.type != NodeType::Halfspace) {
            EXPECT_FALSE(nodeBounds(n).isEmpty()) << spec.name;
        }
    }
}

TEST(NodeTypes, RandomNodesOfEveryTypeSurviveSaveAndLoad)
{
    test::RandomShapes r(41);
    for (const NodeType type : test::RandomShapes::primitiveTypes())
        for (int i = 0; i < 50; ++i) {
            const Document d = around(r.primitive(type));
            const Document back = Document::parse(d.serialize(), "round trip");
            EXPECT_EQ(back.root, d.root) << nodeTypeName(type) << "\n" << d.serialize();
            EXPECT_EQ(back.serialize(), d.serialize());
        }
    for (const NodeType type : test::RandomShapes::operationTypes())
        for (int i = 0; i < 50; ++i) {
            const Document d = around(r.operation(type));
            const Document back = Document::parse(d.serialize(), "round trip");
            EXPECT_EQ(back.serialize(), d.serialize()) << nodeTypeName(type);
        }
}

// A document with one revolve node and the given profile text.
std::string revolveDocument(const std::string& profile)
{
    return R"({"format": "kerf", "version": 1, "root": {"id": "leg", "type": "revolve", "profile": )" + profile + "}}";
}

TEST(NodeTypes, ARevolveLoadsSavesAndHasTheBoundsOfItsProfile)
{
    const Document d = Document::parse(revolveDocument("[[0, 0], [20, 0], [25, 40], [10, 60], [0, 60]]"), "leg.kerf");
    ASSERT_EQ(d.root.type, NodeType::Revolve);
    EXPECT_EQ(d.root.as<RevolveParams>().profile.size(), 5u);
    const Aabb b = nodeBounds(d.root);
    EXPECT_EQ(b.min, glm::dvec3(-25, -25, 0));
    EXPECT_EQ(b.max, glm::dvec3(25, 25, 60));
    EXPECT_EQ(Document::parse(d.serialize(), "again").root, d.root);
    EXPECT_NE(d.serialize().find("\"type\": \"revolve\""), std::string::npos);
}

TEST(NodeTypes, BadRevolveProfilesAreRefusedNamingTheNodeAndField)
{
    struct Case {
        std::string profile, field, reason;
    };
    const Case cases[] = {
        {"[[0, 0], [-1, 0], [10, 5]]", "profile[1][0]", "r must be >= 0"},
        {"[[0, 0], [10, 0]]", "profile", "at least 3"},
        {"[[0, 0], [10, 5], [10, 0], [0, 8]]", "profile", "self-intersecting"},
        {"[[0, 0], [5, 0], [10, 0]]", "profile", "no area"},
        {"[[0, 0], [10, 0], [10, true]]", "profile[2][1]", "must be a number"},
        {"[[0, 0], [10, 0], [10, \"5 +\"]]", "profile[2][1]", "the expression \"5 +\" ends where"},
        {"[[0, 0], [10, 0, 1], [10, 5]]", "profile[1]", "[r, z] point"},
        {"5", "profile", "[r, z] points"},
        {"[[0, 0], [1e300, 0], [0, 5]]", "profile[1][0]", "limited to"},
    };
    for (const Case& c : cases) {
        try {
            (void)Document::parse(revolveDocument(c.profile), "leg.kerf");
            ADD_FAILURE() << "accepted " << c.profile;
        } catch (const DocumentError& e) {
            EXPECT_EQ(e.nodeId(), "leg") << e.what();
            EXPECT_EQ(e.field(), c.field) << e.what();
            EXPECT_NE(std::string(e.what()).find(c.reason), std::string::npos) << e.what();
        }
    }
    try {
        (void)Document::parse(R"({"format": "kerf", "version": 1, "root": {"id": "leg", "type": "revolve"}})", "leg.kerf");
        ADD_FAILURE() << "accepted a revolve without a profile";
    } catch (const DocumentError& e) {
        EXPECT_EQ(e.field(), "profile");
        EXPECT_NE(std::string(e.what()).find("missing"), std::string::npos) << e.what();
    }
}

} // namespace
} // namespace kerf
