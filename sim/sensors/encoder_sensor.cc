#include "sim/sensors/encoder_sensor.h"

#include <cmath>
#include <stdexcept>
#include <utility>

namespace pavilion::sim {

EncoderSensor::EncoderSensor(const std::string& robot_id, const EncoderOptions& options,
                             double left_radius_m, double right_radius_m, core::RandomStream stream,
                             double physics_rate_hz, const Eigen::Vector2d& left_wheel_m,
                             const Eigen::Vector2d& right_wheel_m)
    : encoders_(options, left_radius_m, right_radius_m, std::move(stream)),
      sample_rate_hz_(options.rate_hz),
      wheel_m_{left_wheel_m, right_wheel_m} {
  if (options.rate_hz > physics_rate_hz) {
    // Encoders faster than the physics (the thesis' 200 Hz odometry over
    // 100 Hz physics) read several times a tick, at wheel angles interpolated
    // within it; the rate must then be a whole multiple of the physics rate.
    const double ratio = options.rate_hz / physics_rate_hz;
    if (std::abs(ratio - std::round(ratio)) > 1e-9 * ratio) {
      throw std::invalid_argument(
          robot_id + " encoders: rate " + std::to_string(options.rate_hz) +
          " Hz is neither a divisor nor a whole multiple of the physics rate " +
          std::to_string(physics_rate_hz) + " Hz");
    }
    readings_per_tick_ = static_cast<int>(std::round(ratio));
    sample_rate_hz_ = physics_rate_hz;
  }
}

void EncoderSensor::Sample(const SensorTick& tick, SensorOutputs* out) {
  const RobotState& before = tick.before;
  const RobotState& after = tick.after;
  const double t0 = tick.start_s;
  const double t1 = tick.end_s;
  const int n = readings_per_tick_;
  // The patches under the wheels at the start of the tick.
  const bool patches = !encoders_.options().patches.empty();
  const double left = patches ? PatchScale(before.pose, 0) : 1.0;
  const double right = patches ? PatchScale(before.pose, 1) : 1.0;
  for (int k = 1; k < n; ++k) {
    const double f = static_cast<double>(k) / n;
    out->encoders.push_back(encoders_.Read(
        t0 + f * (t1 - t0),
        before.left_wheel_rad + f * (after.left_wheel_rad - before.left_wheel_rad),
        before.right_wheel_rad + f * (after.right_wheel_rad - before.right_wheel_rad), left,
        right));
  }
  out->encoders.push_back(
      encoders_.Read(t1, after.left_wheel_rad, after.right_wheel_rad, left, right));
}

double EncoderSensor::PatchScale(const core::Pose2& world_from_base, int side) const {
  const Eigen::Vector2d contact = world_from_base * wheel_m_[side];
  for (const FloorPatch& p : encoders_.options().patches) {
    if (core::Contains(p.area_m, contact)) return 1.0 + p.travel_scale_error;
  }
  return 1.0;
}

}  // namespace pavilion::sim
