#pragma once

// The robots-block-each-other deadlock of thesis §6.5: the virtual contours
// of §6.3.5.1 (nav/local/robot_contours.h) of two nearby robots, drawn when
// their markers suddenly became visible, lie within the other's hull, and the
// dynamic window stops both for good (at Expo.02 staff pulled one away).
//
// Each robot detects and resolves it from its own sensing alone — never from
// ground truth — by one rule that all robots evaluate alike:
//   clear    -> suspect   a contour overlaps (or nearly touches) the own
//                         hull while the robot, having a goal, is stalled;
//   suspect  -> detected  after detect_s without a break (`detected`);
//   detected -> clipping  after a seeded random back-off, so that two robots
//                         in the same deadlock rarely act in the same cycle;
//                         while clipping the caller shrinks overlapping
//                         contours with ClipRadius (another robot cannot
//                         overlap our own hull);
//   clipping -> retreat   still stalled retreat_after_s later (the clipped
//                         contours leave no way on: two robots face each
//                         other where only one fits): the robot yields —
//                         it drives away from the other's contour, and the
//                         other, whose back-off is later, finds the room;
//   resolved              once the robot has moved resolved_move_m since
//                         detection, or kDeadlockClearS passed with neither
//                         overlap nor stall (`resolved`, with its duration);
//   unresolved            give_up_s after detection: counted, and the rule
//                         starts over from clear.
// With resolve off the monitor only observes: `detected` is still emitted and
// counted, `clip` is never set and nothing counts as resolved (an episode that
// dissolves by itself ends silently; give_up_s still counts it unresolved).
// Without a goal the monitor returns to clear and an open episode is dropped.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/random/random_stream.h"

namespace pavilion::nav {

// Neither overlap nor stall for this long ends an episode (s): ten cycles of
// the 10 Hz dynamic window (§6.3.4).
inline constexpr double kDeadlockClearS = 1.0;

struct DeadlockOptions {
  // Clip contours to resolve a detected deadlock; false: detect and count only.
  bool resolve = true;
  // Overlap and stall this long is a deadlock, s, (0, 600]. Chosen: longer
  // than a visitor crossing between two robots, shorter than the blocked
  // monitor's 5 s, so the rule acts before replanning and staff intervention.
  double detect_s = 3.0;
  // The back-off is uniform in [0, backoff_max_s], s, [0, 60]. Chosen: two
  // robots' draws then fall in the same 0.1 s cycle with probability ~5 %.
  double backoff_max_s = 4.0;
  // Moving this far since detection resolves it, m, (0, 10]. Chosen: about
  // the marker offset (0.34 m), the geometry that caused the overlap is gone.
  double resolved_move_m = 0.3;
  // Clipping this long after the back-off without a way on: retreat, s,
  // [0, 60]. Chosen: ten cycles to find a way past the clipped contour, a
  // few to start on it.
  double retreat_after_s = 2.0;
  // Unresolved this long after detection: count it and start over, s,
  // (backoff_max_s + retreat_after_s, 3600]. Chosen: below the blocked
  // monitor's 45 s abort.
  double give_up_s = 30.0;

  void Validate() const;  // throws std::invalid_argument naming the field
};

class DeadlockMonitor {
 public:
  // `seed` seeds the back-off draws (give each robot its own).
  DeadlockMonitor(const DeadlockOptions& options, std::uint64_t seed);

  struct Step {
    bool detected = false;      // a deadlock was detected in this cycle
    bool resolved = false;      // the open deadlock was resolved in this cycle
    bool clip = false;          // shrink contours that overlap the own hull now
    bool retreat = false;       // yield: drive away from the other robot now (with clip)
    double resolution_s = 0.0;  // with `resolved`: time from detection (s)
  };
  // One dynamic-window cycle at `now_s` (non-decreasing): `overlap` when a
  // virtual contour overlaps the own hull, `stalled` when the window found no
  // admissible motion or the robot is stopped, `odometer_m` the distance
  // travelled so far (non-decreasing). Throws std::invalid_argument for
  // non-finite times or distances.
  Step Update(double now_s, bool has_goal, bool overlap, bool stalled, double odometer_m);

  int detected() const { return detected_; }
  int resolved() const { return resolved_; }
  int unresolved() const { return unresolved_; }
  double longest_resolution_s() const { return longest_resolution_s_; }
  // The back-off drawn for the latest detected deadlock (s), 0 before any.
  double backoff_s() const { return backoff_s_; }

 private:
  enum class State { kClear, kSuspect, kDetected };
  Step Detect(double now_s, double odometer_m);
  Step Follow(double now_s, bool overlap, bool stalled, double odometer_m);

  DeadlockOptions options_;
  core::RandomStream random_;
  State state_ = State::kClear;
  double suspect_since_s_ = 0.0;
  double detected_at_s_ = 0.0;
  double detected_odometer_m_ = 0.0;
  double free_since_s_ = -1.0;  // start of the current overlap- and stall-free run; < 0: none
  double backoff_s_ = 0.0;
  int detected_ = 0;
  int resolved_ = 0;
  int unresolved_ = 0;
  double longest_resolution_s_ = 0.0;
};

// The direction (unit vector, robot frame) the robot yields in: of 16
// directions, the one with the most room — the least distance of `points`
// (the dynamic window's obstacle points) from the leg of `leg_m` that starts
// on the hull's inscribed circle (`inradius_m`), capped at 0.3 m so that all
// open directions tie — preferring those away from `other`, the other
// robot's contour centre (non-zero). Ties go to the first direction
// counter-clockwise from +x.
Eigen::Vector2d YieldDirection(const Eigen::Vector2d& other, double inradius_m, double leg_m,
                               const std::vector<Eigen::Vector2d>& points);

}  // namespace pavilion::nav
