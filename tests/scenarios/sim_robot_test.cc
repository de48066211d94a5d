// A simulated robot's sensors in a world: scan and encoder timing, the
// retro-reflective markers of one Robox in another's scan, bumpers, and
// determinism. Uses the shipped robots/robox model.
#include "sim/sim_robot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/odometry/diff_drive.h"
#include "scenarios/robot_loader.h"
#include "scenarios/robot_setup.h"

namespace pavilion {
namespace {

constexpr double kPi = std::numbers::pi;

sim::WorldDescription Floor(bool wall) {
  sim::WorldDescription w;
  w.name = "floor";
  w.materials["floor"] = sim::Material{0.8, 0.0, {0.5, 0.5, 0.5, 1}, core::LaserResponse::kNormal};
  w.floor = {{-10, -10}, {10, 10}, "floor"};
  if (wall) {
    sim::Wall x;
    x.id = "wall";
    x.points_m = {{3, -4}, {3, 4}};
    x.thickness_m = 0.2;
    x.height_m = 2.0;
    x.material = "floor";
    w.walls.push_back(x);
  }
  return w;
}

// Dead reckoning from encoder readings with the robot file's calibrated odometry.
struct EncoderOdometer {
  sim::OdometryCalibration calibration;
  core::Pose2 pose;
  bool started = false;
  std::int64_t left = 0, right = 0;
  void Update(const core::EncoderReading& r) {
    if (started) {
      const double per_tick = 2 * kPi / r.ticks_per_revolution;
      pose = core::DiffDriveStep(
          pose,
          {static_cast<double>(r.left_ticks - left) * per_tick * calibration.left_wheel_radius_m,
           static_cast<double>(r.right_ticks - right) * per_tick *
               calibration.right_wheel_radius_m},
          calibration.wheelbase_m);
    }
    started = true;
    left = r.left_ticks;
    right = r.right_ticks;
  }
};

const sim::RobotConfig& Robox() {
  static const sim::RobotConfig config =
      scenarios::LoadRobotFile(PAVILION_SOURCE_DIR "/robots/robox/robot.yaml");
  return config;
}

struct Scene {
  std::unique_ptr<sim::World> world;
  std::vector<std::unique_ptr<sim::SimRobot>> robots;
  std::vector<std::vector<sim::SensorOutputs>> outputs;

  Scene(bool wall, const std::vector<core::Pose2>& poses, std::uint64_t seed = 1) {
    sim::WorldDescription d = Floor(wall);
    std::vector<sim::SimRobotSetup> setups;
    for (std::size_t k = 0; k < poses.size(); ++k) {
      setups.push_back(
          scenarios::MakeSimRobotSetup("robox_" + std::to_string(k), Robox(), poses[k], &d));
    }
    world = std::make_unique<sim::World>(d, sim::WorldOptions{});
    for (auto& s : setups) robots.push_back(std::make_unique<sim::SimRobot>(world.get(), s, seed));
    outputs.resize(robots.size());
  }

  void Run(double seconds) {
    const int steps = static_cast<int>(std::lround(seconds / world->step_s()));
    for (int i = 0; i < steps; ++i) {
      const sim::TickSnapshot before = world->Snapshot();
      world->Step();
      const sim::TickSnapshot after = world->Snapshot();
      for (std::size_t k = 0; k < robots.size(); ++k) {
        outputs[k].push_back(robots[k]->AfterStep(before.robots[k], after.robots[k]));
      }
    }
  }

