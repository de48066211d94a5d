#pragma once

// A synthetic world for the Monte Carlo localization tests: an L-shaped room
// given as map segments, scans ray cast against the same segments, and a
// differential-drive robot whose true wheels differ from its odometry model.

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "core/geometry/segment2.h"
#include "core/localization/encoder_odometry.h"
#include "core/map/robot_map.h"
#include "core/odometry/diff_drive.h"
#include "core/random/random_stream.h"
#include "core/types/pose2.h"
#include "core/types/sensor_data.h"

namespace pavilion::testing {

using Wall = std::pair<Eigen::Vector2d, Eigen::Vector2d>;

// A map segment from a to b (the line's direction runs from a to b, as
// ValidateRobotMap wants); a and b must not be collinear with the origin.
inline core::MapSegment MapSegmentFromTo(const std::string& id, const Eigen::Vector2d& a,
                                         const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = (b - a).normalized();
  core::MapSegment s;
  s.id = id;
  s.line.alpha_rad = std::atan2(-d.x(), d.y());
  s.line.r_m = s.line.normal().dot(a);
  s.line.covariance = Eigen::Matrix2d::Identity() * 1e-6;
  s.first_endpoint = {a, Eigen::Matrix2d::Identity() * 1e-6};
  s.second_endpoint = {b, Eigen::Matrix2d::Identity() * 1e-6};
  return s;
}

// The walls of an L-shaped room: x in [1, 11] by y in [1, 5], and an arm x in
// [1, 5] by y in [5, 9] (offset from the origin so that no line has r = 0),
// plus a free-standing 1 m panel in the long part to break symmetries.
inline std::vector<Wall> LShapedRoomWalls() {
  const std::vector<Eigen::Vector2d> corner = {{1, 1}, {11, 1}, {11, 5}, {5, 5}, {5, 9}, {1, 9}};
  std::vector<Wall> walls;
  for (std::size_t i = 0; i < corner.size(); ++i) {
    walls.emplace_back(corner[i], corner[(i + 1) % corner.size()]);
  }
  walls.emplace_back(Eigen::Vector2d(8.0, 3.5), Eigen::Vector2d(9.0, 4.0));
  return walls;
}

// The map of `walls` with one topology node inside the room.
inline core::RobotMap LShapedRoomMap() {
  core::RobotMap map;
  map.name = "l_room";
  map.beam_height_m = 0.5;
  const std::vector<Wall> walls = LShapedRoomWalls();
  for (std::size_t i = 0; i < walls.size(); ++i) {
    map.segments.push_back(
        MapSegmentFromTo("wall_" + std::to_string(i), walls[i].first, walls[i].second));
  }
  map.nodes.push_back({"hub", {3.0, 3.0, 0.0}, true});
  return map;
}

// A 180-degree, 181-reading scan from the robot at `world_from_robot` against
// `walls`, ranges with N(0, sigma) noise when `noise` is given; no return
// beyond max range (valid = false).
inline core::LaserScan CastScan(const std::vector<Wall>& walls, const core::Pose2& world_from_robot,
                                double stamp_s, core::RandomStream* noise, double sigma_m = 0.01) {
  constexpr int kReadings = 181;
  core::LaserScan scan;
  scan.sensor_id = "front";
  scan.stamp_s = stamp_s;
  scan.max_range_m = 8.0;
  scan.robot_from_sensor = {0.2, 0.0, 0.0};
  const core::Pose2 world_from_sensor = world_from_robot * scan.robot_from_sensor;
  const Eigen::Vector2d origin = world_from_sensor.translation();
  for (int i = 0; i < kReadings; ++i) {
    core::LaserReading r;
    r.bearing_rad = -0.5 * std::numbers::pi + std::numbers::pi * i / (kReadings - 1);
    const double angle = world_from_sensor.theta_rad + r.bearing_rad;
    const Eigen::Vector2d end =
        origin + scan.max_range_m * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    double t = std::numeric_limits<double>::infinity();
    for (const Wall& w : walls)
      t = std::min(t, core::RaySegmentHit(origin, end, w.first, w.second));
    r.valid = std::isfinite(t);
    r.range_m = r.valid ? t * scan.max_range_m : scan.max_range_m;
    if (r.valid && noise != nullptr) r.range_m += noise->Normal(0.0, sigma_m);
    scan.readings.push_back(r);
  }
  return scan;
}

// A differential-drive robot: its true wheel radii are `scale` times the
// odometry model's, so dead reckoning drifts by (1 - 1/scale) of the path.
class DriveSimulator {
 public:
  DriveSimulator(const core::Pose2& start, const core::EncoderOdometryOptions& model, double scale)
      : truth_(start), model_(model), scale_(scale) {}

  // Drives for dt_s at v_mps and w_radps; returns the encoder reading after it.
  core::EncoderReading Step(double v_mps, double w_radps, double dt_s) {
    const double half_b = 0.5 * model_.wheelbase_m;
    const core::WheelTravel travel{(v_mps - w_radps * half_b) * dt_s,
                                   (v_mps + w_radps * half_b) * dt_s};
    truth_ = core::DiffDriveStep(truth_, travel, model_.wheelbase_m);
    left_m_ += travel.left_m;
    right_m_ += travel.right_m;
    stamp_s_ += dt_s;
    return Reading();
  }
  core::EncoderReading Reading() const {
    const auto ticks = [&](double travel_m, double radius_m) {
      return static_cast<std::int64_t>(std::llround(
          travel_m / (2.0 * std::numbers::pi * radius_m * scale_) * kTicksPerRevolution));
    };
    return {stamp_s_, ticks(left_m_, model_.left_wheel_radius_m),
            ticks(right_m_, model_.right_wheel_radius_m), kTicksPerRevolution};
  }
  void Teleport(const core::Pose2& pose) { truth_ = pose; }  // odometry is not told
  const core::Pose2& truth() const { return truth_; }
  double stamp_s() const { return stamp_s_; }

 private:
  static constexpr int kTicksPerRevolution = 4096;
  core::Pose2 truth_;
  core::EncoderOdometryOptions model_;
  double scale_;
  double left_m_ = 0.0;
  double right_m_ = 0.0;
  double stamp_s_ = 0.0;
};

}  // namespace pavilion::testing
