#include "nav/fleet/deadlock_monitor.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace pavilion::nav {
namespace {

void Require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("DeadlockOptions.") + what);
}

}  // namespace

void DeadlockOptions::Validate() const {
  Require(std::isfinite(detect_s) && detect_s > 0.0 && detect_s <= 600.0,
          "detect_s must be in (0, 600] s");
  Require(std::isfinite(backoff_max_s) && backoff_max_s >= 0.0 && backoff_max_s <= 60.0,
          "backoff_max_s must be in [0, 60] s");
  Require(std::isfinite(resolved_move_m) && resolved_move_m > 0.0 && resolved_move_m <= 10.0,
          "resolved_move_m must be in (0, 10] m");
  Require(std::isfinite(retreat_after_s) && retreat_after_s >= 0.0 && retreat_after_s <= 60.0,
          "retreat_after_s must be in [0, 60] s");
  Require(std::isfinite(give_up_s) && give_up_s > backoff_max_s + retreat_after_s &&
              give_up_s <= 3600.0,
          "give_up_s must be in (backoff_max_s + retreat_after_s, 3600] s");
}

DeadlockMonitor::DeadlockMonitor(const DeadlockOptions& options, std::uint64_t seed)
    : options_(options), random_(seed, core::RandomStream::StreamId("deadlock_monitor")) {
  options_.Validate();
}

DeadlockMonitor::Step DeadlockMonitor::Update(double now_s, bool has_goal, bool overlap,
                                              bool stalled, double odometer_m) {
  if (!std::isfinite(now_s) || !std::isfinite(odometer_m)) {
    throw std::invalid_argument("DeadlockMonitor::Update: now_s and odometer_m must be finite");
  }
  if (!has_goal) {  // dwelling or idle: nothing to resolve, an open episode is dropped
    state_ = State::kClear;
    return {};
  }
  const bool suspect = overlap && stalled;
  switch (state_) {
    case State::kClear:
      if (suspect) {
        state_ = State::kSuspect;
        suspect_since_s_ = now_s;
      }
      break;
    case State::kSuspect:
      if (!suspect) {
        state_ = State::kClear;
      } else if (now_s - suspect_since_s_ >= options_.detect_s) {
        return Detect(now_s, odometer_m);
      }
      break;
    case State::kDetected:
      return Follow(now_s, overlap, stalled, odometer_m);
  }
  return {};
}

DeadlockMonitor::Step DeadlockMonitor::Detect(double now_s, double odometer_m) {
  state_ = State::kDetected;
  detected_at_s_ = now_s;
  detected_odometer_m_ = odometer_m;
  free_since_s_ = -1.0;
  ++detected_;
  if (options_.resolve) backoff_s_ = random_.Uniform(0.0, options_.backoff_max_s);
  Step step;
  step.detected = true;
  step.clip = options_.resolve && backoff_s_ == 0.0;
  return step;
}

DeadlockMonitor::Step DeadlockMonitor::Follow(double now_s, bool overlap, bool stalled,
                                              double odometer_m) {
  const double elapsed_s = now_s - detected_at_s_;
  if (overlap || stalled) {
    free_since_s_ = -1.0;
  } else if (free_since_s_ < 0.0) {
    free_since_s_ = now_s;
  }
  const bool moved = odometer_m - detected_odometer_m_ >= options_.resolved_move_m;
  const bool free = free_since_s_ >= 0.0 && now_s - free_since_s_ >= kDeadlockClearS;
  Step step;
  if (moved || free) {
    state_ = State::kClear;
    if (options_.resolve) {
      ++resolved_;
      longest_resolution_s_ = std::max(longest_resolution_s_, elapsed_s);
      step.resolved = true;
      step.resolution_s = elapsed_s;
    }
    return step;
  }
  if (elapsed_s >= options_.give_up_s) {
    ++unresolved_;
    state_ = State::kClear;
    return step;
  }
  step.clip = options_.resolve && elapsed_s >= backoff_s_;
  step.retreat = options_.resolve && elapsed_s >= backoff_s_ + options_.retreat_after_s;
  return step;
}

Eigen::Vector2d YieldDirection(const Eigen::Vector2d& other, double inradius_m, double leg_m,
                               const std::vector<Eigen::Vector2d>& points) {
  constexpr int kDirections = 16;
  constexpr double kRoomCapM = 0.3;     // about a Robox's half-width
  constexpr double kAwayWeightM = 0.1;  // room a direction away from the other is worth
  const Eigen::Vector2d away = -other.normalized();
  Eigen::Vector2d best = Eigen::Vector2d::UnitX();
  double best_score = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < kDirections; ++k) {
    const double a = 2.0 * std::numbers::pi * k / kDirections;
    const Eigen::Vector2d u(std::cos(a), std::sin(a));
    const Eigen::Vector2d from = u * inradius_m;
    double room_m = kRoomCapM;
    for (const Eigen::Vector2d& p : points) {
      const double t = std::clamp((p - from).dot(u), 0.0, leg_m);
      room_m = std::min(room_m, (p - from - t * u).norm());
    }
    const double score = room_m + kAwayWeightM * u.dot(away);
    if (score > best_score) {
      best_score = score;
      best = u;
    }
  }
  return best;
}

}  // namespace pavilion::nav
