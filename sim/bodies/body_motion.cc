#include "sim/bodies/body_motion.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

namespace pavilion::sim {
namespace {

// Bounds that catch unit mistakes in scripted and random-walk motion.
constexpr double kMaxSegmentS = 1e7;
constexpr double kMaxYawRateRadps = 100.0;
constexpr double kMaxWalkSpeedMps = 5.0;
constexpr double kMinMeanLegS = 1e-3;  // about a physics step
constexpr double kMaxMeanLegS = 1e4;

void Require(bool ok, const char* options, const char* field, const char* expected) {
  if (!ok) throw std::invalid_argument(std::string(options) + "." + field + " must be " + expected);
}

}  // namespace

void VelocitySegment::Validate() const {
  Require(duration_s > 0.0 && duration_s <= kMaxSegmentS, "VelocitySegment", "duration_s",
          "in (0, 1e7] s");
  Require(velocity_mps.allFinite(), "VelocitySegment", "velocity_mps", "finite");
  Require(yaw_rate_radps >= -kMaxYawRateRadps && yaw_rate_radps <= kMaxYawRateRadps,
          "VelocitySegment", "yaw_rate_radps", "in [-100, 100] rad/s");
}

void RandomWalkOptions::Validate() const {
  Require(speed_mps >= 0.0 && speed_mps <= kMaxWalkSpeedMps, "RandomWalkOptions", "speed_mps",
          "in [0, 5] m/s");
  Require(mean_leg_s >= kMinMeanLegS && mean_leg_s <= kMaxMeanLegS, "RandomWalkOptions",
          "mean_leg_s", "in [1e-3, 1e4] s");
  Require(blocked_ratio >= 0.0 && blocked_ratio <= 1.0, "RandomWalkOptions", "blocked_ratio",
          "in [0, 1]");
  Require(blocked_s >= 0.0 && std::isfinite(blocked_s), "RandomWalkOptions", "blocked_s",
          "finite and >= 0 s");
}

ScriptedMotion::ScriptedMotion(ScriptedMotionOptions options) : options_(std::move(options)) {
  for (const auto& s : options_.segments) total_s_ += s.duration_s;
}

PlanarVelocity ScriptedMotion::Update(double time_s, const BodyState& state) {
  double t = time_s;
  if (options_.loop && total_s_ > 0.0) t = std::fmod(t, total_s_);
  for (const auto& s : options_.segments) {
    if (t < s.duration_s) {
      PlanarVelocity v;
      v.yaw_rate_radps = s.yaw_rate_radps;
      if (options_.body_frame) {
        const double c = std::cos(state.pose.theta_rad);
        const double sn = std::sin(state.pose.theta_rad);
        v.linear_mps = {c * s.velocity_mps.x() - sn * s.velocity_mps.y(),
                        sn * s.velocity_mps.x() + c * s.velocity_mps.y()};
      } else {
        v.linear_mps = s.velocity_mps;
      }
      return v;
    }
    t -= s.duration_s;
  }
  return {};
}

RandomWalkMotion::RandomWalkMotion(RandomWalkOptions options, core::RandomStream stream)
    : options_(options), stream_(std::move(stream)) {}

void RandomWalkMotion::NewLeg(double time_s) {
  heading_rad_ = stream_.Uniform(-std::numbers::pi, std::numbers::pi);
  // Exponential leg duration by inversion; 1 - U lies in (0, 1].
  leg_end_s_ = time_s - options_.mean_leg_s * std::log(1.0 - stream_.Uniform());
  blocked_since_s_ = -1.0;
}

PlanarVelocity RandomWalkMotion::Update(double time_s, const BodyState& state) {
  if (time_s >= leg_end_s_) NewLeg(time_s);
  if (options_.roam_area && !core::Contains(*options_.roam_area, state.pose.translation())) {
    Eigen::Vector2d centroid(0, 0);
    for (const auto& p : *options_.roam_area) centroid += p;
    centroid /= static_cast<double>(options_.roam_area->size());
    const Eigen::Vector2d home = centroid - state.pose.translation();
    heading_rad_ = std::atan2(home.y(), home.x());
  }
  const bool slow = state.velocity_mps.norm() < options_.blocked_ratio * options_.speed_mps;
  // The first step of a leg starts from rest, so "slow" counts only after it.
  if (slow && time_s > 0.0) {
    if (blocked_since_s_ < 0.0) blocked_since_s_ = time_s;
    if (time_s - blocked_since_s_ >= options_.blocked_s) NewLeg(time_s);
  } else {
    blocked_since_s_ = -1.0;
  }
  PlanarVelocity v;
  v.linear_mps =
      options_.speed_mps * Eigen::Vector2d(std::cos(heading_rad_), std::sin(heading_rad_));
  return v;
}

}  // namespace pavilion::sim
