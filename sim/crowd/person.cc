#include "sim/crowd/person.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/types/pose2.h"

namespace pavilion::sim::crowd {
namespace {

// Reference speed of PersonBodyOptions::step_length_m, m/s (Weidmann 1993).
constexpr double kReferenceSpeedMps = 1.34;
// The swing amplitude follows its target with this time constant (s): legs
// come to rest within a step or two when a person stops (chosen).
constexpr double kSwingTimeConstantS = 0.3;

void Require(bool ok, const char* field, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("person.") + field + " " + what);
}

}  // namespace

void PersonBodyOptions::Validate() const {
  const auto in = [](double v, double lo, double hi) {
    return std::isfinite(v) && v > lo && v <= hi;
  };
  Require(in(min_shoulder_radius_m, 0, 0.4), "min_shoulder_radius_m", "must be in (0, 0.4]");
  Require(in(max_shoulder_radius_m, 0, 0.4) && max_shoulder_radius_m >= min_shoulder_radius_m,
          "max_shoulder_radius_m", "must be in [min_shoulder_radius_m, 0.4]");
  Require(in(min_leg_diameter_m, 0, 0.3), "min_leg_diameter_m", "must be in (0, 0.3]");
  Require(in(max_leg_diameter_m, 0, 0.3) && max_leg_diameter_m >= min_leg_diameter_m,
          "max_leg_diameter_m", "must be in [min_leg_diameter_m, 0.3]");
  Require(in(hip_height_m, 0.2, 1.5), "hip_height_m", "must be in (0.2, 1.5]");
  Require(in(height_m, hip_height_m, 2.5), "height_m", "must be in (hip_height_m, 2.5]");
  Require(std::isfinite(hip_half_width_m) && hip_half_width_m >= 0 && hip_half_width_m <= 0.2,
          "hip_half_width_m", "must be in [0, 0.2]");
  Require(in(mass_kg, 0, 300), "mass_kg", "must be in (0, 300]");
  Require(in(step_length_m, 0, 1.5), "step_length_m", "must be in (0, 1.5]");
}

PersonShape PersonShape::Draw(const PersonBodyOptions& options, core::RandomStream* random) {
  PersonShape s;
  s.radius_m = random->Uniform(options.min_shoulder_radius_m,
                               std::nextafter(options.max_shoulder_radius_m, 1.0));
  s.leg_radius_m = 0.5 * random->Uniform(options.min_leg_diameter_m,
                                         std::nextafter(options.max_leg_diameter_m, 1.0));
  s.hip_height_m = options.hip_height_m;
  s.height_m = options.height_m;
  s.hip_half_width_m = options.hip_half_width_m;
  s.mass_kg = options.mass_kg;
  return s;
}

void Gait::Advance(double speed_mps, double dt, const PersonBodyOptions& options) {
  const double v = std::max(0.0, speed_mps);
  const double step_m = options.step_length_m * std::sqrt(v / kReferenceSpeedMps);
  // Half a turn of phase per step.
  if (step_m > 1e-3)
    phase_rad = core::NormalizeAngle(phase_rad + std::numbers::pi * v * dt / step_m);
  swing_m += (0.5 * step_m - swing_m) * (1.0 - std::exp(-dt / kSwingTimeConstantS));
}

std::array<Eigen::Vector2d, 2> PersonState::LegCentres(double z_m) const {
  const Eigen::Vector2d forward(std::cos(heading_rad), std::sin(heading_rad));
  const Eigen::Vector2d left(-forward.y(), forward.x());
  const double scale = std::clamp((shape.hip_height_m - z_m) / shape.hip_height_m, 0.0, 1.0);
  const double fore = gait.swing_m * std::sin(gait.phase_rad) * scale;
  return {position_m + shape.hip_half_width_m * left + fore * forward,
          position_m - shape.hip_half_width_m * left - fore * forward};
}

}  // namespace pavilion::sim::crowd
