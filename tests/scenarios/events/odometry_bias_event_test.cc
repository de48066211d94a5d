// The odometry_bias event (issue 17's timeline): a drive wheel's true radius
// changes (a flat tyre, a carpet) while the robot's calibrated odometry stays
// as it was. A robot driving straight then curves as the geometry of its
// wheels says, in both wheel models, and its dead reckoning does not see the
// curve. Bad input is one line at its key.
#include "scenarios/events/odometry_bias_event.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/localization/encoder_odometry.h"
#include "scenarios/config/robot_loader.h"
#include "scenarios/config/robot_setup.h"
#include "scenarios/config/scenario.h"
#include "scenarios/run/scenario_runner.h"
#include "sim/robot/sim_robot.h"
#include "tests/support/floor_world.h"
#include "tests/support/load_errors.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

using pavilion::testing::TestDir;
using pavilion::testing::WriteFile;

constexpr double kSpeedMps = 0.5;
constexpr double kRunUpS = 1.0;
constexpr double kDriveS = 8.0;

// What a straight drive did, from the start of the command to its end.
struct Drive {
  double heading_rad = 0.0;      // true heading change
  double distance_m = 0.0;       // true path length
  double biased_m = 0.0;         // true path length while the bias ran
  double odo_heading_rad = 0.0;  // dead-reckoned heading change (calibrated model)
  double odo_distance_m = 0.0;   // dead-reckoned path length
  int records = 0;               // the event's records (Apply, and Continue's end)
};

// A Robox (built as nominal: robot.yaml has no systematic errors) on a bare
// floor commanded equal wheel rates for kSpeedMps: after a run-up of
// kRunUpS (its wheels at speed), `bias` is applied (none: no event) and the
// drive is measured over the next kDriveS.
Drive DriveStraight(sim::WheelModel wheels, const std::optional<OdometryBiasOptions>& bias) {
  sim::WorldDescription d = pavilion::testing::FloorWorld(30, false);
  sim::RobotConfig config =
      WithWorldMaterials(LoadRobotFile(PAVILION_SOURCE_DIR "/robots/robox/robot.yaml"), &d);
  config.lasers.clear();  // not needed here
  sim::World world(d, sim::WorldOptions{});
  sim::SimRobot robot(&world, config, sim::RobotPlacement{"robox_1", {-10, 0, 0}, wheels}, 1);
  for (int i = 0; i < 50; ++i) world.Step();  // settle on the floor

  const std::map<std::string, int> robot_index{{"robox_1", robot.index()}};
  const std::map<std::string, int> body_index;
  sim::TickSnapshot snapshot = world.Snapshot();
  EventStreams streams(1);
  std::vector<double> step_m(1, 0.0);
  std::vector<KidnapNote> kidnaps;
  EventContext context{&world,  &robot_index, &body_index, &snapshot, &streams,
                       &step_m, &kidnaps,     {},          {}};
  context.sim_robot = [&robot](int) { return &robot; };
  std::optional<OdometryBiasEvent> event;
  Drive drive;

  const double omega = kSpeedMps / config.description.left_wheel.radius_m;
  robot.SetWheelSpeeds(omega, omega);
  core::DeadReckoning odometry(config.odometry, core::Pose2{});
  core::Pose2 last_odo;
  sim::RobotState before = world.robot_state(robot.index());
  // One tick: the world steps, the encoders are read into the dead reckoning;
  // with `measure`, the drive's figures grow.
  const auto tick = [&](bool measure) {
    const bool biased = bias && robot.wheel_radius_scale(0) * robot.wheel_radius_scale(1) != 1.0;
    world.Step();
    snapshot = world.Snapshot();
    const sim::RobotState after = snapshot.robots[robot.index()];
    const double step = (after.pose.translation() - before.pose.translation()).norm();
    for (const core::EncoderReading& e : robot.AfterStep(before, after).encoders) {
      odometry.Update(e);
      if (measure) {
        drive.odo_distance_m += (odometry.pose().translation() - last_odo.translation()).norm();
      }
      last_odo = odometry.pose();
    }
    if (measure) drive.distance_m += step;
    if (measure && biased) drive.biased_m += step;
    if (event && event->ongoing()) drive.records += event->Continue(context).is_null() ? 0 : 1;
    before = after;
  };
  for (int i = 0; i < static_cast<int>(std::lround(kRunUpS / world.step_s())); ++i) tick(false);

  const double start_heading = before.pose.theta_rad;
  const double start_odo_heading = odometry.pose().theta_rad;
  if (bias) {
    event.emplace("robox_1", *bias);
    drive.records += event->Apply(context).is_null() ? 0 : 1;
  }
  for (int i = 0; i < static_cast<int>(std::lround(kDriveS / world.step_s())); ++i) tick(true);
  drive.heading_rad = core::NormalizeAngle(before.pose.theta_rad - start_heading);
  drive.odo_heading_rad = core::NormalizeAngle(odometry.pose().theta_rad - start_odo_heading);
  std::printf("%s: distance %.4f m (biased %.4f), heading %.5f rad; odometry %.4f m, %.5f rad\n",
              sim::WheelModelName(wheels), drive.distance_m, drive.biased_m, drive.heading_rad,
              drive.odo_distance_m, drive.odo_heading_rad);
  return drive;
}

