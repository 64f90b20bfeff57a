// The progress line's durations (app/cli.hpp format_duration): a person reads them at a glance,
// also when a stiff scene's dt makes the ETA 10¹⁵⁰ s. The option checks' messages and the
// "did you mean" suggestion (app/cli_checks.hpp).
#include <gtest/gtest.h>

#include <limits>

#include "app/cli.hpp"
#include "app/cli_checks.hpp"

namespace apiclab::cli {
namespace {

TEST(FormatDuration, EachScaleInItsUnits) {
  EXPECT_EQ(format_duration(0), "0.0s");
  EXPECT_EQ(format_duration(12.34), "12.3s");
  EXPECT_EQ(format_duration(59.97), "1m00s");
  EXPECT_EQ(format_duration(245), "4m05s");
  EXPECT_EQ(format_duration(3599.7), "1h00m");
  EXPECT_EQ(format_duration(12000), "3h20m");
  EXPECT_EQ(format_duration(2.5 * 86400), "2.5 days");
  EXPECT_EQ(format_duration(2.0784e155), "6.59e+147 years");
  EXPECT_EQ(format_duration(std::numeric_limits<double>::infinity()), "unbounded");
  EXPECT_EQ(format_duration(std::numeric_limits<double>::quiet_NaN()), "unbounded");
}

// Option values refused in apiclab's words before CLI11 converts them (app/cli_checks.hpp):
// CLI11's "Could not convert" and "not in range" never reach the user.
TEST(OptionChecks, ValuesRefusedInOurWords) {
  const auto check = [](const CLI::Validator& v, std::string text) { return v(text); };
  EXPECT_EQ(check(whole_number(1, 4096), "abc"),
            "expected a whole number from 1 to 4096, got 'abc'");
  EXPECT_EQ(check(whole_number(1, 4096), "12"), "");
  EXPECT_EQ(check(whole_number(1, std::numeric_limits<int>::max()), "2.5"),
            "expected a whole number of at least 1, got '2.5'");
  EXPECT_EQ(check(whole_number(1, 4096), "99999999999999999999"),
            "expected a whole number from 1 to 4096, got '99999999999999999999'");
  EXPECT_EQ(check(number_above(0), "-1"), "expected a number above 0, got '-1'");
  EXPECT_EQ(check(number_above(0), "1e8"), "");
  EXPECT_EQ(check(one_of({"scene-keys", "schemes"}), "schemse"),
            "expected one of scene-keys, schemes, got 'schemse' (did you mean 'schemes'?)");
}

// "did you mean": a typo's nearest candidate, nothing for a word that is no typo of any.
TEST(OptionChecks, NearestIsATypoOnly) {
  EXPECT_EQ(nearest("--tend", {"--t-end", "--fps", "--frames"}), "--t-end");
  EXPECT_EQ(nearest("runn", {"run", "render", "roundtrip"}), "run");
  EXPECT_EQ(nearest("--zzzzzz", {"--t-end", "--fps"}), "");
}

}  // namespace
}  // namespace apiclab::cli
