#pragma once

// The hall benchmark's wander as a robot-stack controller: on each scan of one
// laser, the wander controller's new command (held until the next such scan).

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
  std::optional<WheelSpeeds> OnTick(const ControlTick&) override { return std::nullopt; }
  std::optional<WheelSpeeds> OnScan(const core::LaserScan& scan,
                                    const ScanContext& context) override;

 private:
  WanderController wander_;
  std::string laser_id_;
  core::EncoderOdometryOptions odometry_;
};

}  // namespace pavilion::nav
