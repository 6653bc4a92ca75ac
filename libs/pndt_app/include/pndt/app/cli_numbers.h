#pragma once
// Number checks for the apps' command lines. CLI11's PositiveNumber / NonNegativeNumber say
// "Value -1 not in range 0.000000 to <DBL_MAX in 309 digits>"; these say what is wanted.
#include <CLI/CLI.hpp>

#include <string>

namespace pndt::app
{
namespace detail
{
inline CLI::Validator numberAbove(double bound, bool inclusive, const std::string& wanted)
{
    return CLI::Validator(
        [bound, inclusive, wanted](std::string& input) -> std::string {
            double v = 0;
            if (!CLI::detail::lexical_cast(input, v)) return "'" + input + "' is not a number";
            if (!(inclusive ? v >= bound : v > bound)) return input + " is not " + wanted;  // NaN: neither
            return {};
        },
        inclusive ? "NONNEGATIVE" : "POSITIVE");
}
}  // namespace detail

/// A number > 0 (not NaN).
inline const CLI::Validator kPositive = detail::numberAbove(0.0, false, "a positive number");
/// A number >= 0 (not NaN).
inline const CLI::Validator kNonNegative = detail::numberAbove(0.0, true, "a number >= 0");
}  // namespace pndt::app
