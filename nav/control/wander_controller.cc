#include "nav/control/wander_controller.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace pavilion::nav {
namespace {

constexpr double kMaxSpeedMps = 10.0;
constexpr double kMaxTurnRateRadps = 10.0;
constexpr double kMaxDistanceM = 1000.0;  // beyond any scanner's range: a unit mistake
constexpr int kMaxAvoidScans = 1000000;

void Require(bool ok, const std::string& field, const std::string& what) {
  if (!ok) throw std::invalid_argument("WanderOptions." + field + " must be " + what);
}

}  // namespace

void WanderOptions::Validate() const {
  Require(std::isfinite(cruise_speed_mps) && cruise_speed_mps >= 0.0 &&
              cruise_speed_mps <= kMaxSpeedMps,
          "cruise_speed_mps", "in [0, 10] m/s");
  Require(
      std::isfinite(avoid_speed_mps) && avoid_speed_mps >= 0.0 && avoid_speed_mps <= kMaxSpeedMps,
      "avoid_speed_mps", "in [0, 10] m/s");
  Require(std::isfinite(avoid_turn_rate_radps) && avoid_turn_rate_radps > 0.0 &&
              avoid_turn_rate_radps <= kMaxTurnRateRadps,
          "avoid_turn_rate_radps", "in (0, 10] rad/s");
  Require(std::isfinite(obstruction_distance_m) && obstruction_distance_m > 0.0 &&
              obstruction_distance_m <= kMaxDistanceM,
          "obstruction_distance_m", "in (0, 1000] m");
  Require(std::isfinite(stop_distance_m) && stop_distance_m >= 0.0 &&
              stop_distance_m <= obstruction_distance_m,
          "stop_distance_m", "in [0, obstruction_distance_m] m");
  Require(min_avoid_scans >= 1 && min_avoid_scans <= kMaxAvoidScans, "min_avoid_scans",
          "in [1, 1000000] scans");
  Require(max_avoid_scans >= min_avoid_scans && max_avoid_scans <= kMaxAvoidScans,
          "max_avoid_scans", "in [min_avoid_scans, 1000000] scans");
}

WanderController::WanderController(const WanderOptions& options, core::RandomStream stream)
    : options_(options), stream_(stream) {
  options_.Validate();
}

VelocityCommand WanderController::Update(std::span<const core::LaserReading> readings) {
  const std::size_t n = readings.size();
  if (n == 0) return command_;
  constexpr double kFree = std::numeric_limits<double>::infinity();
  bool obstruction = false;
  bool stop = false;
  double min_left = kFree;
  double min_right = kFree;
  // The index bounds are the peers' integer arithmetic, kept exactly (for 361
  // readings: front 121..240, left 181..360).
  for (std::size_t i = 0; i < n; ++i) {
    const double range = readings[i].valid ? readings[i].range_m : kFree;
    if (i > n / 3 && i < n - n / 3 && range < options_.obstruction_distance_m) obstruction = true;
    if (range < options_.stop_distance_m) stop = true;
    if (i > n / 2) {
      min_left = std::min(min_left, range);
    } else {
      min_right = std::min(min_right, range);
    }
  }
  if (obstruction || stop || avoid_scans_left_ > 0) {
    command_.linear_mps = stop ? 0.0 : options_.avoid_speed_mps;
    if (avoid_scans_left_ < 1) {
      avoid_scans_left_ =
          static_cast<int>(stream_.UniformInt(options_.min_avoid_scans, options_.max_avoid_scans));
      avoid_turn_radps_ =
          min_left < min_right ? -options_.avoid_turn_rate_radps : options_.avoid_turn_rate_radps;
    }
    command_.angular_radps = avoid_turn_radps_;
    --avoid_scans_left_;
  } else {
    avoid_scans_left_ = 0;
    command_.linear_mps = options_.cruise_speed_mps;
    command_.angular_radps = 0.0;
  }
  return command_;
}

}  // namespace pavilion::nav
