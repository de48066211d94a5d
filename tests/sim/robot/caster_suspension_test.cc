// Robox's rear caster on a spring (robot.yaml `suspension`, thesis A.5: "a
// castor wheel on each side – one on a spring suspension") in the fast wheel
// model; the articulated reference keeps its casters rigid. Two drive wheels and two rigid casters
// are four rigid supports: the share of the weight the drive wheels carry is not determined by
// statics, and in a turn reversal the solver could leave them unloaded for tens of milliseconds
// while the body coasted on (a skid the encoders never see: docs/benchmarks.md, session 14). With
// one caster sprung the drive wheels and the rigid caster determine the support: the drive wheels
// keep their share of the weight whatever pushed the robot before.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include "scenarios/config/robot_setup.h"
#include "sim/world/world.h"
#include "tests/support/floor_world.h"
#include "tests/support/shipped_robots.h"
#include "tests/support/world_robot.h"

namespace pavilion::sim {
namespace {

struct Loads {
  double rest_n = 0.0;   // the smaller drive wheel's floor load, at rest
  double after_n = 0.0;  // the same after two pushes, at rest again
  double weight_n = 0.0;
};

// Robox at rest, pushed sideways and then forwards (300 N for 0.3 s at the
// centre of mass, its motors holding), each push followed by 2 s at rest.
Loads PushTwice(WheelModel wheels, bool sprung) {
  WorldDescription d = pavilion::testing::FloorWorld(30, false);
  RobotConfig config = scenarios::WithWorldMaterials(pavilion::testing::ShippedRobot("robox"), &d);
  if (!sprung) {
    for (CasterSpec& c : config.description.casters) c.stiffness_npm = c.damping_nspm = 0.0;
  }
  World world(d, WorldOptions{});
  pavilion::testing::WorldRobot spec{"r", config.description, config.systematic, core::Pose2{}};
  spec.wheel_model = wheels;
  const int robot = pavilion::testing::AddRobot(world, spec);
  auto advance = [&](double seconds, const Eigen::Vector2d& force_n) {
    for (int i = 0; i < static_cast<int>(std::lround(seconds / world.step_s())); ++i) {
      if (force_n.norm() > 0.0) world.ApplyRobotImpulse(robot, force_n * world.step_s());
      world.Step();
    }
  };
  auto least = [&] {
    const std::array<double, 2> loads = world.DriveWheelLoads(robot);
    return std::min(loads[0], loads[1]);
  };
  advance(1.0, {0, 0});
  Loads out;
  out.rest_n = least();
  advance(0.3, {0.0, 300.0});
  advance(2.0, {0, 0});
  advance(0.3, {300.0, 0.0});
  advance(2.0, {0, 0});
  out.after_n = least();
  out.weight_n = world.robot_model(robot).total_mass_kg() * 9.81;
  std::printf(
      "%s, rear caster %s: drive wheel load %.0f N at rest, %.0f N after the pushes (weight %.0f "
      "N)\n",
      WheelModelName(wheels), sprung ? "sprung" : "rigid", out.rest_n, out.after_n, out.weight_n);
  return out;
}

// The shipped Robox has its rear caster sprung.
TEST(CasterSuspensionFile, RoboxHasItsRearCasterOnASpring) {
  const RobotConfig& robox = pavilion::testing::ShippedRobot("robox");
  ASSERT_EQ(robox.description.casters.size(), 2u);
  EXPECT_EQ(robox.description.casters[0].stiffness_npm, 0.0);
  EXPECT_EQ(robox.description.casters[1].link, "caster_rear");
  EXPECT_GT(robox.description.casters[1].stiffness_npm, 0.0);
}

// Sprung, the fast model's drive wheels carry most of the weight (Robox's
// centre of mass is over its axle) and still do after being pushed about:
// within 5 %.
TEST(CasterSuspension, TheDriveWheelsKeepTheirLoadAfterPushes) {
  const Loads sprung = PushTwice(WheelModel::kRaycast, true);
  EXPECT_GT(sprung.rest_n, 0.45 * sprung.weight_n);
  EXPECT_NEAR(sprung.after_n / sprung.rest_n, 1.0, 0.05);
}

// Why: with both casters rigid, the fast model's split of the weight drifts
// with what happened before (warm-started impulses of an undetermined
// support): after the two pushes its drive wheels carry a quarter of what
// they did, and a visitor's bump then spins the robot on them.
TEST(CasterSuspension, WithBothCastersRigidTheFastModelsDriveWheelsLoseTheirLoad) {
  const Loads rigid = PushTwice(WheelModel::kRaycast, false);
  EXPECT_LT(rigid.after_n, 0.5 * rigid.rest_n);
}

// Driving, braking into a turn and setting off again, the sprung Robox's
// drive wheels are never without load for longer than a pitching bounce:
// held rigid at a zero gap, the sprung caster once took half the weight with
// the front caster and left the drive wheels touching with none for seconds,
// and the robot glided on its casters while its wheels braked and turned
// (expo_day seed 3, 172 s). A guard: this sequence does not bring the old
// rigid-at-zero-gap row into that state (25 ms either way); the scenario's
// count is in docs/benchmarks.md, session 22.
TEST(CasterSuspension, TheDriveWheelsAreNeverLongWithoutLoad) {
  WorldDescription d = pavilion::testing::FloorWorld(30, false);
  RobotConfig config = scenarios::WithWorldMaterials(pavilion::testing::ShippedRobot("robox"), &d);
  World world(d, WorldOptions{});
  pavilion::testing::WorldRobot spec{"r", config.description, config.systematic, core::Pose2{}};
  spec.wheel_model = WheelModel::kRaycast;
  const int robot = pavilion::testing::AddRobot(world, spec);
  const double weight_n = world.robot_model(robot).total_mass_kg() * 9.81;
  double unloaded_s = 0.0, longest_s = 0.0;
  const auto drive = [&](double left_radps, double right_radps, double seconds) {
    world.SetWheelSpeeds(robot, left_radps, right_radps);
    for (int i = 0; i < static_cast<int>(std::lround(seconds / world.step_s())); ++i) {
      world.Step();
      const std::array<double, 2> loads = world.DriveWheelLoads(robot);
      unloaded_s =
          std::min(loads[0], loads[1]) < 0.1 * weight_n ? unloaded_s + world.step_s() : 0.0;
      longest_s = std::max(longest_s, unloaded_s);
    }
  };
  drive(0.0, 0.0, 1.0);
  for (int k = 0; k < 4; ++k) {
    drive(6.0, 6.0, 2.0);   // 0.54 m/s
    drive(-3.0, 3.0, 1.0);  // braking into a turn on the spot
    drive(6.5, 5.5, 1.0);
    drive(0.0, 0.0, 1.0);
  }
  std::printf("longest time with a drive wheel under 10 %% of the weight: %.3f s\n", longest_s);
  EXPECT_LT(longest_s, 0.05);
}

// The articulated reference ignores the suspension: the same loads with and
// without it.
TEST(CasterSuspension, TheArticulatedReferenceKeepsItsCastersRigid) {
  const Loads sprung = PushTwice(WheelModel::kArticulated, true);
  const Loads rigid = PushTwice(WheelModel::kArticulated, false);
  EXPECT_EQ(sprung.rest_n, rigid.rest_n);
  EXPECT_EQ(sprung.after_n, rigid.after_n);
}

}  // namespace
}  // namespace pavilion::sim
