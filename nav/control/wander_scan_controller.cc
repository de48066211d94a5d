#include "nav/control/wander_scan_controller.h"

#include <utility>

namespace pavilion::nav {
namespace {
// The bumper escape: back away at this speed, turning at this rate, this long.
// Chosen: 15 cm back and about 30 deg of turn clear a glass panel's edge.
constexpr double kBumperEscapeS = 1.0;
constexpr double kEscapeSpeedMps = -0.15;
constexpr double kEscapeTurnRadps = 0.5;
}  // namespace

WanderScanController::WanderScanController(WanderController wander, std::string laser_id,
                                           const core::EncoderOdometryOptions& odometry)
    : wander_(std::move(wander)), laser_id_(std::move(laser_id)), odometry_(odometry) {}

void WanderScanController::OnBumper(const core::BumperReading& reading,
                                    const ScanContext& context) {
  if (reading.zones_in_contact != 0) escape_until_s_ = context.now_s + kBumperEscapeS;
}

std::optional<WheelSpeeds> WanderScanController::OnTick(const ControlTick& tick) {
  const bool escape = tick.now_s < escape_until_s_;
  if (escape == escaping_) return std::nullopt;
  escaping_ = escape;
  // Entering the escape: back away; leaving it: stand until the next scan.
  const VelocityCommand command =
      escape ? VelocityCommand{kEscapeSpeedMps, kEscapeTurnRadps} : VelocityCommand{};
  return ToWheelSpeeds(command, odometry_.left_wheel_radius_m, odometry_.right_wheel_radius_m,
                       odometry_.wheelbase_m);
}

std::optional<WheelSpeeds> WanderScanController::OnScan(const core::LaserScan& scan,
                                                        const ScanContext& context) {
  if (scan.sensor_id != laser_id_ || context.now_s < escape_until_s_) return std::nullopt;
  const VelocityCommand command = wander_.Update(scan.readings);
  return ToWheelSpeeds(command, odometry_.left_wheel_radius_m, odometry_.right_wheel_radius_m,
                       odometry_.wheelbase_m);
}

}  // namespace pavilion::nav
