#pragma once

// A ray-cast 2D laser over wall segments and a drive by whole encoder ticks,
// for the global localization tests: scans and cumulative encoder readings as
// a robot receives them, generated from the true pose.

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "core/odometry/diff_drive.h"
#include "core/random/random_stream.h"
#include "core/types/pose2.h"
#include "core/types/sensor_data.h"
#include "tests/support/localization_world.h"

namespace pavilion::testing {

struct Wall {
  Eigen::Vector2d a, b;  // world frame
};

struct Scanner {
  std::string id = "laser";
  int beams = 361;
  double field_of_view_rad = std::numbers::pi;  // centred on the sensor's x axis
  double max_range_m = 8.0;
  double range_sigma_m = 0.005;
  core::Pose2 robot_from_sensor;
};

// The range along the ray from `origin` in direction `d` to the nearest wall, or +inf.
inline double CastRay(const std::vector<Wall>& walls, const Eigen::Vector2d& origin,
                      const Eigen::Vector2d& d) {
  double best = std::numeric_limits<double>::infinity();
  for (const Wall& w : walls) {
    const Eigen::Vector2d e = w.b - w.a;
    const double den = d.x() * e.y() - d.y() * e.x();
    if (std::abs(den) < 1e-12) continue;
    const Eigen::Vector2d q = w.a - origin;
    const double t = (q.x() * e.y() - q.y() * e.x()) / den;
    const double u = (q.x() * d.y() - q.y() * d.x()) / den;
    if (t > 0.0 && u >= 0.0 && u <= 1.0) best = std::min(best, t);
  }
  return best;
}

// One scan from the robot at `world_from_robot`, beams evenly over the field
// of view (a full circle: `beams` intervals, no beam twice), N(0, sigma)
// range noise from `rng` when given.
inline core::LaserScan CastScan(const std::vector<Wall>& walls, const core::Pose2& world_from_robot,
                                const Scanner& scanner, double stamp_s, core::RandomStream* rng) {
  core::LaserScan scan;
  scan.sensor_id = scanner.id;
  scan.stamp_s = stamp_s;
  scan.max_range_m = scanner.max_range_m;
  scan.robot_from_sensor = scanner.robot_from_sensor;
  const core::Pose2 world_from_sensor = world_from_robot * scanner.robot_from_sensor;
  const bool full = scanner.field_of_view_rad >= 2.0 * std::numbers::pi - 1e-9;
  const double step = scanner.field_of_view_rad / (full ? scanner.beams : scanner.beams - 1);
  for (int i = 0; i < scanner.beams; ++i) {
    core::LaserReading r;
    r.bearing_rad = -0.5 * scanner.field_of_view_rad + i * step;
    const double heading = world_from_sensor.theta_rad + r.bearing_rad;
    const double range = CastRay(walls, world_from_sensor.translation(),
                                 Eigen::Vector2d(std::cos(heading), std::sin(heading)));
    r.valid = range < scanner.max_range_m;
    r.range_m = r.valid ? range : scanner.max_range_m;
    if (r.valid && rng != nullptr) r.range_m += rng->Normal(0.0, scanner.range_sigma_m);
    scan.readings.push_back(r);
  }
  return scan;
}

// The walls of a closed polygon.
inline std::vector<Wall> PolygonWalls(const std::vector<Eigen::Vector2d>& corners) {
  std::vector<Wall> walls;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    walls.push_back({corners[i], corners[(i + 1) % corners.size()]});
  }
  return walls;
}

// The true robot driven by whole encoder ticks; with `rng`, each wheel's true
// travel departs from the measured one by N(0, k |s|) (eq. 2.9).
class TickDrive {
 public:
  TickDrive(const core::Pose2& start, int ticks_per_revolution, double wheel_radius_m,
            double wheelbase_m, double period_s)
      : pose_(start),
        encoders_(ticks_per_revolution, wheel_radius_m, wheel_radius_m),
        wheelbase_m_(wheelbase_m),
        period_s_(period_s) {}

  core::EncoderReading Start() { return encoders_.Step(stamp_s_, 0, 0); }
  core::EncoderReading Step(std::int64_t left, std::int64_t right, core::RandomStream* rng,
                            double k_m) {
    stamp_s_ += period_s_;
    core::WheelTravel actual = encoders_.Travel(left, right);
    if (rng != nullptr && k_m > 0.0) {
      actual.left_m += rng->Normal(0.0, std::sqrt(k_m * std::abs(actual.left_m)));
      actual.right_m += rng->Normal(0.0, std::sqrt(k_m * std::abs(actual.right_m)));
    }
    pose_ = core::DiffDriveStep(pose_, actual, wheelbase_m_);
    return encoders_.Step(stamp_s_, left, right);
  }
  // An unmodelled jump of the true pose (a kidnap or a collision).
  void Teleport(const core::Pose2& pose) { pose_ = pose; }

  const core::Pose2& pose() const { return pose_; }
  double stamp_s() const { return stamp_s_; }

 private:
  core::Pose2 pose_;
  EncoderStream encoders_;
  double wheelbase_m_;
  double period_s_;
  double stamp_s_ = 0.0;
};

// Position error (m) and heading error (rad) of an estimate.
inline double PositionError(const core::Pose2& a, const core::Pose2& b) {
  return std::hypot(a.x_m - b.x_m, a.y_m - b.y_m);
}
inline double HeadingError(const core::Pose2& a, const core::Pose2& b) {
  return std::abs(core::NormalizeAngle(a.theta_rad - b.theta_rad));
}

}  // namespace pavilion::testing
