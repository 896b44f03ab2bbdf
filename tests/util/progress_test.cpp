// Progress into a log (stderr not a terminal): nothing for short work, a plain line per
// interval for long work with its share, rate and ETA, and one line when it ends; nothing with
// -q. gtest's CaptureStderr sends stderr to a file, so these run as a log would.
#include <gtest/gtest.h>

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

TEST(ProgressRate, UnitsPerSecondOrSecondsPerUnit) {
  EXPECT_EQ(format_rate(30, 2.0, "frame"), "15.0 frame/s");
  EXPECT_EQ(format_rate(3, 30.0, "frame"), "10.00 s/frame");
  EXPECT_EQ(format_rate(0, 5.0, "step"), "0.0 step/s");
}

}  // namespace
}  // namespace pb4u
