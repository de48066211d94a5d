#include "sim/sensors/robot_sensors.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/types/pose2.h"

namespace pavilion::sim {

void EncoderOptions::Validate() const {
  constexpr double kMaxRateHz = 1e5;  // beyond any physics rate: a unit mistake
  constexpr double kMaxK = 1.0;       // §2.3 k_L, k_R (m); the thesis found 5e-6
  if (ticks_per_revolution < 1) {
    throw std::invalid_argument("EncoderOptions.ticks_per_revolution must be >= 1");
  }
  if (!(rate_hz > 0.0 && rate_hz <= kMaxRateHz)) {
    throw std::invalid_argument("EncoderOptions.rate_hz must be in (0, 1e5] Hz");
  }
  if (!(k_left_m >= 0.0 && k_left_m <= kMaxK)) {
    throw std::invalid_argument("EncoderOptions.k_left_m must be in [0, 1] m");
  }
  if (!(k_right_m >= 0.0 && k_right_m <= kMaxK)) {
    throw std::invalid_argument("EncoderOptions.k_right_m must be in [0, 1] m");
  }
  if (!(k_turn_m >= 0.0 && k_turn_m <= kMaxK)) {
    throw std::invalid_argument("EncoderOptions.k_turn_m must be in [0, 1] m");
  }
  if (!(k_accel_s2 >= 0.0 && k_accel_s2 <= 1.0)) {
    throw std::invalid_argument("EncoderOptions.k_accel_s2 must be in [0, 1] s^2");
  }
  for (const FloorPatch& p : patches) {
    if (!(std::abs(p.travel_scale_error) < 0.1) || p.area_m.size() < 3) {
      throw std::invalid_argument("EncoderOptions.patches: '" + p.id +
                                  "' needs an area of >= 3 points and |travel_scale_error| < 0.1");
    }
  }
}

void SystematicErrors::Validate() const {
  // Systematic errors of real robots are of the order of 1 % (UMBmark); 10 %
  // is a badly built robot, beyond it a unit or ratio mistake.
  if (!(wheel_radius_ratio >= 0.9 && wheel_radius_ratio <= 1.1)) {
    throw std::invalid_argument("SystematicErrors.wheel_radius_ratio must be in [0.9, 1.1]");
  }
  if (!(wheelbase_factor >= 0.9 && wheelbase_factor <= 1.1)) {
    throw std::invalid_argument("SystematicErrors.wheelbase_factor must be in [0.9, 1.1]");
  }
  if (!(mean_radius_factor >= 0.9 && mean_radius_factor <= 1.1)) {
    throw std::invalid_argument("SystematicErrors.mean_radius_factor must be in [0.9, 1.1]");
  }
}

WheelEncoders::WheelEncoders(EncoderOptions options, double left_radius_m, double right_radius_m,
                             core::RandomStream stream)
    : options_(options), radius_m_{left_radius_m, right_radius_m}, stream_(stream) {
  options_.Validate();
  if (!(left_radius_m > 0.0 && right_radius_m > 0.0)) {
    throw std::invalid_argument("encoder wheel radii must be > 0");
  }
}

core::EncoderReading WheelEncoders::Read(double stamp_s, double left_wheel_rad,
                                         double right_wheel_rad, double left_scale,
                                         double right_scale) {
  const double true_rad[2] = {left_wheel_rad, right_wheel_rad};
  const double k_m[2] = {options_.k_left_m, options_.k_right_m};
  const double scale[2] = {left_scale, right_scale};
  if (!started_) {
    // Counters start at zero wherever the wheels are.
    for (int side = 0; side < 2; ++side) last_true_rad_[side] = true_rad[side];
    last_stamp_s_ = stamp_s;
    started_ = true;
  }
  core::EncoderReading reading;
  reading.stamp_s = stamp_s;
  reading.ticks_per_revolution = options_.ticks_per_revolution;
  double delta[2];
  double travel_m[2];
  for (int side = 0; side < 2; ++side) {
    delta[side] = true_rad[side] - last_true_rad_[side];
    last_true_rad_[side] = true_rad[side];
    travel_m[side] = delta[side] * radius_m_[side];
    if (scale[side] != 1.0) delta[side] *= scale[side];  // a floor patch
    if (options_.noise && k_m[side] > 0.0) {
      // Cov(u) = diag(k_R|s_r|, k_L|s_l|), eq. 2.9: σ² grows with the travel.
      delta[side] +=
          stream_.Normal(0.0, std::sqrt(k_m[side] * std::abs(travel_m[side]))) / radius_m_[side];
    }
  }
  AddSlip(stamp_s, travel_m, delta);
  std::int64_t ticks[2];
  for (int side = 0; side < 2; ++side) {
    measured_rad_[side] += delta[side];
    ticks[side] = static_cast<std::int64_t>(
        std::floor(measured_rad_[side] / (2.0 * std::numbers::pi) * options_.ticks_per_revolution));
  }
  reading.left_ticks = ticks[0];
  reading.right_ticks = ticks[1];
  return reading;
}

void WheelEncoders::AddSlip(double stamp_s, const double travel_m[2], double delta[2]) {
  const double dt = stamp_s - last_stamp_s_;
  last_stamp_s_ = stamp_s;
  if (!options_.noise || !(dt > 0.0)) return;
  if (options_.k_accel_s2 > 0.0) {
    for (int side = 0; side < 2; ++side) {
      const double speed = travel_m[side] / dt;
      const double accel = std::abs(speed - last_speed_mps_[side]) / dt;
      last_speed_mps_[side] = speed;
      const double variance = options_.k_accel_s2 * accel * std::abs(travel_m[side]);
      delta[side] += stream_.Normal(0.0, std::sqrt(variance)) / radius_m_[side];
    }
  }
  if (options_.k_turn_m > 0.0) {
    const double d =
        stream_.Normal(0.0, std::sqrt(options_.k_turn_m * std::abs(travel_m[1] - travel_m[0])));
    delta[0] -= 0.5 * d / radius_m_[0];
    delta[1] += 0.5 * d / radius_m_[1];
  }
}

std::uint32_t PressedBumperZones(const std::vector<BumperZone>& zones,
                                 const std::vector<Eigen::Vector2d>& contact_points_m) {
  std::uint32_t pressed = 0;
  for (const Eigen::Vector2d& p : contact_points_m) {
    const double bearing = std::atan2(p.y(), p.x());
    for (std::size_t i = 0; i < zones.size() && i < 32; ++i) {
      // Zones run counter-clockwise from `from` to `to` and may cross ±π.
      const double span = core::NormalizeAngle(zones[i].to_rad - zones[i].from_rad);
      const double width = span <= 0.0 ? span + 2 * std::numbers::pi : span;
      double offset = core::NormalizeAngle(bearing - zones[i].from_rad);
      if (offset < 0.0) offset += 2 * std::numbers::pi;
      if (offset <= width) pressed |= 1u << i;
    }
  }
  return pressed;
}

}  // namespace pavilion::sim
