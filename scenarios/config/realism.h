#pragma once

// The scenario's `realism:` profile (issue 20, docs/realism.md): the error
// sources a real robot meets and an ideal simulator leaves out. `ideal` (the
// default) adds none of them; `realistic` draws them from the scenario's seed
// with the magnitudes below, calibrated against the real CARMEN logs and the
// thesis' Table 4.2. The profile changes the world and the physical robot,
// never the robot's software: the extraction, filter and odometry options the
// robot files give stay as they are.
//
//   realism: realistic                  # or ideal
//   realism: {profile: realistic, wall_offset_sigma_m: 0.03}   # magnitudes overridden
//
// Each draw comes from a stream named after what it draws ("realism/<robot>/
// <laser>/mount", ...), so one magnitude changed leaves every other draw as it was.

#include <cstdint>
#include <string>
#include <vector>

namespace pavilion::scenarios {

struct RealismProfile {
  bool realistic = false;  // `profile: ideal | realistic`

  // The laser (each laser of each robot), thesis §2.2.1. Mount error: the true
  // mount is off the robot file's by these σ (per axis, and in heading); the
  // mirror's zero angle by another (the two add: a planar scanner cannot tell
  // them apart).
  double laser_mount_sigma_m = 0.003;         // m, [0, 0.05]
  double laser_mount_yaw_sigma_rad = 0.0017;  // rad, [0, 0.05] (0.1°)
  double laser_angle_offset_sigma_rad = 0.0017;
  // The true white range noise σ (the robot file's laser profile says what
  // the datasheet and the extraction assume: 1 cm for the LMS 200). The real
  // logs' wall residuals are smaller near the sensor (docs/realism.md). m, [0, 0.1].
  double laser_range_sigma_m = 0.006;
  // Range bias per surface, correlated range noise along the scan, and the
  // intensity-dependent bias and noise (sim::LaserSystematicErrors): the
  // real logs' residuals grow with range where the simulated white noise
  // alone stays flat.
  double laser_surface_bias_sigma_m = 0.004;  // m, [0, 0.5]
  double laser_correlated_sigma_m = 0.004;    // m, [0, 0.5]
  double laser_correlation_readings = 4.0;    // readings, [0.1, 1e4]
  double laser_intensity_bias_m = 0.01;       // m, [0, 0.5]
  double laser_intensity_sigma_m = 0.025;     // m, [0, 0.5]
  // Time (§4.4.3): each scan's stamp jitters with this σ; each laser's stamps
  // lag (or lead) the encoders' by a constant drawn with this σ, the residual
  // of a timestamp calibration (§2.2.1.5).
  double laser_stamp_jitter_s = 0.0005;  // s, [0, 0.1]
  double laser_latency_sigma_s = 0.003;  // s, [0, 0.1]

  // Odometry: the true wheels differ from those the calibration found, within
  // its residuals (UMBmark leaves about a tenth of the uncorrected errors).
  double wheel_radius_ratio_sigma = 0.0005;  // [0, 0.02]
  double wheelbase_factor_sigma = 0.001;     // [0, 0.02]
  double mean_radius_factor_sigma = 0.0005;  // [0, 0.02]
  // Wheel-space noise (§2.3, eq. 2.9: variance k·|Δs| per wheel): what an
  // uneven floor, joints and slip do to the wheels' travel and the encoders
  // do not see. The thesis measured k_L = k_R = 5e-6 m on Pygmalion; the
  // simulated wheels on a flat floor give 3e-8 m. The encoders get it as
  // injected noise, and the robot's calibration as it would measure it (the
  // localizer adds injected k to the calibrated k, as for `encoder_noise`). m, [0, 1e-3].
  double wheel_noise_k_m = 5.0e-6;
  // Slip the encoders do not see (sim::EncoderOptions): in turns (the
  // calibrated k_turn's model; the localizer adds it as it adds k), and with
  // acceleration (no term of the filter models it).
  double turn_slip_k_m = 1.0e-5;    // m, [0, 1e-2]
  double accel_slip_k_s2 = 1.0e-5;  // s², [0, 1e-2]
  // Carpet: this share of the floor, in 4 m squares, where the wheels turn
  // farther per metre (pile compressed under the tyre), each square by a
  // uniform draw in [0.2, 1] x carpet_travel_error.
  double carpet_fraction = 0.25;       // [0, 1]
  double carpet_travel_error = 0.005;  // [0, 0.05]
  // An uneven floor (sim::FloorRelief): slopes and bumps no steeper than
  // this, in the physics (both wheel models) and so in the lasers' tilt; the
  // encoders do not see them. rad, [0, 0.05] (0: flat); key
  // floor_max_slope_deg. The issue's ±0.5°. Its waves' wavelengths span
  // [min, max] m, 0.1 <= min <= max <= 100.
  double floor_max_slope_rad = 0.5 * 3.14159265358979323846 / 180.0;
  double floor_min_wavelength_m = 0.5;
  double floor_max_wavelength_m = 8.0;

  // The map and the world. Each end of each wall of a derived map is
  // surveyed off along the wall's normal by a draw of this σ (the whole wall
  // shifted and turned, beside the tape-measure noise of its corners).
  double wall_offset_sigma_m = 0.02;  // m, [0, 0.1]
  // Unmapped objects against the walls (radiators, cabinets, plants, framed
  // posters), per metre of free wall face; never in the map.
  double clutter_per_m = 0.12;  // 1/m, [0, 2]
  // Chance that a door stands otherwise than the map (and the world file) say.
  double door_flip_probability = 0.2;  // [0, 1]

  // Throws std::invalid_argument naming the field.
  void Validate() const;
};

// "ideal" or "realistic".
const char* ProfileName(const RealismProfile& profile);

}  // namespace pavilion::scenarios
