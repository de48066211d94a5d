#include "nav/local/scan_obstacles.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/geometry/polygon.h"
#include "core/geometry/segment2.h"
#include "nav/reactive/swept_polygon.h"

namespace pavilion::nav {
namespace {

// Blind-zone memory: one scan per laser this often (s), points this near (m).
constexpr double kMemoryPeriodS = 0.1;
constexpr double kMemoryReachM = 3.0;

}  // namespace

ScanObstacles::ScanObstacles(std::vector<Eigen::Vector2d> footprint_in_robot,
                             std::vector<Eigen::Vector2d> ghosts_in_world, double blind_memory_s)
    : footprint_(std::move(footprint_in_robot)),
      ghosts_in_world_(std::move(ghosts_in_world)),
      blind_memory_s_(blind_memory_s) {}

void ScanObstacles::AddScan(const core::LaserScan& scan, const core::Pose2& odom_from_robot) {
  auto it = std::find_if(lasers_.begin(), lasers_.end(),
                         [&](const LaserPoints& l) { return l.sensor_id == scan.sensor_id; });
  if (it == lasers_.end()) {
    LaserPoints added;
    added.sensor_id = scan.sensor_id;
    lasers_.push_back(std::move(added));
    it = std::prev(lasers_.end());
  }
  // The blind-zone memory keeps a scan per laser every kMemoryPeriodS, and of
  // it only the points within kMemoryReachM of the robot: what the dynamic
  // window may need, at a tenth of the points to test each cycle.
  if (!it->in_odom.empty() && scan.stamp_s - it->remembered_s >= kMemoryPeriodS) {
    Remembered kept{scan.stamp_s, {}};
    for (const Eigen::Vector2d& p : it->in_odom) {
      if ((p - odom_from_robot.translation()).squaredNorm() <= kMemoryReachM * kMemoryReachM) {
        kept.in_odom.push_back(p);
      }
    }
    memory_.push_back(std::move(kept));
    it->remembered_s = scan.stamp_s;
  }
  std::erase_if(memory_,
                [&](const Remembered& m) { return m.stamp_s < scan.stamp_s - blind_memory_s_; });
  it->in_odom.clear();
  it->sensor_from_robot = scan.robot_from_sensor.Inverse();
  it->max_range_m = scan.max_range_m;
  if (!scan.readings.empty()) {
    it->min_bearing_rad =
        std::min(scan.readings.front().bearing_rad, scan.readings.back().bearing_rad);
    it->max_bearing_rad =
        std::max(scan.readings.front().bearing_rad, scan.readings.back().bearing_rad);
  }
  const core::Pose2 odom_from_sensor = odom_from_robot * scan.robot_from_sensor;
  for (const core::LaserReading& r : scan.readings) {
    if (!r.valid) continue;
    const Eigen::Vector2d in_sensor(r.range_m * std::cos(r.bearing_rad),
                                    r.range_m * std::sin(r.bearing_rad));
    const Eigen::Vector2d in_robot = scan.robot_from_sensor * in_sensor;
    if (!footprint_.empty() && core::Contains(footprint_, in_robot)) continue;
    it->in_odom.push_back(odom_from_sensor * in_sensor);
  }
}

void ScanObstacles::InRobot(const core::Pose2& odom_from_robot, const core::Pose2& world_from_robot,
                            double reach_m, std::vector<Eigen::Vector2d>* points_in_robot) const {
  points_in_robot->clear();
  const core::Pose2 robot_from_odom = odom_from_robot.Inverse();
  const double reach2 = reach_m * reach_m;
  for (const LaserPoints& l : lasers_) {
    for (const Eigen::Vector2d& p : l.in_odom) {
      const Eigen::Vector2d q = robot_from_odom * p;
      if (q.squaredNorm() <= reach2) points_in_robot->push_back(q);
    }
  }
  for (const Remembered& m : memory_) {
    for (const Eigen::Vector2d& p : m.in_odom) {
      const Eigen::Vector2d q = robot_from_odom * p;
      if (q.squaredNorm() <= reach2 && !Covered(q)) points_in_robot->push_back(q);
    }
  }
  const core::Pose2 robot_from_world = world_from_robot.Inverse();
  for (const Eigen::Vector2d& g : ghosts_in_world_) {
    if ((g - world_from_robot.translation()).squaredNorm() > reach2) continue;
    points_in_robot->push_back(robot_from_world * g);
  }
}

bool ScanObstacles::Covered(const Eigen::Vector2d& point_in_robot) const {
  for (const LaserPoints& l : lasers_) {
    const Eigen::Vector2d q = l.sensor_from_robot * point_in_robot;
    const double bearing = std::atan2(q.y(), q.x());
    if (bearing >= l.min_bearing_rad && bearing <= l.max_bearing_rad && q.norm() < l.max_range_m) {
      return true;
    }
  }
  return false;
}

void ScanObstacles::InWorld(const core::Pose2& odom_from_robot, const core::Pose2& world_from_robot,
                            double reach_m, std::vector<Eigen::Vector2d>* points_in_world) const {
  points_in_world->clear();
  const core::Pose2 world_from_odom = world_from_robot * odom_from_robot.Inverse();
  const Eigen::Vector2d center = world_from_robot.translation();
  const double reach2 = reach_m * reach_m;
  for (const LaserPoints& l : lasers_) {
    for (const Eigen::Vector2d& p : l.in_odom) {
      const Eigen::Vector2d q = world_from_odom * p;
      if ((q - center).squaredNorm() <= reach2) points_in_world->push_back(q);
    }
  }
  for (const Eigen::Vector2d& g : ghosts_in_world_) {
    if ((g - center).squaredNorm() <= reach2) points_in_world->push_back(g);
  }
}

std::size_t ScanObstacles::laser_points() const {
  std::size_t n = 0;
  for (const LaserPoints& l : lasers_) n += l.in_odom.size();
  return n;
}

double PolygonClearance(std::span<const Eigen::Vector2d> polygon,
                        std::span<const Eigen::Vector2d> points) {
  double best = std::numeric_limits<double>::infinity();
  const core::Polygon2 outline(polygon.begin(), polygon.end());
  const double radius_m = Circumradius(outline);
  for (const Eigen::Vector2d& p : points) {
    if (p.norm() - radius_m > best) continue;  // farther than the nearest so far
    if (core::Contains(outline, p)) return 0.0;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const Eigen::Vector2d& a = polygon[i];
      const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
      best = std::min(best, core::PointSegmentDistance(p, a, b));
    }
  }
  return best;
}

}  // namespace pavilion::nav
