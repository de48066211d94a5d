#include "nav/control/wander_scan_controller.h"

#include <utility>

namespace pavilion::nav {

WanderScanController::WanderScanController(WanderController wander, std::string laser_id,
                                           const core::EncoderOdometryOptions& odometry)
    : wander_(std::move(wander)), laser_id_(std::move(laser_id)), odometry_(odometry) {}

std::optional<WheelSpeeds> WanderScanController::OnScan(const core::LaserScan& scan,
                                                        const ScanContext& /*context*/) {
  if (scan.sensor_id != laser_id_) return std::nullopt;
  const VelocityCommand command = wander_.Update(scan.readings);
  return ToWheelSpeeds(command, odometry_.left_wheel_radius_m, odometry_.right_wheel_radius_m,
                       odometry_.wheelbase_m);
}

}  // namespace pavilion::nav
