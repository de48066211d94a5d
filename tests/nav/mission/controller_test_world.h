#pragma once
// The small worlds the navigation controller's tests drive in: two stations
// 8 m apart on an empty floor, a square robot, walls as segments and the two
// lasers cast against them, and one tick of a localized robot among them.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "core/geometry/segment2.h"
#include "nav/mission/navigation_controller.h"

namespace pavilion::nav::test {

inline constexpr double kStepS = 0.005;

// An empty floor with two stations 8 m apart and one edge.
inline core::RobotMap TwoStations() {
  core::RobotMap map;
  map.name = "two_stations";
  map.nodes.push_back({"a", {0.0, 0.0, 0.0}, true});
  map.nodes.push_back({"b", {8.0, 0.0, 0.0}, true});
  map.edges.push_back({"a", "b", 8.0});
  return map;
}

inline std::vector<Eigen::Vector2d> Square() {
  return {{-0.3, -0.3}, {0.3, -0.3}, {0.3, 0.3}, {-0.3, 0.3}};
}

using Wall = std::pair<Eigen::Vector2d, Eigen::Vector2d>;

// A room 5 m x 4 m of segments whose wall stands 0.6 m before the front of a
// robot at the origin facing +x.

inline std::vector<Wall> Room() {
  const Eigen::Vector2d a(-4.0, -2.0), b(0.9, -2.0), c(0.9, 2.0), d(-4.0, 2.0);
  return {{a, b}, {b, c}, {c, d}, {d, a}};
}

// A front and a rear laser (180° each, 0.5° steps) cast against `walls`.
inline core::LaserScan RoomScan(const core::Pose2& pose, const std::vector<Wall>& walls, bool front,
                                double now_s) {
  core::LaserScan scan;
  scan.sensor_id = front ? "front" : "rear";
  scan.stamp_s = now_s;
  scan.robot_from_sensor = front ? core::Pose2{0.22, 0.0, 0.0} : core::Pose2{-0.22, 0.0, M_PI};
  const core::Pose2 world_from_sensor = pose * scan.robot_from_sensor;
  const Eigen::Vector2d origin = world_from_sensor.translation();
  for (int i = 0; i <= 360; ++i) {
    core::LaserReading r;
    r.bearing_rad = -0.5 * M_PI + i * 0.5 * M_PI / 180.0;
    const Eigen::Vector2d end =
        world_from_sensor * Eigen::Vector2d(scan.max_range_m * std::cos(r.bearing_rad),
                                            scan.max_range_m * std::sin(r.bearing_rad));
    double t = std::numeric_limits<double>::infinity();
    for (const Wall& w : walls)
      t = std::min(t, core::RaySegmentHit(origin, end, w.first, w.second));
    r.valid = std::isfinite(t);
    r.range_m = r.valid ? t * scan.max_range_m : scan.max_range_m;
    scan.readings.push_back(r);
  }
  return scan;
}

// One physics tick of a localized robot (belief = truth) among `walls`:
// both lasers every 20 ticks (10 Hz), then the controller's tick; a new
// command replaces `held`.
inline void TickAmongWalls(NavigationController& controller, const std::vector<Wall>& walls,
                           std::int64_t tick, const core::Pose2& pose, WheelSpeeds* held) {
  const double now_s = tick * kStepS;
  if (tick % 20 == 0) {
    for (const bool front : {true, false}) {
      controller.OnScan(RoomScan(pose, walls, front, now_s), ScanContext{now_s, pose, pose});
    }
  }
  if (const std::optional<WheelSpeeds> w =
          controller.OnTick(ControlTick{tick, now_s, pose, pose, false})) {
    *held = *w;
  }
}

}  // namespace pavilion::nav::test
