// Scan registration while moving (thesis §2.2.1.4, eq. 2.4, and §4.4.4).
#include "core/localization/scan_deskew.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/support/localization_world.h"

namespace pavilion::core {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kWheelbaseM = 0.5;

// A robot turning and driving during a slow scan of a wall: each reading is
// taken from the sensor pose of its own instant. After registration every
// point lies on the wall as seen from the sensor pose of the first reading,
// where the raw scan is visibly bent.
TEST(ScanDeskewTest, RegistersReadingsIntoTheFirstReadingsFrame) {
  OdometryBuffer buffer(kWheelbaseM, {}, 10.0);
  const Pose2 start{1.0, -0.5, 0.2};
  buffer.Reset(10.0, {start, Eigen::Matrix3d::Zero()}, start);
  // 0.4 s scan (Acuity-like, §2.2.1.4), odometry at 200 Hz, turning while driving.
  for (int k = 1; k <= 100; ++k) buffer.Append(10.0 + 0.005 * k, {0.002, 0.004});
  const Pose2 robot_from_sensor{0.2, 0.05, 0.1};
  const MapLine wall = testing::MapLineThrough("wall", {6, -10}, {6, 10}, {0, 0});

  LaserScan scan;
  scan.stamp_s = 10.0;
  scan.robot_from_sensor = robot_from_sensor;
  for (int i = 0; i < 181; ++i) {
    const double t = 0.4 * i / 180.0;
    const Pose2 world_from_sensor = *buffer.OdometryPoseAt(10.0 + t) * robot_from_sensor;
    LaserReading r;
    r.bearing_rad = -kPi / 2 + kPi * i / 180.0;
    r.time_offset_s = t;
    // Range to the wall x = 6 along the beam.
    const double heading = world_from_sensor.theta_rad + r.bearing_rad;
    r.range_m = (6.0 - world_from_sensor.x_m) / std::cos(heading);
    r.valid = std::cos(heading) > 0.2 && r.range_m < 30.0;
    if (!r.valid) r.range_m = 30.0;
    scan.readings.push_back(r);
  }
  const std::optional<LaserScan> registered = DeskewScan(scan, buffer);
  ASSERT_TRUE(registered.has_value());
  EXPECT_DOUBLE_EQ(registered->stamp_s, 10.0);
  const Line seen = LineInChild(wall.line, start * robot_from_sensor);
  double raw_worst = 0.0;
  int checked = 0;
  for (std::size_t i = 0; i < scan.readings.size(); ++i) {
    const LaserReading& r = registered->readings[i];
    EXPECT_EQ(r.time_offset_s, 0.0);
    if (!r.valid) continue;
    const Eigen::Vector2d p(r.range_m * std::cos(r.bearing_rad),
                            r.range_m * std::sin(r.bearing_rad));
    EXPECT_NEAR(seen.SignedDistance(p), 0.0, 1e-9) << i;
    const LaserReading& raw = scan.readings[i];
    raw_worst = std::max(raw_worst,
                         std::abs(seen.SignedDistance({raw.range_m * std::cos(raw.bearing_rad),
                                                       raw.range_m * std::sin(raw.bearing_rad)})));
    ++checked;
  }
  EXPECT_GT(checked, 100);
  EXPECT_GT(raw_worst, 0.1);  // the uncompensated scan is bent by tens of cm
}

// A scan whose readings share one time is returned unchanged (with its stamp
// moved to the first reading); one beyond the buffered odometry cannot be
// registered.
TEST(ScanDeskewTest, LeavesInstantScansAloneAndNeedsOdometryCoverage) {
  OdometryBuffer buffer(kWheelbaseM, {}, 10.0);
  buffer.Reset(0.0, {}, {});
  buffer.Append(0.1, {0.01, 0.02});
  LaserScan scan;
  scan.stamp_s = 0.05;
  for (int i = 0; i < 3; ++i) scan.readings.push_back({2.0 + i, 0.1 * i, 0.0, true, false});
  const std::optional<LaserScan> same = DeskewScan(scan, buffer);
  ASSERT_TRUE(same.has_value());
  for (int i = 0; i < 3; ++i) EXPECT_EQ(same->readings[i].range_m, scan.readings[i].range_m);
  scan.readings[2].time_offset_s = 0.08;  // 0.13 s: after the latest odometry
  EXPECT_FALSE(DeskewScan(scan, buffer).has_value());
}

}  // namespace
}  // namespace pavilion::core
