#include "nav/mission/blocked_monitor.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pavilion::nav {
namespace {

void Require(bool ok, const std::string& field, const std::string& range) {
  if (!ok) throw std::invalid_argument("BlockedMonitorOptions." + field + " must be " + range);
}

// The net turn on the spot is judged over at least this long (s): ten
// 10 Hz cycles, so that one cycle's turn of a dither does not count.
constexpr double kTurnWindowS = 1.0;

}  // namespace

void BlockedMonitorOptions::Validate() const {
  Require(speed_mps > 0.0 && speed_mps <= 1.0, "speed_mps", "in (0, 1] m/s");
  Require(blocked_after_s > 0.0 && blocked_after_s <= 600.0, "blocked_after_s", "in (0, 600] s");
  Require(replan_after_s > 0.0 && replan_after_s <= 600.0, "replan_after_s", "in (0, 600] s");
  Require(abort_after_s > 0.0 && abort_after_s <= 3600.0, "abort_after_s", "in (0, 3600] s");
  Require(turn_rate_radps > 0.0 && turn_rate_radps <= 10.0, "turn_rate_radps", "in (0, 10] rad/s");
}

BlockedMonitor::BlockedMonitor(const BlockedMonitorOptions& options) : options_(options) {
  options_.Validate();
}

void BlockedMonitor::Reset() {
  if (blocked_) {
    const double d = last_s_ - slow_since_s_;
    closed_blocked_s_ += d;
    longest_s_ = std::max(longest_s_, d);
  }
  slow_ = false;
  blocked_ = false;
  abort_reported_ = false;
}

BlockedMonitor::Step BlockedMonitor::Update(double now_s, double speed_mps, double turn_rate_radps,
                                            bool has_goal) {
  Step step;
  const double dt_s = std::max(0.0, now_s - last_s_);
  bool moving = std::abs(speed_mps) >= options_.speed_mps;
  if (slow_ && !moving) {
    // On the spot: moving while the net turn keeps up with the rate.
    net_turn_rad_ += turn_rate_radps * dt_s;
    const double elapsed_s = now_s - slow_since_s_;
    moving = elapsed_s >= kTurnWindowS &&
             std::abs(net_turn_rad_) >= options_.turn_rate_radps * elapsed_s;
  }
  if (!has_goal || moving) {
    Reset();  // the episode ended at the last slow sample
    last_s_ = now_s;
    return step;
  }
  last_s_ = now_s;
  if (!slow_) {
    slow_ = true;
    slow_since_s_ = now_s;
    net_turn_rad_ = 0.0;
  }
  const double slow_s = now_s - slow_since_s_;
  if (!blocked_ && slow_s > options_.blocked_after_s) {
    blocked_ = true;
    ++episodes_;
    step.became_blocked = true;
    next_replan_s_ = slow_since_s_ + options_.replan_after_s;
  }
  if (blocked_ && now_s >= next_replan_s_) {
    step.replan = true;
    next_replan_s_ += options_.replan_after_s;
  }
  if (blocked_ && !abort_reported_ && slow_s >= options_.abort_after_s) {
    step.abort = true;
    abort_reported_ = true;
  }
  return step;
}

double BlockedMonitor::time_blocked_s() const {
  return closed_blocked_s_ + (blocked_ ? last_s_ - slow_since_s_ : 0.0);
}

double BlockedMonitor::longest_blocked_s() const {
  return std::max(longest_s_, blocked_ ? last_s_ - slow_since_s_ : 0.0);
}

}  // namespace pavilion::nav
