// The route controller: waits for its start time, steers only on its control
// ticks, and reports its mission done once the follower reaches the goal.
#include "nav/control/route_controller.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace pavilion::nav {
namespace {

ControlTick Tick(std::int64_t tick, double now_s, const core::Pose2& belief) {
  ControlTick t;
  t.tick = tick;
  t.now_s = now_s;
  t.belief = belief;
  return t;
}

RouteControllerOptions Options() {
  RouteControllerOptions o;
  o.start_s = 1.0;
  o.period_ticks = 4;
  o.step_s = 0.01;
  o.odometry.left_wheel_radius_m = 0.1;
  o.odometry.right_wheel_radius_m = 0.1;
  o.odometry.wheelbase_m = 0.5;
  return o;
}

TEST(RouteControllerTest, WaitsForStartAndRunsAtItsRate) {
  RouteController route({{0, 0}, {2, 0}}, Options());
  EXPECT_FALSE(route.OnTick(Tick(0, 0.0, {0, 0, 0})));     // before the start
  EXPECT_FALSE(route.OnTick(Tick(101, 1.01, {0, 0, 0})));  // not a control tick
  const auto command = route.OnTick(Tick(100, 1.0, {0, 0, 0}));
  ASSERT_TRUE(command);
  EXPECT_GT(command->left_radps, 0.0);  // accelerating straight ahead
  EXPECT_NEAR(command->left_radps, command->right_radps, 1e-9);
  ASSERT_TRUE(route.mission());
  EXPECT_FALSE(route.mission()->done);
  EXPECT_NEAR(route.mission()->path_length_m, 2.0, 1e-12);
}

// Standing on the goal, the first control tick ends the mission.
TEST(RouteControllerTest, ReportsTheMissionDoneAtTheGoal) {
  RouteController route({{0, 0}, {1, 0}}, Options());
  const auto command = route.OnTick(Tick(200, 2.0, {1.0, 0.0, 0.0}));
  ASSERT_TRUE(command);
  ASSERT_TRUE(route.mission()->done);
  EXPECT_DOUBLE_EQ(route.mission()->done_at_s, 2.0);
  EXPECT_FALSE(route.OnTick(Tick(204, 2.04, {1.0, 0.0, 0.0})));  // done: nothing more
}

TEST(RouteControllerTest, RejectsAZeroControlPeriod) {
  RouteControllerOptions o = Options();
  o.period_ticks = 0;
  EXPECT_THROW(RouteController({{0, 0}, {1, 0}}, o), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::nav
