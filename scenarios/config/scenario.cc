#include "scenarios/config/scenario.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace pavilion::scenarios {
namespace {

// Bounds that catch unit mistakes in a scenario file.
constexpr double kMaxLocalizationRateHz = 1000.0;
constexpr double kMinSignificance = 0.5;
constexpr double kMaxSignificance = 0.999999;
constexpr double kMaxDerivedMapNoiseM = 0.1;  // tape-measure noise, not a different map
constexpr double kMaxLineFloorRM = 0.1;       // a floor, not a different sensor
constexpr double kMaxLineFloorAlphaRad = 5.0 * 3.14159265358979323846 / 180.0;
constexpr double kMaxStartS = 1e7;
constexpr double kMaxControlRateHz = 1000.0;
constexpr double kMaxTrajectoryRateHz = 1e4;
constexpr double kMaxSectionHeightM = 100.0;
constexpr int kMinImageWidthPx = 100;
constexpr int kMaxImageWidthPx = 8000;

void Require(bool ok, const char* options, const char* field, const char* expected) {
  if (!ok) throw std::invalid_argument(std::string(options) + "." + field + " must be " + expected);
}

bool InRange(double v, double lo, double hi) { return v >= lo && v <= hi; }  // false for NaN

}  // namespace

void LocalizationEntry::Validate() const {
  Require(!derive_map_noise_m || InRange(*derive_map_noise_m, 0.0, kMaxDerivedMapNoiseM),
          "LocalizationEntry", "derive_map_noise_m", "in [0, 0.1] m");
  Require(!line_floor_r_m || InRange(*line_floor_r_m, 0.0, kMaxLineFloorRM), "LocalizationEntry",
          "line_floor_r_m", "in [0, 0.1] m");
  Require(!line_floor_alpha_rad || InRange(*line_floor_alpha_rad, 0.0, kMaxLineFloorAlphaRad),
          "LocalizationEntry", "line_floor_alpha_rad", "in [0, 5] deg");
  Require(!hold_s || InRange(*hold_s, 0.0, 1.0), "LocalizationEntry", "hold_s", "in [0, 1000] ms");
  Require(InRange(odometry_k_scale, 1.0, 1000.0), "LocalizationEntry", "odometry_k_scale",
          "in [1, 1000]");
  Require(slip_sigma.allFinite() && (slip_sigma.array() >= 0.0).all() &&
              (slip_sigma.array() <= 0.5).all(),
          "LocalizationEntry", "slip_sigma", "in [0, 0.5] each (m, m, rad)");
  Require(InRange(rate_hz, 0.01, kMaxLocalizationRateHz), "LocalizationEntry", "rate_hz",
          "in [0.01, 1000] Hz");
  Require(initial_sigma.allFinite() && (initial_sigma.array() > 0.0).all(), "LocalizationEntry",
          "initial_sigma", "finite and > 0 (m, m, rad)");
  Require(InRange(significance, kMinSignificance, kMaxSignificance), "LocalizationEntry",
          "significance", "in [0.5, 0.999999]");
}

void RouteEntry::Validate() const {
  Require(InRange(start_s, 0.0, kMaxStartS), "RouteEntry", "start_s", "in [0, 1e7] s");
  Require(InRange(control_rate_hz, 0.1, kMaxControlRateHz), "RouteEntry", "control_rate_hz",
          "in [0.1, 1000] Hz");
}

void OutputOptions::Validate() const {
  Require(InRange(trajectory_rate_hz, 1e-3, kMaxTrajectoryRateHz), "OutputOptions",
          "trajectory_rate_hz", "in [1e-3, 1e4] Hz");
  Require(InRange(body_rate_hz, 1e-3, kMaxTrajectoryRateHz), "OutputOptions", "body_rate_hz",
          "in [1e-3, 1e4] Hz");
  Require(InRange(scan_log_robot_minutes, 0.0, 1e6), "OutputOptions", "scan_log_robot_minutes",
          "in [0, 1e6] robot-min");
  Require(InRange(section_height_m, 0.0, kMaxSectionHeightM), "OutputOptions", "section_height_m",
          "in [0, 100] m");
  Require(image_width_px >= kMinImageWidthPx && image_width_px <= kMaxImageWidthPx, "OutputOptions",
          "image_width_px", "in [100, 8000] px");
}

}  // namespace pavilion::scenarios
