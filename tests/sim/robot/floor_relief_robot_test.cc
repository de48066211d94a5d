// Robots on an uneven floor (sim::FloorRelief, issue 20), in both wheel
// models: a robot stands tilted with the floor and does not creep down a
// 0.5° slope with its motors holding; driving over a drawn relief, the fast
// model (its tyres compliant there: four rigid points cannot all touch an
// uneven floor, and a lifted drive wheel has no traction) ends where the
// articulated reference does (the flat floor's conformance bounds), the
// encoders count the same wheel turns as on a flat floor, and the robot ends
// within 2 cm of the flat floor's pose after 10 m (1-7 mm measured; 4-11 mm between the models).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <string>

#include "scenarios/config/robot_loader.h"
#include "scenarios/config/robot_setup.h"
#include "sim/world/floor_relief.h"
#include "sim/world/world.h"
#include "tests/support/floor_world.h"
#include "tests/support/shipped_robots.h"
#include "tests/support/world_robot.h"

namespace pavilion::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
// The flat floor's conformance bounds (wheel_model_conformance_test.cc).
constexpr double kPoseToleranceM = 0.02;
constexpr double kHeadingToleranceRad = kDeg;

// A shipped robot file (robots/<name>/robot.yaml).
const RobotConfig& Config(const std::string& name) { return pavilion::testing::ShippedRobot(name); }

// A slope of `slope_rad` rising along +x at the origin: one 40 m wave, so
// that the floor under a robot is a plane within 0.01 mm.
FloorRelief Incline(double slope_rad) {
  constexpr double kWavelengthM = 40.0;
  const double kappa = 2.0 * kPi / kWavelengthM;
  // h = a cos(kappa x - pi/2) = a sin(kappa x): slope a kappa at x = 0.
  return FloorRelief({{{kappa, 0.0}, std::tan(slope_rad) / kappa, -0.5 * kPi}});
}

// The default relief the realistic profile draws, on the test floor.
FloorRelief Drawn(std::uint64_t seed) {
  core::RandomStream random(seed, core::RandomStream::StreamId("realism/floor"));
  return DrawFloorRelief({}, {-30, -30}, {30, 30}, &random);
}

struct Scene {
  std::unique_ptr<World> world;
  int robot = -1;

  Scene(const std::string& model, WheelModel wheels, const FloorRelief& relief,
        const core::Pose2& pose) {
    WorldDescription d = pavilion::testing::FloorWorld(30, false);
    d.floor.relief = relief;
    const RobotConfig scoped = scenarios::WithWorldMaterials(Config(model), &d);
    pavilion::testing::WorldRobot spec{"r", scoped.description, scoped.systematic, pose};
    spec.wheel_model = wheels;
    world = std::make_unique<World>(d, WorldOptions{});
    robot = pavilion::testing::AddRobot(*world, spec);
  }
  RobotState state() const { return world->robot_state(robot); }
  void Advance(double seconds) {
    const int steps = static_cast<int>(std::lround(seconds / world->step_s()));
    for (int i = 0; i < steps; ++i) world->Step();
  }
};

class ReliefWheels : public ::testing::TestWithParam<WheelModel> {};

// Placed on a 0.5° incline, facing across it and up it: the chassis tilts
// with the floor (its rear caster's spring giving a little), and with the motors holding zero speed
// the robot neither rolls nor slides down.
TEST_P(ReliefWheels, StandsTiltedWithTheFloorAndHoldsOnTheSlope) {
  const double slope = 0.5 * kDeg;
  for (const double heading : {0.0, 0.5 * kPi}) {
    Scene scene("robox", GetParam(), Incline(slope), {0.0, 0.0, heading});
    scene.Advance(2.0);
    const RobotState s = scene.state();
    // Within 0.05° with rigid casters; Robox's sprung rear caster (fast
    // model) lets the body pitch on its spring by up to 0.3° more (0.26°
    // measured facing up the slope).
    const double give = GetParam() == WheelModel::kRaycast ? 0.3 * kDeg : 0.05 * kDeg;
    EXPECT_NEAR(s.tilt_rad, slope, give) << heading;
    EXPECT_NEAR(s.pose.x_m, 0.0, 1e-3) << heading;
    EXPECT_NEAR(s.pose.y_m, 0.0, 1e-3) << heading;
    EXPECT_NEAR(s.pose.theta_rad, heading, 1e-3) << heading;
  }
}

