// The progress line's durations (app/cli.hpp format_duration): a person reads them at a glance,
// also when a stiff scene's dt makes the ETA 10¹⁵⁰ s.
#include <gtest/gtest.h>

#include <limits>

#include "app/cli.hpp"

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

}  // namespace
}  // namespace apiclab::cli
