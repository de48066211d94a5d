#include "nav/control/path_follower.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace pavilion::nav {
namespace {

void Require(bool ok, const char* field, const char* expected) {
  if (!ok) {
    throw std::invalid_argument(std::string("PathFollowerOptions.") + field + ": expected " +
                                expected);
  }
}

bool Positive(double v) { return std::isfinite(v) && v > 0.0; }
bool InRange(double v, double lo, double hi) { return v >= lo && v <= hi; }  // false for NaN

// Moves `value` towards `target` by at most `step`.
double Approach(double value, double target, double step) {
  return value + std::clamp(target - value, -step, step);
}

}  // namespace

void PathFollowerOptions::Validate() const {
  Require(InRange(max_speed_mps, 0.01, 5.0), "max_speed_mps", "a value in [0.01, 5] m/s");
  Require(InRange(max_accel_mps2, 0.01, 10.0), "max_accel_mps2", "a value in [0.01, 10] m/s^2");
  Require(InRange(max_turn_rate_radps, 0.01, 10.0), "max_turn_rate_radps",
          "a value in [0.01, 10] rad/s");
  Require(InRange(max_turn_accel_radps2, 0.01, 100.0), "max_turn_accel_radps2",
          "a value in [0.01, 100] rad/s^2");
  Require(InRange(lookahead_m, 0.05, 10.0), "lookahead_m", "a value in [0.05, 10] m");
  Require(InRange(max_lateral_accel_mps2, 0.01, 10.0), "max_lateral_accel_mps2",
          "a value in [0.01, 10] m/s^2");
  Require(Positive(turn_in_place_rad) && turn_in_place_rad <= std::numbers::pi, "turn_in_place_rad",
          "a value in (0, pi]");
  Require(Positive(heading_gain), "heading_gain", "a finite value > 0");
  Require(InRange(goal_tolerance_m, 0.001, 5.0), "goal_tolerance_m", "a value in [0.001, 5] m");
}

PathFollower::PathFollower(std::vector<Eigen::Vector2d> path, const PathFollowerOptions& options)
    : path_(std::move(path)), options_(options) {
  options_.Validate();
  if (path_.empty()) throw std::invalid_argument("PathFollower: empty path");
  cumulative_.push_back(0.0);
  for (std::size_t k = 1; k < path_.size(); ++k) {
    cumulative_.push_back(cumulative_.back() + (path_[k] - path_[k - 1]).norm());
  }
}

Eigen::Vector2d PathFollower::PointAt(double s_m) const {
  if (s_m <= 0.0) return path_.front();
  if (s_m >= cumulative_.back()) return path_.back();
  const auto it = std::upper_bound(cumulative_.begin(), cumulative_.end(), s_m);
  const std::size_t k = static_cast<std::size_t>(it - cumulative_.begin());  // s in [k-1, k)
  const double segment = cumulative_[k] - cumulative_[k - 1];
  const double t = segment > 0.0 ? (s_m - cumulative_[k - 1]) / segment : 0.0;
  return path_[k - 1] + t * (path_[k] - path_[k - 1]);
}

double PathFollower::Project(const Eigen::Vector2d& p) const {
  // Only forward of the current progress and within a few look-aheads, so that
  // a path passing close to itself (a tour returning along a corridor) is
  // followed in order.
  const double window = progress_m_ + 4.0 * options_.lookahead_m;
  double best_s = progress_m_;
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t k = 1; k < path_.size(); ++k) {
    if (cumulative_[k] < progress_m_) continue;
    if (cumulative_[k - 1] > window) break;
    const Eigen::Vector2d a = path_[k - 1];
    const Eigen::Vector2d ab = path_[k] - a;
    const double len2 = ab.squaredNorm();
    double t = len2 > 0.0 ? (p - a).dot(ab) / len2 : 0.0;
    const double lo = len2 > 0.0 ? (progress_m_ - cumulative_[k - 1]) / std::sqrt(len2) : 0.0;
    t = std::clamp(t, std::max(0.0, lo), 1.0);
    const double d = (a + t * ab - p).norm();
    if (d < best_d) {
      best_d = d;
      best_s = cumulative_[k - 1] + t * std::sqrt(len2);
    }
  }
  return std::min(best_s, window);
}

VelocityCommand PathFollower::Update(const core::Pose2& pose, double dt_s) {
  const Eigen::Vector2d position = pose.translation();
  progress_m_ = std::max(progress_m_, Project(position));
  const double remaining =
      std::max(cumulative_.back() - progress_m_, (path_.back() - position).norm());
  const double dv = options_.max_accel_mps2 * dt_s;
  const double dw = options_.max_turn_accel_radps2 * dt_s;
  if (done_) return last_;
  if (cumulative_.back() - progress_m_ < options_.lookahead_m &&
      (path_.back() - position).norm() < options_.goal_tolerance_m) {
    // At the goal: brake within the acceleration limits, then done.
    last_.linear_mps = Approach(last_.linear_mps, 0.0, dv);
    last_.angular_radps = Approach(last_.angular_radps, 0.0, dw);
    done_ = last_.linear_mps == 0.0 && last_.angular_radps == 0.0;
    return last_;
  }
  const Eigen::Vector2d target = PointAt(progress_m_ + options_.lookahead_m);
  const Eigen::Vector2d to_target = target - position;
  const double distance = std::max(to_target.norm(), 1e-9);
  const double error =
      core::NormalizeAngle(std::atan2(to_target.y(), to_target.x()) - pose.theta_rad);
  VelocityCommand wanted;
  if (std::abs(error) > options_.turn_in_place_rad) {
    // Stop, then turn towards the look-ahead point.
    wanted.linear_mps = 0.0;
    wanted.angular_radps = std::clamp(options_.heading_gain * error, -options_.max_turn_rate_radps,
                                      options_.max_turn_rate_radps);
  } else {
    // Pure pursuit: the arc through the look-ahead point, kappa = 2 sin(e) / d.
    const double kappa = 2.0 * std::sin(error) / distance;
    double v = options_.max_speed_mps;
    if (std::abs(kappa) > 1e-9) {
      v = std::min(v, std::sqrt(options_.max_lateral_accel_mps2 / std::abs(kappa)));
      v = std::min(v, options_.max_turn_rate_radps / std::abs(kappa));
    }
    // Brake to stop at the goal: v <= sqrt(2 a d).
    v = std::min(v, std::sqrt(2.0 * options_.max_accel_mps2 * std::max(0.0, remaining)));
    wanted.linear_mps = v;
    wanted.angular_radps = v * kappa;
  }
  last_.linear_mps = Approach(last_.linear_mps, wanted.linear_mps, dv);
  last_.angular_radps = Approach(last_.angular_radps, wanted.angular_radps, dw);
  // Keep on the arc while the speed ramps: the turn rate follows the speed.
  if (wanted.linear_mps > 0.0 && std::abs(wanted.linear_mps) > 1e-9) {
    const double kappa = wanted.angular_radps / wanted.linear_mps;
    last_.angular_radps = std::clamp(last_.linear_mps * kappa, -options_.max_turn_rate_radps,
                                     options_.max_turn_rate_radps);
  }
  return last_;
}

WheelSpeeds ToWheelSpeeds(const VelocityCommand& command, double left_wheel_radius_m,
                          double right_wheel_radius_m, double wheelbase_m) {
  const double half = 0.5 * wheelbase_m;
  return {(command.linear_mps - half * command.angular_radps) / left_wheel_radius_m,
          (command.linear_mps + half * command.angular_radps) / right_wheel_radius_m};
}

}  // namespace pavilion::nav