// The heading change of a differential drive whose left wheel has s times the
// right's radius, both turning at the same rate, over a path of d: the wheels
// roll s r w and r w, so the centre moves at (1 + s) r w / 2 and turns at
// (1 - s) r w / b; per metre, 2 (1 - s) / ((1 + s) b).
double ExpectedHeadingRad(double distance_m, double s, double wheelbase_m) {
  return distance_m * 2.0 * (1.0 - s) / ((1.0 + s) * wheelbase_m);
}

OdometryBiasOptions LeftTyre(double scale, std::optional<double> duration_s = std::nullopt) {
  OdometryBiasOptions o;
  o.wheel = OdometryBiasOptions::Wheel::kLeft;
  o.radius_scale = scale;
  o.duration_s = duration_s;
  return o;
}

// Relative tolerance on the curve and on what the odometry sees of it: at
// 0.04 rad/m the wheels do not slip sideways, so the turn is the wheels' speed
// difference over the contacts' wheelbase, the URDF's b (the calibrated
// b = 0.504 m of robot.yaml holds the slip of turns in place, not of gentle
// curves); the run-up keeps the motors' acceleration ramp, which acts on the
// built wheel (sim_robot.cc), out of it. What remains is the contacts'
// compliance, well under 1 %.
constexpr double kCurveTolerance = 0.01;

// With the left tyre 2 % smaller, a straight drive curves to the left (the
// smaller left wheel rolls less: an anticlockwise turn) by the geometry's amount, in both wheel
// models; without it the robot goes straight. The dead reckoning (calibrated model, encoders
// counting wheel turns) sees a straight drive, and a path 2 / (1 + s) times the true one.
TEST(OdometryBiasEventTest, SmallerLeftTyreCurvesAndOdometryDoesNotSeeIt) {
  const double wheelbase_m = 0.50;  // robots/robox: the URDF's (no systematic errors)
  for (sim::WheelModel wheels : {sim::WheelModel::kArticulated, sim::WheelModel::kRaycast}) {
    SCOPED_TRACE(sim::WheelModelName(wheels));
    const Drive straight = DriveStraight(wheels, std::nullopt);
    EXPECT_LT(std::abs(straight.heading_rad), 1e-3);
    const Drive biased = DriveStraight(wheels, LeftTyre(0.98));
    EXPECT_EQ(biased.records, 1);
    EXPECT_NEAR(biased.biased_m, biased.distance_m, 1e-9);
    const double expected = ExpectedHeadingRad(biased.distance_m, 0.98, wheelbase_m);
    EXPECT_NEAR(biased.heading_rad - straight.heading_rad, expected,
                kCurveTolerance * std::abs(expected));
    // The odometry: as straight as without the bias.
    EXPECT_NEAR(biased.odo_heading_rad, straight.odo_heading_rad,
                kCurveTolerance * std::abs(expected));
    // The encoders count the true wheels' turns: the small one turned as
    // often as the other, so the odometry takes each for a nominal one.
    const double odo_scale = biased.odo_distance_m / biased.distance_m;
    const double straight_scale = straight.odo_distance_m / straight.distance_m;
    EXPECT_NEAR(odo_scale / straight_scale, 2.0 / (1.0 + 0.98), 1e-3);
  }
}

// A bias for 4 s of the 8 s drive: the curve is that of the biased path only,
// and a second record marks its end.
TEST(OdometryBiasEventTest, WithADurationTheRadiusReturns) {
  for (sim::WheelModel wheels : {sim::WheelModel::kArticulated, sim::WheelModel::kRaycast}) {
    SCOPED_TRACE(sim::WheelModelName(wheels));
    const Drive straight = DriveStraight(wheels, std::nullopt);
    const Drive biased = DriveStraight(wheels, LeftTyre(1.02, 4.0));
    EXPECT_EQ(biased.records, 2);
    EXPECT_NEAR(biased.biased_m, 0.5 * biased.distance_m, 0.02 * biased.distance_m);
    const double expected = ExpectedHeadingRad(biased.biased_m, 1.02, 0.50);
    EXPECT_LT(expected, 0.0);  // a bigger left tyre: a clockwise curve
    EXPECT_NEAR(biased.heading_rad - straight.heading_rad, expected,
                kCurveTolerance * std::abs(expected));
  }
}

