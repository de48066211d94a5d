#pragma once

// Synthetic 2D laser scans of wall segments and leg-sized circles, with the
// wall each reading hit: the ground truth of the feature-extraction tests.

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "core/features/uncertain_geometry.h"
#include "core/random/random_stream.h"
#include "core/types/pose2.h"
#include "core/types/sensor_data.h"

namespace pavilion::testing {

struct WallElement {
  Eigen::Vector2d a, b;  // world frame
};
struct LegCircle {
  Eigen::Vector2d center;
  double radius_m;
};
struct SyntheticWorld {
  std::vector<WallElement> walls;
  std::vector<LegCircle> legs;
};

// An 8 m x 5 m room with a 0.6 m square pillar.
inline std::vector<WallElement> RoomWithPillar() {
  std::vector<WallElement> walls;
  const std::vector<Eigen::Vector2d> room = {{0, 0}, {8, 0}, {8, 5}, {0, 5}};
  for (int i = 0; i < 4; ++i) walls.push_back({room[i], room[(i + 1) % 4]});
  const std::vector<Eigen::Vector2d> pillar = {{5.5, 3.2}, {6.1, 3.2}, {6.1, 3.8}, {5.5, 3.8}};
  for (int i = 0; i < 4; ++i) walls.push_back({pillar[i], pillar[(i + 1) % 4]});
  return walls;
}

struct SimulatedScan {
  core::LaserScan scan;
  std::vector<int> wall_hit;  // per reading, -1 for none or a leg
};

struct ScanModel {
  int readings = 361;  // LMS 200: 0.5 deg over 180 deg
  double range_sigma_m = 0.01;
  double max_range_m = 8.0;
};

// A scan from `world_from_sensor`; Gaussian range noise when `rng` is given.
inline SimulatedScan SimulateScan(const SyntheticWorld& world, const core::Pose2& world_from_sensor,
                                  core::RandomStream* rng, const ScanModel& model = {}) {
  constexpr double kPi = std::numbers::pi;
  SimulatedScan out;
  out.scan.max_range_m = model.max_range_m;
  const Eigen::Vector2d o = world_from_sensor.translation();
  for (int i = 0; i < model.readings; ++i) {
    core::LaserReading reading;
    reading.bearing_rad = -kPi / 2 + i * kPi / (model.readings - 1);
    const double heading = world_from_sensor.theta_rad + reading.bearing_rad;
    const Eigen::Vector2d d(std::cos(heading), std::sin(heading));
    double best = std::numeric_limits<double>::infinity();
    int wall = -1;
    for (int k = 0; k < static_cast<int>(world.walls.size()); ++k) {
      const Eigen::Vector2d e = world.walls[k].b - world.walls[k].a;
      const double den = d.x() * e.y() - d.y() * e.x();
      if (std::abs(den) < 1e-12) continue;
      const Eigen::Vector2d w = world.walls[k].a - o;
      const double t = (w.x() * e.y() - w.y() * e.x()) / den;
      const double u = (w.x() * d.y() - w.y() * d.x()) / den;
      if (t > 0 && u >= 0 && u <= 1 && t < best) {
        best = t;
        wall = k;
      }
    }
    for (const LegCircle& c : world.legs) {
      const Eigen::Vector2d oc = o - c.center;
      const double b = oc.dot(d);
      const double disc = b * b - (oc.squaredNorm() - c.radius_m * c.radius_m);
      if (disc < 0) continue;
      const double t = -b - std::sqrt(disc);
      if (t > 0 && t < best) {
        best = t;
        wall = -1;
      }
    }
    reading.valid = best < model.max_range_m;
    reading.range_m = reading.valid ? best : model.max_range_m;
    if (reading.valid && rng != nullptr) reading.range_m += rng->Normal(0.0, model.range_sigma_m);
    out.scan.readings.push_back(reading);
    out.wall_hit.push_back(reading.valid ? wall : -1);
  }
  return out;
}

// The true line of a wall in the sensor frame, r >= 0.
inline core::Line TrueLine(const WallElement& wall, const core::Pose2& world_from_sensor) {
  const core::Pose2 sensor_from_world = world_from_sensor.Inverse();
  const Eigen::Vector2d p = sensor_from_world * wall.a;
  const Eigen::Vector2d q = sensor_from_world * wall.b;
  const Eigen::Vector2d t = (q - p).normalized();
  core::Line line;
  line.alpha_rad = std::atan2(t.x(), -t.y());
  line.r_m = line.normal().dot(p);
  if (line.r_m < 0) {
    line.r_m = -line.r_m;
    line.alpha_rad = core::NormalizeAngle(line.alpha_rad + std::numbers::pi);
  }
  return line;
}

}  // namespace pavilion::testing
