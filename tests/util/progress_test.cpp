// Progress into a log (stderr not a terminal): nothing for short work, a plain line per
// interval for long work with its share, rate and ETA, and one line when it ends; nothing with
// -q. gtest's CaptureStderr sends stderr to a file, so these run as a log would.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "pb4u/util/progress.h"

namespace pb4u {
namespace {

class ProgressLog : public ::testing::Test {
 protected:
  void TearDown() override {
    Progress::set_log_interval(60);
    Progress::set_quiet(false);
  }
};

TEST_F(ProgressLog, ShortWorkWritesNothing) {
  testing::internal::CaptureStderr();
  {
    Progress bar("work", 4, "frame");
    for (int i = 0; i < 4; ++i) bar.step(1, "a");
  }
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

TEST_F(ProgressLog, LongWorkWritesALinePerIntervalAndOneAtTheEnd) {
  Progress::set_log_interval(0);  // every step is "a minute later"
  testing::internal::CaptureStderr();
  {
    Progress bar("evaluate Lv.5", 4, "frame");
    bar.step(1, "Reference, tshirt on walk");
    bar.step(2);
    bar.step(1);
  }
  const std::string log = testing::internal::GetCapturedStderr();
  EXPECT_NE(log.find("evaluate Lv.5: 1/4 frame (25%), "), std::string::npos) << log;
  EXPECT_NE(log.find(", ETA "), std::string::npos) << log;
  EXPECT_NE(log.find(", Reference, tshirt on walk\n"), std::string::npos) << log;
  EXPECT_NE(log.find("evaluate Lv.5: 3/4 frame (75%), "), std::string::npos) << log;
  EXPECT_NE(log.find("evaluate Lv.5: 4/4 frame in "), std::string::npos) << log;
  EXPECT_EQ(log.find('\r'), std::string::npos) << "no terminal redraws in a log";
  EXPECT_EQ(log.find("0/4"), std::string::npos) << "no line before the first unit is done";
}

TEST_F(ProgressLog, QuietWritesNothing) {
  Progress::set_log_interval(0);
  Progress::set_quiet(true);
  testing::internal::CaptureStderr();
  {
    Progress bar("work", 2, "frame");
    bar.step(1);
    bar.step(1);
  }
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

TEST(ProgressEta, PricesWhatIsLeftAtTheRecentCostOfAUnit) {
  double cost = unit_seconds_after(-1, 3.0, 30);  // a network's frames: 0.1 s each
  EXPECT_DOUBLE_EQ(cost, 0.1);
  for (int i = 0; i < 100; ++i) cost = unit_seconds_after(cost, 0.1, 1);
  EXPECT_NEAR(cost, 0.1, 1e-12);
  // Then a solver's frames of 40 s: after one the estimate is 1 - exp(-40/60) of the way there
  // (an ETA from the mean so far would still price them near 0.5 s), after five nearly there.
  cost = unit_seconds_after(cost, 40.0, 1);
  EXPECT_NEAR(cost, 0.1 + (1 - std::exp(-40.0 / 60)) * 39.9, 1e-9);
  for (int i = 0; i < 4; ++i) cost = unit_seconds_after(cost, 40.0, 1);
  EXPECT_NEAR(cost, 40.0, 40.0 * std::exp(-200.0 / 60) + 1e-9);
  EXPECT_DOUBLE_EQ(unit_seconds_after(2.0, 5.0, 0), 2.0);  // no unit done: unchanged
}

TEST(ProgressRate, UnitsPerSecondOrSecondsPerUnit) {
  EXPECT_EQ(format_rate(30, 2.0, "frame"), "15.0 frame/s");
  EXPECT_EQ(format_rate(3, 30.0, "frame"), "10.00 s/frame");
  EXPECT_EQ(format_rate(0, 5.0, "step"), "0.0 step/s");
}

}  // namespace
}  // namespace pb4u
