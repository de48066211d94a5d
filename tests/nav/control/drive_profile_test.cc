// The scripted drive profile: each step's wheel speeds from its time on, the
// last of several steps due in one tick winning, nothing new in between.
#include "nav/control/drive_profile.h"

#include <gtest/gtest.h>

namespace pavilion::nav {
namespace {

ControlTick At(double t) {
  ControlTick tick;
  tick.now_s = t;
  return tick;
}

TEST(DriveProfileControllerTest, AppliesEachStepOnceFromItsTime) {
  DriveProfileController drive({{0.0, 1.0, 1.0}, {0.5, 2.0, -2.0}, {0.5, 3.0, 3.0}, {2.0, 0, 0}});
  const auto first = drive.OnTick(At(0.0));
  ASSERT_TRUE(first);
  EXPECT_DOUBLE_EQ(first->left_radps, 1.0);
  EXPECT_FALSE(drive.OnTick(At(0.25)));  // held
  const auto second = drive.OnTick(At(0.5));
  ASSERT_TRUE(second);  // two steps due: the later one holds
  EXPECT_DOUBLE_EQ(second->left_radps, 3.0);
  EXPECT_FALSE(drive.OnTick(At(1.0)));
  EXPECT_TRUE(drive.OnTick(At(2.0 - 1e-12)));  // tick times are rounded
  EXPECT_FALSE(drive.OnTick(At(3.0)));
  EXPECT_FALSE(drive.mission());
}

}  // namespace
}  // namespace pavilion::nav
