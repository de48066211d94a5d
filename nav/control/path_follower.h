#pragma once

// A path follower for a differential-drive robot: pure pursuit on a polyline
// with a speed profile limited by acceleration, turn rate and the distance to
// the goal; sharp corners are taken by turning on the spot. It steers from the
// robot's pose estimate (its localization), never from ground truth. A
// stand-in until the navigation issue's elastic band and dynamic window.

#include <Eigen/Core>
#include <vector>

#include "core/types/pose2.h"

namespace pavilion::nav {

struct PathFollowerOptions {
  double max_speed_mps = 0.6;          // m/s, [0.01, 5]
  double max_accel_mps2 = 0.4;         // m/s^2, also for braking, [0.01, 10]
  double max_turn_rate_radps = 1.0;    // rad/s, [0.01, 10]
  double max_turn_accel_radps2 = 2.0;  // rad/s^2, [0.01, 100]
  double lookahead_m = 0.6;            // pure-pursuit look-ahead distance, m, [0.05, 10]
  // Lateral acceleration allowed in curves, v^2 kappa <= this, m/s^2, [0.01, 10].
  double max_lateral_accel_mps2 = 0.3;
  // Heading errors to the look-ahead point beyond this are turned on the spot,
  // rad, (0, pi].
  double turn_in_place_rad = 0.6;
  double heading_gain = 1.5;       // turn on the spot: omega = gain * error, 1/s, > 0
  double goal_tolerance_m = 0.05;  // done within this of the last point, m, [0.001, 5]

  void Validate() const;  // throws std::invalid_argument naming the field
};

struct VelocityCommand {
  double linear_mps = 0.0;
  double angular_radps = 0.0;
};

class PathFollower {
 public:
  // `path`: at least one point; the robot starts near the first.
  PathFollower(std::vector<Eigen::Vector2d> path, const PathFollowerOptions& options);

  // The command for the next `dt_s` seconds from the pose estimate `pose`.
  VelocityCommand Update(const core::Pose2& pose, double dt_s);

  bool done() const { return done_; }
  // Arc length of the path's point nearest the robot, m.
  double progress_m() const { return progress_m_; }
  double length_m() const { return cumulative_.back(); }

 private:
  Eigen::Vector2d PointAt(double s_m) const;
  // Nearest arc length to `p` within [progress, progress + window].
  double Project(const Eigen::Vector2d& p) const;

  std::vector<Eigen::Vector2d> path_;
  std::vector<double> cumulative_;  // arc length at each point
  PathFollowerOptions options_;
  double progress_m_ = 0.0;
  VelocityCommand last_;
  bool done_ = false;
};

// Wheel speeds (rad/s, positive forward) for a command on a differential drive.
struct WheelSpeeds {
  double left_radps = 0.0;
  double right_radps = 0.0;
};
WheelSpeeds ToWheelSpeeds(const VelocityCommand& command, double left_wheel_radius_m,
                          double right_wheel_radius_m, double wheelbase_m);

}  // namespace pavilion::nav
