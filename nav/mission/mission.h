#pragma once

// Missions (issue 14, thesis §4.5.3 and §6.3.3): one goal each — a node of the
// map's topology to reach with its full pose, then an optional dwell there. A
// tour is a sequence of missions. Plain value types the scenarios read: the
// events a navigation controller reports, its figures (metrics.md names) and
// what the top-down snapshot draws of it.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/types/pose2.h"

namespace pavilion::nav {

struct Mission {
  std::string goal;        // node id of the robot's map (a station)
  core::Pose2 goal_pose;   // the node's full pose (x, y, theta), world frame
  double dwell_s = 0.0;    // wait at the goal after arrival, s, >= 0
  double timeout_s = 0.0;  // aborted when not completed this long after its start, s, > 0
};

// Why a mission was aborted (metrics.md: missions_aborted by reason).
enum class AbortReason { kUnreachable, kTimeout, kLost, kBlocked };
inline constexpr std::array<AbortReason, 4> kAbortReasons = {
    AbortReason::kUnreachable, AbortReason::kTimeout, AbortReason::kLost, AbortReason::kBlocked};
const char* ToString(AbortReason reason);

// What the navigation reports up (events.jsonl: mission_started,
// mission_completed, mission_aborted, blocked, replanned, deadlock_detected,
// deadlock_resolved, deadlock_unresolved).
struct NavigationEvent {
  enum class Type {
    kMissionStarted,
    kMissionCompleted,
    kMissionAborted,
    kBlocked,
    kReplanned,
    kDeadlockDetected,
    kDeadlockResolved,
    kDeadlockUnresolved,
    kUncertaintyHold,      // stands for its belief's uncertainty (UncertaintyOptions)
    kUncertaintyHoldEnded  // ... and drives on, or the hold ended otherwise
  };
  Type type = Type::kMissionStarted;
  double at_s = 0.0;
  int mission = 0;                                 // index in the robot's sequence of missions
  std::string goal;                                // the mission's goal node
  AbortReason reason = AbortReason::kUnreachable;  // kMissionAborted
  // kReplanned: "band_snap", "blocked", "relocalized" or "fleet"
  std::string cause;
  // kMissionCompleted/Aborted: since its start; kDeadlockResolved: since
  // detection; kUncertaintyHoldEnded: since the hold began
  double duration_s = 0.0;
  double path_length_m = 0;  // kMissionCompleted/Aborted: travelled since its start (odometry)
  bool rest = false;         // mission events: the goal is a rest node (no station was free)
};
const char* ToString(NavigationEvent::Type type);

// Running figures of one robot's navigation (metrics.md, Navigation and fleet).
struct NavigationFigures {
  int missions_started = 0;
  int missions_completed = 0;
  std::array<int, kAbortReasons.size()> missions_aborted{};  // by AbortReason
  double mission_time_s = 0.0;                               // summed over completed missions
  double mission_path_length_m = 0.0;  // summed over completed missions (odometry)
  int replans = 0;                     // band snaps and blocked replans
  int band_snaps = 0;
  int global_plans = 0;
  int blocked_episodes = 0;     // slower than the blocked speed for longer than the blocked time
  double time_blocked_s = 0.0;  // inside blocked episodes, from their first slow moment
  double longest_blocked_s = 0.0;
  // Clearance: distance (m) from the robot's polygon to the nearest obstacle
  // point (laser readings and ghost points) at each dynamic-window cycle.
  double clearance_sum_m = 0.0;
  std::int64_t clearance_samples = 0;
  double min_clearance_m = 0.0;  // meaningful when clearance_samples > 0
  std::int64_t dwa_cycles = 0;
  std::int64_t band_updates = 0;
  std::int64_t no_admissible_cycles = 0;  // the dynamic window found nothing but stop
  // Fleet (§6.3.5): replans because the others' weights or a deviation made
  // another way cheaper; cycles waiting because every remaining station was
  // taken; missions to a station visited before after waiting station_wait_s.
  int fleet_replans = 0;
  std::int64_t station_waits = 0;
  int station_revisits = 0;
  int rest_missions = 0;  // missions to a rest node (NavigationControllerOptions::rest_among)
  // The overlap deadlock of §6.5 (nav/fleet/deadlock_monitor.h).
  int deadlocks_detected = 0;
  int deadlocks_resolved = 0;
  int deadlocks_unresolved = 0;
  double longest_deadlock_s = 0.0;  // detection to resolution, s
  // The longest time the robot stayed within kStillMoveM (0.3 m, net
  // displacement: a dither is not progress) of one place while it had a
  // mission to drive (across blocked aborts and new missions; a dwell before
  // it counts in): "stuck" when over 120 s (issue 15).
  double longest_still_s = 0.0;
  // How long it has stood so far (0 when it moved or has no mission to drive):
  // the run judges when a human would have stepped in. Not in metrics.json.
  double still_s = 0.0;
  int escapes = 0;  // escapes from a pocket (EscapeOptions)
  // Holds for the belief's uncertainty (UncertaintyOptions) and their time, s.
  int uncertainty_holds = 0;
  double uncertainty_hold_s = 0.0;

  int missions_aborted_total() const;
};

// What the snapshot draws of a robot's navigation (world frame).
struct NavigationPicture {
  std::vector<Eigen::Vector2d> plan;  // the global plan's nodes still ahead
  std::vector<Eigen::Vector2d> band_centers;
  std::vector<double> band_radii_m;
  std::vector<Eigen::Vector2d> dwa_arc;  // the chosen command's predicted path
};

}  // namespace pavilion::nav
