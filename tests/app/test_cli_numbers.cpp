// The apps' number checks: what they take, what they refuse, and that the refusal says what
// is wanted (CLI11's own printed DBL_MAX in 309 digits).
#include <gtest/gtest.h>
#include <pndt/app/cli_numbers.h>

using pndt::app::kNonNegative;
using pndt::app::kPositive;

namespace
{
std::string check(const CLI::Validator& v, std::string input) { return v(input); }
}  // namespace

TEST(CliNumbers, PositiveTakesNumbersAboveZeroOnly)
{
    EXPECT_EQ(check(kPositive, "0.05"), "");
    EXPECT_EQ(check(kPositive, "1e-9"), "");
    EXPECT_EQ(check(kPositive, "-1"), "-1 is not a positive number");
    EXPECT_EQ(check(kPositive, "0"), "0 is not a positive number");
    EXPECT_EQ(check(kPositive, "nan"), "nan is not a positive number");
    EXPECT_EQ(check(kPositive, "abc"), "'abc' is not a number");
}

TEST(CliNumbers, NonNegativeTakesZero)
{
    EXPECT_EQ(check(kNonNegative, "0"), "");
    EXPECT_EQ(check(kNonNegative, "3.5"), "");
    EXPECT_EQ(check(kNonNegative, "-0.1"), "-0.1 is not a number >= 0");
    EXPECT_EQ(check(kNonNegative, "nan"), "nan is not a number >= 0");
}

TEST(CliNumbers, AnOptionsMessageNamesItAndTheValue)
{
    CLI::App app;
    double voxel = 0.1;
    app.add_option("--voxel-size", voxel)->check(kPositive);
    try
    {
        app.parse("--voxel-size -1", false);
        FAIL() << "accepted";
    }
    catch (const CLI::ValidationError& e)
    {
        EXPECT_STREQ(e.what(), "--voxel-size: -1 is not a positive number");
    }
}