  std::vector<sim::ScanRecord> Scans(int robot) const {
    std::vector<sim::ScanRecord> scans;
    for (const auto& o : outputs[robot]) scans.insert(scans.end(), o.scans.begin(), o.scans.end());
    return scans;
  }
};

// Acceptance: a 10 m straight drive of the shipped Pygmalion on the flat floor,
// its encoders (50,000 ticks per turn) integrated with its robot file's
// calibrated odometry, ends within 0.5 % of the distance from the truth.
TEST(SimRobot, PygmalionTenMetreStraightDriveOdometryWithinHalfAPercent) {
  const sim::RobotConfig pygmalion =
      scenarios::LoadRobotFile(PAVILION_SOURCE_DIR "/robots/pygmalion/robot.yaml");
  sim::WorldDescription d = Floor(false);
  const core::Pose2 start{-5, 0, 0};
  const sim::SimRobotSetup setup = scenarios::MakeSimRobotSetup("p", pygmalion, start, &d);
  sim::World world(d, sim::WorldOptions{});
  sim::SimRobot robot(&world, setup, 1);
  EncoderOdometer odo{pygmalion.odometry, start};
  const double speed = 0.5;  // m/s
  robot.SetWheelSpeeds(speed / pygmalion.odometry.left_wheel_radius_m,
                       speed / pygmalion.odometry.right_wheel_radius_m);
  for (int i = 0; i < 6000 && world.robot_state(robot.index()).pose.x_m < 5.0; ++i) {
    const sim::RobotState before = world.robot_state(robot.index());
    world.Step();
    for (const auto& e : robot.AfterStep(before, world.robot_state(robot.index())).encoders) {
      odo.Update(e);
    }
  }
  const core::Pose2 truth = world.robot_state(robot.index()).pose;
  const double travelled = (truth.translation() - start.translation()).norm();
  ASSERT_GT(travelled, 9.99);
  EXPECT_LT((odo.pose.translation() - truth.translation()).norm(), 0.005 * travelled);
}

TEST(SimRobot, ScansAtTheScanRateAndEncodersAtTheirs) {
  Scene scene(false, {{0, 0, 0}});
  scene.Run(1.0);
  const auto scans = scene.Scans(0);
  ASSERT_EQ(scans.size(), 20u);  // two LMS 200 at 10 Hz
  for (std::size_t i = 0; i < scans.size(); ++i) {
    EXPECT_NEAR(scans[i].scan.stamp_s, 0.1 * static_cast<double>(i / 2), 1e-9);
    EXPECT_EQ(scans[i].scan.readings.size(), 361u);
  }
  EXPECT_EQ(scans[0].scan.sensor_id, "front");
  EXPECT_EQ(scans[1].scan.sensor_id, "rear");
  int encoder_readings = 0;
  for (const auto& o : scene.outputs[0]) encoder_readings += static_cast<int>(o.encoders.size());
  EXPECT_EQ(encoder_readings, 200);  // 200 Hz
}

// §6.3.5.1: the markers in the blind zones make robots visible to each other
// through the reflector bit.
// At 100 Hz physics the shipped robots' 200 Hz encoders read twice a tick, the
// first at the wheel angles halfway through it; scans keep their rate.
TEST(SimRobot, HundredHertzPhysicsKeepsTheSensorRates) {
  for (const sim::WheelModel wheels : {sim::WheelModel::kArticulated, sim::WheelModel::kRaycast}) {
    sim::WorldDescription d = Floor(false);
    sim::SimRobotSetup setup = scenarios::MakeSimRobotSetup("r", Robox(), {0, 0, 0}, &d);
    setup.spec.wheel_model = wheels;
    sim::WorldOptions options;
    options.physics_rate_hz = 100.0;
    sim::World world(d, options);
    sim::SimRobot robot(&world, setup, 1);
    robot.SetWheelSpeeds(3.0, 3.0);
    std::vector<core::EncoderReading> encoders;
    int scans = 0;
    for (int i = 0; i < 100; ++i) {
      const sim::RobotState before = world.robot_state(robot.index());
      world.Step();
      const sim::SensorOutputs out = robot.AfterStep(before, world.robot_state(robot.index()));
      encoders.insert(encoders.end(), out.encoders.begin(), out.encoders.end());
      scans += static_cast<int>(out.scans.size());
    }
    ASSERT_EQ(encoders.size(), 200u);
    EXPECT_EQ(scans, 20);
    for (std::size_t k = 0; k < encoders.size(); ++k) {
      EXPECT_NEAR(encoders[k].stamp_s, 0.005 * static_cast<double>(k + 1), 1e-12);
    }
    // Accelerating: each half tick's ticks lie between the neighbouring readings'.
    for (std::size_t k = 2; k < encoders.size(); k += 2) {
      EXPECT_GE(encoders[k - 1].left_ticks, encoders[k - 2].left_ticks);
      EXPECT_LE(encoders[k - 1].left_ticks, encoders[k].left_ticks);
    }
    EXPECT_GT(encoders.back().left_ticks, encoders[100].left_ticks);
  }
}

TEST(SimRobot, RetroMarkersOfOneRobotAreFlaggedInTheOthersScan) {
  // Robot 1 stands 2.5 m ahead of robot 0, side on: its left marker faces robot 0.
  Scene scene(false, {{0, 0, 0}, {2.5, 0, -kPi / 2}});
  scene.Run(0.1);
  const sim::World& world = *scene.world;
  int flagged = 0, marker_hits = 0;
  for (const auto& s : scene.Scans(0)) {
    for (std::size_t i = 0; i < s.scan.readings.size(); ++i) {
      const int e = s.truth.element[i];
      const bool on_marker = e >= 0 && world.elements()[e].id.starts_with("robox_1/");
      marker_hits += on_marker;
      if (s.scan.readings[i].reflector) {
        ++flagged;
        EXPECT_TRUE(on_marker) << "reflector flag off a marker, reading " << i;
      }
    }
  }
  EXPECT_GT(marker_hits, 0);
  EXPECT_GT(flagged, 0);
  // Its own markers are never seen: the robot's parts are ignored by its rays.
  for (const auto& s : scene.Scans(1)) {
    for (int e : s.truth.element) {
      if (e >= 0) {
        EXPECT_FALSE(world.elements()[e].id.starts_with("robox_1"));
      }
    }
  }
}

TEST(SimRobot, DrivingIntoAWallPressesTheFrontBumper) {
  Scene scene(true, {{1.5, 0, 0}});
  scene.robots[0]->SetWheelSpeeds(4.0, 4.0);
  scene.Run(4.0);
  const auto& zones = Robox().bumpers;
  std::uint32_t pressed = 0;
  for (const auto& o : scene.outputs[0]) {
    for (const auto& b : o.bumpers) pressed |= b.zones_in_contact;
  }
  ASSERT_NE(pressed, 0u);
  ASSERT_EQ(zones[0].name, "front");
  EXPECT_TRUE(pressed & 1u);
  EXPECT_FALSE(pressed & (1u << 4));  // not the rear
}

TEST(SimRobot, SameSeedSameScansDifferentSeedDifferentNoise) {
  const auto run = [](std::uint64_t seed) {
    Scene scene(true, {{0, 0, 0.3}, {1.5, 1.5, 2.0}}, seed);
    scene.robots[0]->SetWheelSpeeds(3.0, 2.0);
    scene.Run(0.5);
    return scene.Scans(0);
  };
  const auto a = run(7), b = run(7), c = run(8);
  ASSERT_EQ(a.size(), b.size());
  bool differs = false;
  for (std::size_t s = 0; s < a.size(); ++s) {
    for (std::size_t i = 0; i < a[s].scan.readings.size(); ++i) {
      EXPECT_EQ(a[s].scan.readings[i].range_m, b[s].scan.readings[i].range_m);
      differs |= a[s].scan.readings[i].range_m != c[s].scan.readings[i].range_m;
    }
  }
  EXPECT_TRUE(differs);
}

}  // namespace
}  // namespace pavilion
