#pragma once

// The controller seam of the robot stack (nav::Navigator): whatever turns the
// robot's belief about its pose and its scans into wheel speeds. Today a
// scripted drive profile, a route follower and the hall benchmark's wander;
// the three-layer navigation of thesis chapter 6 plugs in here next.

#include <cstdint>
#include <optional>

#include "core/types/pose2.h"
#include "core/types/sensor_data.h"
#include "nav/control/path_follower.h"

namespace pavilion::nav {

// How a controller with a goal is doing (route_done event, run metrics).
struct MissionStatus {
  bool done = false;
  double done_at_s = 0.0;      // simulation time the goal was reached
  double path_length_m = 0.0;  // length of the planned path
};

// The control step before the physics step `tick` (at time `now_s`).
struct ControlTick {
  std::int64_t tick = 0;
  double now_s = 0.0;
  core::Pose2 belief;  // the robot's own estimate (EKF, or odometry without one)
};

class Controller {
 public:
  virtual ~Controller() = default;
  // A new wheel-speed command held from this step on, or none to keep the last.
  virtual std::optional<WheelSpeeds> OnTick(const ControlTick& tick) = 0;
  // A scan the robot just finished; a command held from the next step on.
  virtual std::optional<WheelSpeeds> OnScan(const core::LaserScan& /*scan*/) {
    return std::nullopt;
  }
  // Controllers working towards a goal report it; the others none.
  virtual std::optional<MissionStatus> mission() const { return std::nullopt; }
};

}  // namespace pavilion::nav
