#include "nav/stack/pose_estimator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pavilion::nav {

const char* LocalizationModeName(LocalizationMode mode) {
  switch (mode) {
    case LocalizationMode::kLocalized:
      return "localized";
    case LocalizationMode::kNotLocalized:
      return "not_localized";
    case LocalizationMode::kLost:
      return "lost";
  }
  return "unknown";
}

void CollisionNoiseOptions::Validate(const char* owner) const {
  const auto require = [&](double value, const char* field) {
    if (!(value >= 0.0) || !std::isfinite(value)) {
      throw std::invalid_argument(std::string(owner) + ".collision." + field +
                                  " must be finite and >= 0");
    }
  };
  require(press_sigma_m, "press_sigma_m");
  require(press_sigma_rad, "press_sigma_rad");
  require(hold_sigma_m, "hold_sigma_m");
  require(hold_sigma_rad, "hold_sigma_rad");
  require(turn_slip_fraction, "turn_slip_fraction");
}

Eigen::Matrix3d CollisionNoiseOptions::Covariance(const BumperContact& contact) const {
  const double press = contact.press ? 1.0 : 0.0;
  const double held_s = std::max(0.0, contact.held_s);
  const double position_m2 =
      press * press_sigma_m * press_sigma_m + held_s * hold_sigma_m * hold_sigma_m;
  // The slip's sigma over the collision so far is turn_slip_fraction times
  // its whole turn; this report adds the growth of its square.
  const double before_rad = turn_slip_fraction * std::max(0.0, contact.turned_before_rad);
  const double after_rad = before_rad + turn_slip_fraction * std::max(0.0, contact.turned_rad);
  const double heading_rad2 = press * press_sigma_rad * press_sigma_rad +
                              held_s * hold_sigma_rad * hold_sigma_rad +
                              (after_rad * after_rad - before_rad * before_rad);
  return Eigen::Vector3d(position_m2, position_m2, heading_rad2).asDiagonal();
}

}  // namespace pavilion::nav