const std::string kWorld = pavilion::testing::WalledRoomWorld("bias_room", 8);

std::string Write(const std::string& events) {
  const auto dir = TestDir();
  WriteFile(dir, "world.yaml", kWorld);
  return WriteFile(dir, "scenario.yaml",
                   "kind: scenario\n"
                   "name: bias_test\n"
                   "seed: 4\n"
                   "duration_s: 5\n"
                   "world: world.yaml\n"
                   "physics: {wheel_model: raycast}\n"
                   "robots:\n"
                   "  - {id: r1, model: robox, pose: [-4, 0, 0],\n"
                   "     drive: [{at_s: 0, speed_mps: 0.5, turn_radps: 0.0}]}\n"
                   "events:\n" +
                       events);
}

// In a run: the record in events.jsonl, and the robot's dead reckoning
// drifting by the curve it does not see (about 4 m * 0.16 rad/m * 2 m / 2).
TEST(OdometryBiasEventTest, RunRecordsTheEventAndTheOdometryDrifts) {
  const auto run = [](const std::string& events, const std::string& name) {
    const Scenario s = LoadScenarioFile(Write(events));
    const auto out = TestDir() / name;
    const RunMetrics m = RunScenario(s, RunOptions{out.string(), false, 1}).metrics;
    std::vector<nlohmann::json> records;
    std::ifstream in(out / "events.jsonl");
    for (std::string line; std::getline(in, line);) {
      nlohmann::json e = nlohmann::json::parse(line);
      if (e.at("type") == "odometry_bias") records.push_back(std::move(e));
    }
    return std::make_pair(m, records);
  };
  const auto [plain, none] = run("  []\n", "plain");
  const auto [biased, records] =
      run("  - {at_s: 0.5, type: odometry_bias, robot: r1, wheel: left, radius_scale: 0.98}\n",
          "biased");
  EXPECT_TRUE(none.empty());
  ASSERT_EQ(records.size(), 1u);
  EXPECT_EQ(records[0].at("robot"), "r1");
  EXPECT_EQ(records[0].at("wheel"), "left");
  EXPECT_DOUBLE_EQ(records[0].at("radius_scale").get<double>(), 0.98);
  EXPECT_NEAR(records[0].at("time_s").get<double>(), 0.5, 1e-9);
  // Over ~2 m after the bias the true path bends by ~0.08 rad: its end is
  // ~8 cm off the straight line the odometry believes.
  EXPECT_LT(plain.robots[0].odometry_final_position_error_m, 0.02);
  EXPECT_GT(biased.robots[0].odometry_final_position_error_m, 0.04);
}

TEST(OdometryBiasEventTest, BadInputIsAnErrorAtItsKey) {
  const auto expect_error = [](const std::string& events, const std::string& key_path,
                               const std::string& says) {
    pavilion::testing::ExpectOneLoadError(Write(events), key_path, says);
  };
  expect_error("  - {at_s: 1, type: odometry_bias, robot: r9, wheel: left, radius_scale: 0.98}\n",
               "events[0].robot", "no robot 'r9'");
  expect_error("  - {at_s: 1, type: odometry_bias, robot: r1, wheel: left, radius_scale: 0.7}\n",
               "events[0].radius_scale", "[0.8, 1.2]");
  expect_error("  - {at_s: 1, type: odometry_bias, robot: r1, wheel: left, radius_scale: 1.3}\n",
               "events[0].radius_scale", "[0.8, 1.2]");
  expect_error("  - {at_s: 1, type: odometry_bias, robot: r1, wheel: front, radius_scale: 0.98}\n",
               "events[0].wheel", "");
  expect_error("  - {at_s: 1, type: odometry_bias, robot: r1, wheel: left}\n",
               "events[0].radius_scale", "required");
  expect_error(
      "  - {at_s: 1, type: odometry_bias, robot: r1, wheel: both, radius_scale: 0.9, "
      "duration_s: -2}\n",
      "events[0].duration_s", "duration_s");
}

// The options' own check names the field at fault.
TEST(OdometryBiasEventTest, OptionsValidate) {
  OdometryBiasOptions o;
  o.radius_scale = 0.79;
  EXPECT_NE(pavilion::testing::ValidateMessage(o).find("radius_scale"), std::string::npos);
  o.radius_scale = 1.2;
  EXPECT_EQ(pavilion::testing::ValidateMessage(o), "");
  o.duration_s = 0.0;
  EXPECT_NE(pavilion::testing::ValidateMessage(o).find("duration_s"), std::string::npos);
}

}  // namespace
}  // namespace pavilion::scenarios
