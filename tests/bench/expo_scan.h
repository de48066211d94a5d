#pragma once

// The Expo hall map and a scan ray cast against its own geometry (361
// readings over 180 deg, 8 m, noise free) at its first station: the common
// input of the localization benchmarks.

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "core/geometry/segment2.h"
#include "core/localization/mcl/likelihood_field.h"
#include "scenarios/maps/map_file.h"

namespace pavilion::bench {

inline constexpr int kReadings = 361;
inline constexpr double kMaxRangeM = 8.0;

inline core::RobotMap ExpoMap() {
  return scenarios::LoadMapFile(std::string(PAVILION_SOURCE_DIR) + "/worlds/expo_hall/map.yaml");
}

// Where the scans are taken: the map's first station (a pose in the hall).
inline core::Pose2 ScanPose(const core::RobotMap& map) {
  for (const core::MapNode& n : map.nodes) {
    if (n.station) return n.pose;
  }
  return map.nodes.front().pose;
}

// A noise-free scan from `world_from_robot` against the map's segments and discs.
inline core::LaserScan CastAgainstMap(const core::RobotMap& map,
                                      const core::Pose2& world_from_robot) {
  const core::MapGeometry g = core::CollectMapGeometry(map);
  core::LaserScan scan;
  scan.sensor_id = "front";
  scan.max_range_m = kMaxRangeM;
  const Eigen::Vector2d o = world_from_robot.translation();
  for (int i = 0; i < kReadings; ++i) {
    core::LaserReading r;
    r.bearing_rad = -0.5 * std::numbers::pi + std::numbers::pi * i / (kReadings - 1);
    const double a = world_from_robot.theta_rad + r.bearing_rad;
    const Eigen::Vector2d e = o + kMaxRangeM * Eigen::Vector2d(std::cos(a), std::sin(a));
    double t = std::numeric_limits<double>::infinity();
    for (const auto& [p, q] : g.segments) t = std::min(t, core::RaySegmentHit(o, e, p, q));
    for (const auto& [c, radius] : g.discs) {
      for (const double h : core::LineCircleHits(o, e, c, radius)) {
        if (h >= 0.0 && h <= 1.0) t = std::min(t, h);
      }
    }
    r.valid = std::isfinite(t);
    r.range_m = r.valid ? t * kMaxRangeM : kMaxRangeM;
    scan.readings.push_back(r);
  }
  return scan;
}

}  // namespace pavilion::bench
