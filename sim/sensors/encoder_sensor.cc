#include "sim/sensors/encoder_sensor.h"

#include <cmath>
#include <stdexcept>
#include <utility>

namespace pavilion::sim {

EncoderSensor::EncoderSensor(const std::string& robot_id, const EncoderOptions& options,
                             double left_radius_m, double right_radius_m, core::RandomStream stream,
                             double physics_rate_hz)
    : encoders_(options, left_radius_m, right_radius_m, std::move(stream)),
      sample_rate_hz_(options.rate_hz) {
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
  for (int k = 1; k < n; ++k) {
    const double f = static_cast<double>(k) / n;
    out->encoders.push_back(encoders_.Read(
        t0 + f * (t1 - t0),
        before.left_wheel_rad + f * (after.left_wheel_rad - before.left_wheel_rad),
        before.right_wheel_rad + f * (after.right_wheel_rad - before.right_wheel_rad)));
  }
  out->encoders.push_back(encoders_.Read(t1, after.left_wheel_rad, after.right_wheel_rad));
}

}  // namespace pavilion::sim
