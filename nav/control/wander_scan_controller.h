#pragma once

// The hall benchmark's wander as a robot-stack controller: on each scan of one
// laser, the wander controller's new command (held until the next such scan).
// A pressed bumper (an obstacle the laser does not see: glass, a low bench)
// makes it back away, turning, for `kBumperEscapeS` before the scans take over
// again — the reflex of a real robot's bumper rather than wheels spinning
// against a glass panel.

#include <optional>
#include <string>

#include "core/localization/encoder_odometry.h"
#include "nav/control/controller.h"
#include "nav/control/wander_controller.h"

namespace pavilion::nav {

class WanderScanController : public Controller {
 public:
  // Reacts to the scans of `laser_id`; `odometry` turns (v, omega) into wheel speeds.
  WanderScanController(WanderController wander, std::string laser_id,
                       const core::EncoderOdometryOptions& odometry);
  std::optional<WheelSpeeds> OnTick(const ControlTick& tick) override;
  std::optional<WheelSpeeds> OnScan(const core::LaserScan& scan,
                                    const ScanContext& context) override;
  void OnBumper(const core::BumperReading& reading, const ScanContext& context) override;

 private:
  WanderController wander_;
  std::string laser_id_;
  core::EncoderOdometryOptions odometry_;
  double escape_until_s_ = -1.0;  // backing away from a bumper contact until then
  bool escaping_ = false;
};

}  // namespace pavilion::nav