// Drives `left_mps`, `right_mps` for `seconds` from the origin and stops.
RobotState Drive(const std::string& model, WheelModel wheels, const FloorRelief& relief,
                 double left_mps, double right_mps, double seconds) {
  Scene scene(model, wheels, relief, {0.0, 0.0, 0.3});
  scene.Advance(0.5);
  const RobotDescription& m = scene.world->robot_model(scene.robot);
  scene.world->SetWheelSpeeds(scene.robot, left_mps / m.left_wheel.radius_m,
                              right_mps / m.right_wheel.radius_m);
  scene.Advance(seconds);
  scene.world->SetWheelSpeeds(scene.robot, 0.0, 0.0);
  scene.Advance(2.0);
  return scene.state();
}

// 10 m straight and on a 2 m arc over a drawn relief: the fast model ends at
// the reference's pose; the wheels turned as far as on the flat floor (the
// encoders see no relief); the true pose ends within a few centimetres of the
// flat floor's (what the slopes and the load changes do, no more).
TEST(ReliefWheelModels, DriveOverTheReliefAsTheReferenceAndTheFlatFloor) {
  for (const std::string model : {"robox", "pygmalion"}) {
    const double b = Config(model).description.wheelbase_m();
    const double v = 0.4, turn = 0.4 / 2.0;
    struct Profile {
      const char* name;
      double left, right;
    };
    for (const Profile& p :
         {Profile{"straight", v, v}, Profile{"arc", v - 0.5 * turn * b, v + 0.5 * turn * b}}) {
      const double seconds = 10.0 / v;
      const FloorRelief relief = Drawn(3);
      const RobotState reference =
          Drive(model, WheelModel::kArticulated, relief, p.left, p.right, seconds);
      const RobotState fast = Drive(model, WheelModel::kRaycast, relief, p.left, p.right, seconds);
      const RobotState flat = Drive(model, WheelModel::kRaycast, {}, p.left, p.right, seconds);
      const double apart = (fast.pose.translation() - reference.pose.translation()).norm();
      const double turned =
          std::abs(std::remainder(fast.pose.theta_rad - reference.pose.theta_rad, 2 * kPi));
      const double off_flat = (fast.pose.translation() - flat.pose.translation()).norm();
      std::printf(
          "%s %s: fast-reference %.1f mm %.3f deg, relief-flat %.1f mm, wheels %.5f vs %.5f rad\n",
          model.c_str(), p.name, 1e3 * apart, turned / kDeg, 1e3 * off_flat, fast.left_wheel_rad,
          flat.left_wheel_rad);
      EXPECT_LT(apart, kPoseToleranceM) << model << " " << p.name;
      EXPECT_LT(turned, kHeadingToleranceRad) << model << " " << p.name;
      EXPECT_NEAR(fast.left_wheel_rad, flat.left_wheel_rad, 1e-6) << model << " " << p.name;
      EXPECT_NEAR(fast.right_wheel_rad, flat.right_wheel_rad, 1e-6) << model << " " << p.name;
      EXPECT_LT(off_flat, 0.02) << model << " " << p.name;
      EXPECT_LT(fast.tilt_rad, 0.6 * kDeg);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(BothModels, ReliefWheels,
                         ::testing::Values(WheelModel::kArticulated, WheelModel::kRaycast),
                         [](const auto& info) {
                           return info.param == WheelModel::kRaycast ? "Raycast" : "Articulated";
                         });

}  // namespace
}  // namespace pavilion::sim
