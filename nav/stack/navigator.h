#pragma once

// One robot's software: what runs on the robot, given only what a real robot
// gets — timestamped sensor readings, its map (inside its estimator) and its
// mission (inside its controller) — never ground truth. It dead-reckons from
// its encoders, keeps a pose estimate when it has an estimator, and turns its
// belief and scans into wheel speeds through its controller.
//
// Each tick of a run calls Control() before the physics step and Sense() after
// it (architecture.md: the robot-stack tasks run on multiples of the physics
// step). Sense() touches only this navigator, so the robots of a fleet may
// sense on several threads at once.

#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "core/localization/encoder_odometry.h"
#include "core/types/sensor_data.h"
#include "nav/control/controller.h"
#include "nav/stack/pose_estimator.h"

namespace pavilion::nav {

struct NavigatorOptions {
  core::EncoderOdometryOptions odometry;  // the robot's calibrated odometry model
  core::Pose2 start_pose;                 // where its dead reckoning starts
  // A new bumper press counts as one (BumperContact::press) at most once in
  // this long, s >= 0: a visitor's bump flickers the bumper zones on and off
  // several times in a second, and each flicker is not another collision
  // (stacked, eight additions of a 0.15 rad sigma left an EKF 40 deg off).
  // The time the zones stay pressed counts in full (BumperContact::held_s);
  // the odometry's turn counts from a press while the zones stay pressed and
  // for this long after it (BumperContact::turned_rad).
  double collision_refractory_s = 1.0;
};

// The readings of one tick, in the order the sensors produced them.
struct SensorFrame {
  double now_s = 0.0;  // end of the tick
  std::span<const core::EncoderReading> encoders;
  std::vector<const core::LaserScan*> scans;
  std::span<const core::BumperReading> bumpers;
  std::vector<const core::CameraImage*> images;
};

// What the stack did with a tick's readings.
struct SenseResult {
  std::optional<EstimatorCycle> cycle;         // an estimation cycle completed
  std::optional<EstimatorCycle> shadow_cycle;  // the shadow estimator's
  std::optional<WheelSpeeds> command;          // the controller reacted to a scan
};

class Navigator {
 public:
  // `estimator` and `controller` may be null: a robot without localization
  // believes its odometry; one without a controller keeps its wheels still.
  Navigator(const NavigatorOptions& options, std::unique_ptr<PoseEstimator> estimator,
            std::unique_ptr<Controller> controller);

  // Before the physics step `tick` at `now_s`: the controller's new command.
  std::optional<WheelSpeeds> Control(std::int64_t tick, double now_s);
  // Whether Control at `tick` is worth a worker thread (Controller::BusyTick).
  bool ControlBusy(std::int64_t tick) const { return controller_ && controller_->BusyTick(tick); }
  // After the step: the tick's readings update odometry and estimate; the
  // controller sees the scans.
  SenseResult Sense(const SensorFrame& frame);

  // An estimator run in shadow on the same readings (a baseline to compare
  // with, e.g. Monte Carlo localization); it never drives the robot.
  void SetShadowEstimator(std::unique_ptr<PoseEstimator> shadow) { shadow_ = std::move(shadow); }

  // The pose the robot believes: its estimate, or its odometry without one.
  core::Pose2 belief() const;
  // The estimator holds no single location (lost or not localized).
  bool not_localized() const {
    return estimator_ && estimator_->mode() != LocalizationMode::kLocalized;
  }
  const core::Pose2& odometry_pose() const { return odometry_.pose(); }
  const PoseEstimator* estimator() const { return estimator_.get(); }
  const PoseEstimator* shadow_estimator() const { return shadow_.get(); }
  const Controller* controller() const { return controller_.get(); }
  Controller* mutable_controller() { return controller_.get(); }

 private:
  core::DeadReckoning odometry_;
  std::unique_ptr<PoseEstimator> estimator_;
  std::unique_ptr<Controller> controller_;
  std::unique_ptr<PoseEstimator> shadow_;
  // What the bumpers felt this frame, from their readings (in order), and
  // how far the odometry turned in it (`turned_rad`) if during a collision.
  BumperContact FeelBumpers(const SensorFrame& frame, double turned_rad);

  // The belief and the odometry at the last Control() while localized
  // (ControlTick::last_localized).
  struct Anchor {
    core::Pose2 belief;
    core::Pose2 odometry;
  };
  std::optional<Anchor> localized_at_;

  std::uint32_t bumper_zones_ = 0;  // pressed at the last bumper reading
  double collision_refractory_s_ = 1.0;
  double last_press_s_ = -1e300;     // the last press that counted
  double held_until_s_ = 0.0;        // pressed time is counted up to here
  double collision_turn_rad_ = 0.0;  // the odometry's turn since the last press
};

}  // namespace pavilion::nav
