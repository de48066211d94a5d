#include "scenarios/config/realism.h"

#include <stdexcept>

namespace pavilion::scenarios {
namespace {

void Require(bool ok, const char* field, const char* expected) {
  if (!ok) {
    throw std::invalid_argument(std::string("RealismProfile.") + field + " must be " + expected);
  }
}

}  // namespace

void RealismProfile::Validate() const {
  constexpr double kMaxMountM = 0.05;
  constexpr double kMaxAngleRad = 0.05;
  constexpr double kMaxRangeM = 0.5;
  constexpr double kMaxTimeS = 0.1;
  constexpr double kMaxFactorSigma = 0.02;
  constexpr double kMaxWallOffsetM = 0.1;
  constexpr double kMaxClutterPerM = 2.0;
  const auto in = [](double v, double lo, double hi) { return v >= lo && v <= hi; };
  Require(in(laser_mount_sigma_m, 0.0, kMaxMountM), "laser_mount_sigma_m", "in [0, 0.05] m");
  Require(in(laser_mount_yaw_sigma_rad, 0.0, kMaxAngleRad), "laser_mount_yaw_sigma_rad",
          "in [0, 0.05] rad");
  Require(in(laser_angle_offset_sigma_rad, 0.0, kMaxAngleRad), "laser_angle_offset_sigma_rad",
          "in [0, 0.05] rad");
  Require(in(laser_range_sigma_m, 0.0, 0.1), "laser_range_sigma_m", "in [0, 0.1] m");
  Require(in(laser_surface_bias_sigma_m, 0.0, kMaxRangeM), "laser_surface_bias_sigma_m",
          "in [0, 0.5] m");
  Require(in(laser_correlated_sigma_m, 0.0, kMaxRangeM), "laser_correlated_sigma_m",
          "in [0, 0.5] m");
  Require(in(laser_correlation_readings, 0.1, 1e4), "laser_correlation_readings", "in [0.1, 1e4]");
  Require(in(laser_intensity_bias_m, 0.0, kMaxRangeM), "laser_intensity_bias_m", "in [0, 0.5] m");
  Require(in(laser_intensity_sigma_m, 0.0, kMaxRangeM), "laser_intensity_sigma_m", "in [0, 0.5] m");
  Require(in(laser_stamp_jitter_s, 0.0, kMaxTimeS), "laser_stamp_jitter_s", "in [0, 0.1] s");
  Require(in(laser_latency_sigma_s, 0.0, kMaxTimeS), "laser_latency_sigma_s", "in [0, 0.1] s");
  Require(in(wheel_radius_ratio_sigma, 0.0, kMaxFactorSigma), "wheel_radius_ratio_sigma",
          "in [0, 0.02]");
  Require(in(wheelbase_factor_sigma, 0.0, kMaxFactorSigma), "wheelbase_factor_sigma",
          "in [0, 0.02]");
  Require(in(mean_radius_factor_sigma, 0.0, kMaxFactorSigma), "mean_radius_factor_sigma",
          "in [0, 0.02]");
  Require(in(wheel_noise_k_m, 0.0, 1e-3), "wheel_noise_k_m", "in [0, 1e-3] m");
  Require(in(turn_slip_k_m, 0.0, 1e-2), "turn_slip_k_m", "in [0, 1e-2] m");
  Require(in(accel_slip_k_s2, 0.0, 1e-2), "accel_slip_k_s2", "in [0, 1e-2] s^2");
  Require(in(carpet_fraction, 0.0, 1.0), "carpet_fraction", "in [0, 1]");
  Require(in(carpet_travel_error, 0.0, 0.05), "carpet_travel_error", "in [0, 0.05]");
  Require(in(floor_max_slope_rad, 0.0, 0.05), "floor_max_slope_rad", "in [0, 0.05] rad");
  Require(in(floor_min_wavelength_m, 0.1, 100.0) && in(floor_max_wavelength_m, 0.1, 100.0) &&
              floor_min_wavelength_m <= floor_max_wavelength_m,
          "floor_min_wavelength_m", "at most floor_max_wavelength_m, both in [0.1, 100] m");
  Require(in(wall_offset_sigma_m, 0.0, kMaxWallOffsetM), "wall_offset_sigma_m", "in [0, 0.1] m");
  Require(in(clutter_per_m, 0.0, kMaxClutterPerM), "clutter_per_m", "in [0, 2] per m");
  Require(in(door_flip_probability, 0.0, 1.0), "door_flip_probability", "in [0, 1]");
}

const char* ProfileName(const RealismProfile& profile) {
  return profile.realistic ? "realistic" : "ideal";
}

}  // namespace pavilion::scenarios
