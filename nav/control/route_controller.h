#pragma once

// A route over the map's topology followed by the path follower from the
// robot's belief, at its own control rate (the scenarios' `route:` block).

#include <cstdint>
#include <vector>

#include "core/localization/encoder_odometry.h"
#include "nav/control/controller.h"
#include "nav/control/path_follower.h"

namespace pavilion::nav {

struct RouteControllerOptions {
  PathFollowerOptions follower;
  double start_s = 0.0;           // the robot waits until then (s), >= 0
  std::int64_t period_ticks = 1;  // physics steps between control steps, >= 1
  double step_s = 0.005;          // the physics step (s), > 0
  // Wheel radii and wheelbase that turn (v, omega) into wheel speeds: the
  // robot's calibrated odometry model.
  core::EncoderOdometryOptions odometry;

  void Validate() const;  // throws std::invalid_argument naming the field
};

class RouteController : public Controller {
 public:
  // `path`: the route's polyline from the robot's start (at least one point).
  RouteController(std::vector<Eigen::Vector2d> path, const RouteControllerOptions& options);
  std::optional<WheelSpeeds> OnTick(const ControlTick& tick) override;
  std::optional<MissionStatus> mission() const override { return status_; }

 private:
  RouteControllerOptions options_;
  PathFollower follower_;
  MissionStatus status_;
};

}  // namespace pavilion::nav
