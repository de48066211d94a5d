#pragma once

// The controller seam of the robot stack (nav::Navigator): whatever turns the
// robot's belief about its pose and its scans into wheel speeds. Today a
// scripted drive profile, a route follower and the hall benchmark's wander;
// the three-layer navigation of thesis chapter 6 plugs in here next.

#include <cstdint>
#include <optional>
#include <vector>

#include "core/types/pose2.h"
#include "core/types/sensor_data.h"
#include "nav/control/path_follower.h"
#include "nav/mission/mission.h"

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
  core::Pose2 belief;              // the robot's own estimate (EKF, or odometry without one)
  core::Pose2 odometry;            // its dead reckoning (smooth, drifting)
  bool localization_lost = false;  // its estimator declares itself lost
  // The belief's 1 sigma: the largest of its position (the covariance's
  // major half-axis) and its heading; 0 without an estimator.
  double position_sigma_m = 0.0;
  double heading_sigma_rad = 0.0;
  // Not localized: the belief of the last tick it was localized, carried on
  // by its dead reckoning since — where it is, unless it was carried off;
  // none while localized, or without an estimator. A belief once lost
  // follows look-alike hypotheses: in expo_rush (seed 1, 2 h) lost robots
  // stood a median 0.98 m from their belief when others touched them, and
  // 0.08 m from this pose.
  std::optional<core::Pose2> last_localized = std::nullopt;
  // Not localized with a single hypothesis (§5.5: n = 1 but not yet
  // determined): the belief is that hypothesis. It is often right to within
  // centimetres while last_localized has drifted: in expo_rush (seed 2, 2 h)
  // a Robox pushed by visitors while exploring carried last_localized 1.6 m
  // and 18° off in 300 s, its lone hypothesis 2-4 cm from the truth.
  bool lone_hypothesis = false;
};

// Where the robot is when a scan arrives (after the tick's odometry update).
struct ScanContext {
  double now_s = 0.0;
  core::Pose2 belief;
  core::Pose2 odometry;
};

class Controller {
 public:
  virtual ~Controller() = default;
  // A new wheel-speed command held from this step on, or none to keep the last.
  virtual std::optional<WheelSpeeds> OnTick(const ControlTick& tick) = 0;
  // Whether OnTick at `tick` does enough work to be worth a worker thread
  // (the runner calls the others inline: a thread hand-off costs more than
  // a speed ramp). Only a hint: the calls and their results are the same.
  virtual bool BusyTick(std::int64_t /*tick*/) const { return true; }
  // A scan the robot just finished; a command held from the next step on.
  virtual std::optional<WheelSpeeds> OnScan(const core::LaserScan& /*scan*/,
                                            const ScanContext& /*context*/) {
    return std::nullopt;
  }
  // A bumper reading (bit i: zone i pressed), after the tick's scans.
  virtual void OnBumper(const core::BumperReading& /*reading*/, const ScanContext& /*context*/) {}
  // Controllers working towards a goal report it; the others none.
  virtual std::optional<MissionStatus> mission() const { return std::nullopt; }

  // The navigation's view (chapter 6 controllers; the others report nothing):
  // whether localization should pause now (§6.3.3: near the final goal) ...
  virtual bool localization_paused() const { return false; }
  // ... the events since the last call, in time order ...
  virtual void TakeEvents(std::vector<NavigationEvent>* /*events*/) {}
  // ... its running figures and what the snapshot draws of it.
  virtual const NavigationFigures* navigation() const { return nullptr; }
  virtual std::optional<NavigationPicture> picture() const { return std::nullopt; }
};

}  // namespace pavilion::nav
