#include "sim/runtime/schedule.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace pavilion::sim {
namespace {

// Task rates that divide the physics rate give whole periods; others are refused.
TEST(ScheduleTest, PeriodMustBeWholeNumberOfTicks) {
  EXPECT_EQ(PeriodTicks(200.0, 10.0, "laser"), 20);
  EXPECT_EQ(PeriodTicks(200.0, 200.0, "encoders"), 1);
  EXPECT_EQ(PeriodTicks(1000.0, 3.0 + 1.0 / 3.0, "x"), 300);
  EXPECT_THROW(PeriodTicks(200.0, 30.0, "camera"), std::invalid_argument);
  EXPECT_THROW(PeriodTicks(200.0, 400.0, "too fast"), std::invalid_argument);
  EXPECT_THROW(PeriodTicks(200.0, 0.0, "zero"), std::invalid_argument);
  try {
    PeriodTicks(200.0, 30.0, "camera.rate_hz");
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("camera.rate_hz"), std::string::npos);
  }
}

// Tasks fire on their period from their phase, reported in the order added.
TEST(ScheduleTest, DueTasksFollowPeriodAndPhase) {
  PeriodicSchedule s(200.0);
  const int laser = s.Add("laser", 10.0);
  const int odometry = s.Add("odometry", 200.0);
  const int late = s.Add("late", 50.0, 3);
  EXPECT_EQ(s.Due(0), (std::vector<int>{laser, odometry}));
  EXPECT_EQ(s.Due(3), (std::vector<int>{odometry, late}));
  EXPECT_EQ(s.Due(20), (std::vector<int>{laser, odometry}));
  int count = 0;
  for (std::int64_t t = 0; t < 2000; ++t) count += s.IsDue(laser, t);
  EXPECT_EQ(count, 100);  // 10 s at 10 Hz
  EXPECT_FALSE(s.IsDue(late, 2));
}

}  // namespace
}  // namespace pavilion::sim
