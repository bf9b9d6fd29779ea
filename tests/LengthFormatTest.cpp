// Lengths shown in millimetres or in inches and fractions of an inch
// (document/LengthFormat.hpp): the text for editing reads back, through the
// document's expression language, as the same length; readouts say when
// they round.

#include "kerf/document/Expression.hpp"
#include "kerf/document/LengthFormat.hpp"

#include <gtest/gtest.h>

#include <random>
#include <string>

namespace kerf {
namespace {

double readBack(const std::string& text)
{
    expr::Resolver none;
    none.name = [](std::string_view) -> expr::Quantity { throw expr::ExpressionError("no names"); };
    none.field = [](std::string_view, std::string_view) -> expr::Quantity { throw expr::ExpressionError("no fields"); };
    const expr::Quantity q = expr::evaluate(text, none);
    return q.value;
}

TEST(LengthFormat, MillimetresForEditingAreTheNumberWithoutTrailingZeros)
{
    EXPECT_EQ(lengthForEditing(18.0, LengthUnit::Millimetres), "18");
    EXPECT_EQ(lengthForEditing(2.5, LengthUnit::Millimetres), "2.5");
    EXPECT_EQ(lengthForEditing(0.001, LengthUnit::Millimetres), "0.001");
    EXPECT_EQ(lengthForEditing(-0.0000001, LengthUnit::Millimetres), "0");
}

TEST(LengthFormat, WholeSixtyFourthsAreWrittenAsFractionsInLowestTerms)
{
    EXPECT_EQ(lengthForEditing(19.05, LengthUnit::Inches), "3/4\"");
    EXPECT_EQ(lengthForEditing(298.45, LengthUnit::Inches), "11 3/4\"");
    EXPECT_EQ(lengthForEditing(25.4 * 12, LengthUnit::Inches), "12\"");
    EXPECT_EQ(lengthForEditing(0.0, LengthUnit::Inches), "0\"");
    EXPECT_EQ(lengthForEditing(-38.1, LengthUnit::Inches), "-1 1/2\"");
    EXPECT_EQ(lengthForEditing(25.4 / 64, LengthUnit::Inches), "1/64\"");
    EXPECT_EQ(lengthForEditing(25.4 * 33 / 32, LengthUnit::Inches), "1 1/32\"");
}

TEST(LengthFormat, OtherLengthsAreDecimalInchesForEditing)
{
    EXPECT_EQ(lengthForEditing(18.0, LengthUnit::Inches), "0.708661\"");
    EXPECT_EQ(lengthForEditing(1.0, LengthUnit::Inches), "0.03937\"");
}

// Every whole 64th from -40 to 40 inches, and random lengths: the editing
// text reads back as the length (exactly for fractions, to the decimals
// shown otherwise).
TEST(LengthFormat, EditingTextReadsBackAsTheSameLength)
{
    for (int n = -40 * 64; n <= 40 * 64; ++n) {
        const double mm = n * 25.4 / 64;
        const std::string text = lengthForEditing(mm, LengthUnit::Inches);
        ASSERT_NEAR(readBack(text), mm, 1e-9) << text;
        ASSERT_EQ(text.find('.'), std::string::npos) << text; // a fraction, not decimals
    }
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> any(-3000.0, 3000.0);
    for (int i = 0; i < 20000; ++i) {
        const double mm = any(rng);
        ASSERT_NEAR(readBack(lengthForEditing(mm, LengthUnit::Inches)), mm, 25.4 * 5e-7 + 1e-12);
        ASSERT_NEAR(readBack(lengthForEditing(mm, LengthUnit::Millimetres)), mm, 5e-7 + 1e-12);
    }
}

TEST(LengthFormat, ReadoutsSayWhenTheyRoundToTheNearestSixtyFourth)
{
    EXPECT_EQ(lengthReadout(32.0, LengthUnit::Millimetres), "32.00 mm");
    EXPECT_EQ(lengthReadout(-0.001, LengthUnit::Millimetres), "0.00 mm");
    EXPECT_EQ(lengthReadout(1.23456, LengthUnit::Millimetres, 3), "1.235 mm");
    EXPECT_EQ(lengthReadout(31.75, LengthUnit::Inches), "1 1/4\"");
    EXPECT_EQ(lengthReadout(18.0, LengthUnit::Inches), "≈ 45/64\"");
    EXPECT_EQ(lengthReadout(32.0, LengthUnit::Inches), "≈ 1 17/64\"");
    EXPECT_EQ(lengthReadout(0.1, LengthUnit::Inches), "≈ 0\"");
    EXPECT_EQ(lengthReadout(1e300, LengthUnit::Inches).back(), '"'); // no overflow of the count of 64ths
}

TEST(LengthFormat, BareNumbersTakeTheShownUnitAndSettingsKeysRoundTrip)
{
    EXPECT_DOUBLE_EQ(bareLengthToMm(12.0, LengthUnit::Millimetres), 12.0);
    EXPECT_DOUBLE_EQ(bareLengthToMm(12.0, LengthUnit::Inches), 304.8);
    for (LengthUnit u : {LengthUnit::Millimetres, LengthUnit::Inches}) EXPECT_EQ(lengthUnitFromKey(lengthUnitKey(u)), u);
    EXPECT_FALSE(lengthUnitFromKey("furlong"));
}

} // namespace
} // namespace kerf
