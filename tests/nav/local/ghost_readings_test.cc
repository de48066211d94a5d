// Ghost points injected into a scan as virtual readings (nav/local/ghost_readings.h).
#include "nav/local/ghost_readings.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "core/types/pose2.h"
#include "core/types/sensor_data.h"

namespace pavilion::nav {
namespace {

constexpr double kPi = std::numbers::pi;

// A 180° scan at 1° from a laser 0.2 m ahead of the robot's centre, no returns.
core::LaserScan EmptyScan() {
  core::LaserScan scan;
  scan.sensor_id = "front";
  scan.max_range_m = 8.0;
  scan.robot_from_sensor = core::Pose2(0.2, 0.0, 0.0);
  for (int k = 0; k <= 180; ++k) {
    core::LaserReading r;
    r.bearing_rad = (k - 90) * kPi / 180.0;
    r.range_m = scan.max_range_m;
    scan.readings.push_back(r);
  }
  return scan;
}

TEST(GhostReadings, PutsAGhostOnItsNearestBeamFromTheBelief) {
  // The robot at (1, 2) facing +y; a ghost 1.2 m ahead of its centre, 1 m from the laser.
  const core::Pose2 world_from_robot(1.0, 2.0, kPi / 2.0);
  const GhostReadings ghosts({{1.0, 3.2}}, 0.35);
  const core::LaserScan out = ghosts.Inject(EmptyScan(), world_from_robot);
  const core::LaserReading& ahead = out.readings[90];
  EXPECT_TRUE(ahead.valid);
  EXPECT_NEAR(ahead.range_m, 1.0, 1e-9);
  int valid = 0;
  for (const core::LaserReading& r : out.readings) valid += r.valid ? 1 : 0;
  EXPECT_EQ(valid, 1);
}

TEST(GhostReadings, KeepsNearerReturnsAndSkipsWhatCannotBeThere) {
  const core::Pose2 robot;  // at the origin facing +x
  core::LaserScan scan = EmptyScan();
  scan.readings[90].valid = true;  // a person 0.5 m ahead of the laser
  scan.readings[90].range_m = 0.5;
  const GhostReadings ghosts({{1.2, 0.0},   // behind the person: hidden
                              {0.1, 0.1},   // inside the robot: a wrong belief, left out
                              {-2.0, 0.0},  // behind the laser: outside its field of view
                              {9.0, 0.0}},  // beyond its range
                             0.35);
  const core::LaserScan out = ghosts.Inject(scan, robot);
  for (std::size_t i = 0; i < out.readings.size(); ++i) {
    EXPECT_EQ(out.readings[i].valid, scan.readings[i].valid) << i;
    EXPECT_EQ(out.readings[i].range_m, scan.readings[i].range_m) << i;
  }
}

TEST(GhostReadings, RejectsANegativeRadius) {
  EXPECT_THROW(GhostReadings({}, -0.1), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::nav
