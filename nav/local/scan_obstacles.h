#pragma once

// The obstacle points the local planner and the dynamic window see (thesis
// §6.3.4): every valid reading of the latest scan of each laser — no memory
// beyond it — plus the map's ghost points injected as virtual readings. Scans
// are kept in the odometry frame, which moves smoothly with the robot, so a
// scan taken a few ticks ago still lands where it was seen.
//
// The dynamic window also gets a short memory of the blind zones: a reading
// of the last `blind_memory_s` that no laser's field of view covers now (the
// sides of a robot with two lasers back to back, §6.3.5.1) stays an obstacle,
// so that a robot turning through a door does not sweep its corner into the
// door post it saw a moment ago. The local grid keeps to the thesis: no memory.

#include <Eigen/Core>
#include <span>
#include <string>
#include <vector>

#include "core/types/pose2.h"
#include "core/types/sensor_data.h"

namespace pavilion::nav {

class ScanObstacles {
 public:
  // `footprint_in_robot`: the robot's polygon; readings inside it (the robot
  // seeing itself) are dropped. `ghosts_in_world`: the map's ghost points.
  ScanObstacles(std::vector<Eigen::Vector2d> footprint_in_robot,
                std::vector<Eigen::Vector2d> ghosts_in_world, double blind_memory_s = 1.0);

  // Replaces the points of `scan`'s laser; `odom_from_robot` is the robot's
  // odometry pose when the scan arrived.
  void AddScan(const core::LaserScan& scan, const core::Pose2& odom_from_robot);

  // The laser points, the remembered blind-zone points and the ghost points
  // within `reach_m` of the robot, in the robot frame (the dynamic window's
  // input). `world_from_robot` is the belief, `odom_from_robot` the odometry
  // pose, both now.
  void InRobot(const core::Pose2& odom_from_robot, const core::Pose2& world_from_robot,
               double reach_m, std::vector<Eigen::Vector2d>* points_in_robot) const;
  // The same within `reach_m` of the robot in the world frame (the local grid's input).
  void InWorld(const core::Pose2& odom_from_robot, const core::Pose2& world_from_robot,
               double reach_m, std::vector<Eigen::Vector2d>* points_in_world) const;

  std::size_t laser_points() const;

 private:
  struct LaserPoints {
    std::string sensor_id;
    std::vector<Eigen::Vector2d> in_odom;
    core::Pose2 sensor_from_robot;  // its mount, inverted once per scan
    double min_bearing_rad = 0.0;   // the scan's field of view
    double max_bearing_rad = 0.0;
    double max_range_m = 0.0;
    double remembered_s = -1e9;  // stamp of its last scan kept in memory_
  };
  struct Remembered {
    double stamp_s = 0.0;
    std::vector<Eigen::Vector2d> in_odom;
  };
  // True when a laser's current field of view covers the point (robot frame).
  bool Covered(const Eigen::Vector2d& point_in_robot) const;

  std::vector<Eigen::Vector2d> footprint_;
  std::vector<Eigen::Vector2d> ghosts_in_world_;
  double blind_memory_s_;
  std::vector<LaserPoints> lasers_;
  std::vector<Remembered> memory_;  // earlier scans (thinned), oldest first
};

// Distance (m) from a convex polygon to the nearest of `points` (0 for a point
// inside it); +infinity without points.
double PolygonClearance(std::span<const Eigen::Vector2d> polygon,
                        std::span<const Eigen::Vector2d> points);

}  // namespace pavilion::nav
