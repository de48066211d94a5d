// A robot pushed with its motors disengaged (thesis §6.5: staff pushed the
// Robox with the motors switched off) rolls on its wheels, and its encoders
// see the rolling; with the motors engaged the same push does not move it.
// Both wheel models.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "scenarios/config/robot_loader.h"
#include "scenarios/config/robot_setup.h"
#include "sim/world/world.h"
#include "tests/support/floor_world.h"
#include "tests/support/world_robot.h"

namespace pavilion::sim {
namespace {

struct Pushed {
  double moved_m = 0.0;    // along the push
  double encoder_m = 0.0;  // mean of both wheels' rolled distance
};

// A Robox at rest pulled by `force_n` (world frame, at its centre of mass)
// for `pull_s`, then left for 3 s.
Pushed Pull(WheelModel wheels, bool engaged, const Eigen::Vector2d& force_n, double pull_s) {
  WorldDescription d = pavilion::testing::FloorWorld(20, false);
  const RobotConfig config = scenarios::WithWorldMaterials(
      scenarios::LoadRobotFile(PAVILION_SOURCE_DIR "/robots/robox/robot.yaml"), &d);
  World world(d, WorldOptions{});
  pavilion::testing::WorldRobot spec{"r", config.description, config.systematic, core::Pose2{}};
  spec.wheel_model = wheels;
  const int robot = pavilion::testing::AddRobot(world, spec);
  for (int i = 0; i < 100; ++i) world.Step();
  world.SetMotorsEngaged(robot, engaged);
  EXPECT_EQ(world.motors_engaged(robot), engaged);
  const RobotState start = world.robot_state(robot);
  for (int i = 0; i < static_cast<int>(pull_s / world.step_s()); ++i) {
    world.ApplyRobotImpulse(robot, force_n * world.step_s());
    world.Step();
  }
  for (int i = 0; i < static_cast<int>(3.0 / world.step_s()); ++i) world.Step();
  const RobotState end = world.robot_state(robot);
  const RobotDescription& m = world.robot_model(robot);
  Pushed p;
  p.moved_m = (end.pose.translation() - start.pose.translation()).dot(force_n.normalized());
  p.encoder_m = 0.5 * ((end.left_wheel_rad - start.left_wheel_rad) * m.left_wheel.radius_m +
                       (end.right_wheel_rad - start.right_wheel_rad) * m.right_wheel.radius_m);
  std::printf("%s motors %s, pull (%.0f, %.0f) N for %.1f s: moved %.3f m, encoders %.3f m\n",
              WheelModelName(wheels), engaged ? "engaged" : "disengaged", force_n.x(), force_n.y(),
              pull_s, p.moved_m, p.encoder_m);
  return p;
}

// Pulled forwards, a robot with its motors off rolls and its encoders count
// the roll (within 10 %); with its motors on the braked wheels hold it. (No
// rolling resistance or gearbox drag is modelled: 200 N s roll it 6-7 m.)
TEST(MotorsDisengaged, PulledForwardsItRollsAndTheEncodersSeeIt) {
  for (WheelModel wheels : {WheelModel::kArticulated, WheelModel::kRaycast}) {
    const Pushed off = Pull(wheels, false, {100.0, 0.0}, 2.0);
    EXPECT_GT(off.moved_m, 0.5) << WheelModelName(wheels);
    EXPECT_NEAR(off.encoder_m, off.moved_m, 0.1 * off.moved_m) << WheelModelName(wheels);
    const Pushed on = Pull(wheels, true, {100.0, 0.0}, 2.0);
    // The articulated reference's hinge motors give a few millimetres.
    EXPECT_LT(std::abs(on.moved_m), 0.01) << WheelModelName(wheels);
    EXPECT_LT(std::abs(on.encoder_m), 0.01) << WheelModelName(wheels);
  }
}

// Pulled sideways hard enough to slide, the free wheels do not turn: the
// encoders see (almost) none of the motion.
TEST(MotorsDisengaged, PulledSidewaysTheEncodersSeeLittle) {
  for (WheelModel wheels : {WheelModel::kArticulated, WheelModel::kRaycast}) {
    const Pushed off = Pull(wheels, false, {0.0, 1200.0}, 0.5);
    EXPECT_GT(off.moved_m, 0.05) << WheelModelName(wheels);
    EXPECT_LT(std::abs(off.encoder_m), 0.1 * off.moved_m) << WheelModelName(wheels);
  }
}

}  // namespace
}  // namespace pavilion::sim
