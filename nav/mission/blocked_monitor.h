#pragma once

// Progress of a robot that has a goal (issue 14): it is blocked when slower
// than 2 cm/s for more than 5 s; blocked for 10 s triggers a replan (and
// again every 10 s), and a mission blocked for too long is aborted.

#include <cstdint>

namespace pavilion::nav {

struct BlockedMonitorOptions {
  double speed_mps = 0.02;       // slower than this counts as not moving (issue 14), (0, 1]
  double blocked_after_s = 5.0;  // not moving this long: blocked (issue 14), (0, 600]
  double replan_after_s = 10.0;  // blocked this long: replan, and again each period, (0, 600]
  double abort_after_s = 45.0;   // blocked this long: abort the mission, (0, 3600]
  // Turning on the spot counts as moving while the net angle turned since
  // the robot slowed down grows at this rate (rad/s), (0, 10]: a dither
  // left and right in place is not progress (a Robox stood 267 s wedged
  // against exhibit_09_kiosk, turning alternately faster than this).
  double turn_rate_radps = 0.05;

  void Validate() const;  // throws std::invalid_argument naming the field
};

class BlockedMonitor {
 public:
  explicit BlockedMonitor(const BlockedMonitorOptions& options);

  struct Step {
    bool became_blocked = false;  // a blocked episode begins (the `blocked` event)
    bool replan = false;          // replan now
    bool abort = false;           // give the mission up
  };
  // One sample at `now_s` of the robot's speed (m/s) and signed turn rate
  // (rad/s, counter-clockwise positive); with no goal (dwelling, idle) the
  // monitor resets.
  Step Update(double now_s, double speed_mps, double turn_rate_radps, bool has_goal);
  void Reset();

  bool blocked() const { return blocked_; }
  int episodes() const { return episodes_; }
  // Time inside blocked episodes, counted from their first slow sample (s).
  double time_blocked_s() const;
  double longest_blocked_s() const;

 private:
  BlockedMonitorOptions options_;
  bool slow_ = false;
  bool blocked_ = false;
  double slow_since_s_ = 0.0;
  double net_turn_rad_ = 0.0;  // turned since slow_since_s_, signed
  double last_s_ = 0.0;
  double next_replan_s_ = 0.0;
  bool abort_reported_ = false;
  int episodes_ = 0;
  double closed_blocked_s_ = 0.0;  // of finished episodes
  double longest_s_ = 0.0;
};

}  // namespace pavilion::nav
