#pragma once

// The run in the figures of an operating log (issue 21): Expo.02's statistics
// (thesis §6.5: hours, kilometres, missions) and the Computer 2000 run's
// Table 4.3 (§4.5.3: localization cycles, lost situations, missions without a
// match for 5 s and 10 s, collisions), plus what a human would have had to do
// — the interventions Expo.02's staff made by hand.
//
// RobotDayTracker follows one robot through the run, on the runner's side
// (it sees the truth); MakeRunTable sums the robots into the fleet's table,
// which metrics.json holds as `run_table` and the report draws.

#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "scenarios/metrics/collision_classes.h"
#include "scenarios/metrics/localization_tracker.h"

namespace pavilion::scenarios {

struct RunMetrics;

// A robot standing (net displacement under 0.3 m, as the navigation's
// longest_still figure) with a mission to drive for longer than this needed a
// human to pull it free, s (issue 21).
inline constexpr double kInterventionStillS = 60.0;
// A robot in a lost situation for longer than this needed a human to set it
// back, s (issue 21).
inline constexpr double kInterventionLostS = 30.0;
// A lost situation that begins within this of a kidnap, a push or a collision
// of the robot is that event's doing, s (chosen: a loss shows within a cycle
// or two of its cause; 30 s leaves room for a slowly diverging estimate); one
// that begins within this of the end of the last continues it, with its cause.
inline constexpr double kLossCauseWindowS = 30.0;
// Table 4.3's two lengths of a stretch without a matched feature, s.
inline constexpr double kNoMatchLongS = 10.0;
inline constexpr double kNoMatchShortS = 5.0;

// What began a lost situation, in this order of precedence when several fall
// in the window. Table 4.3's "lost situations" leave out the collisions'.
enum class LossCause { kKidnap, kPush, kCollision, kUnexplained };
inline constexpr std::array<LossCause, 4> kLossCauses = {
    LossCause::kKidnap, LossCause::kPush, LossCause::kCollision, LossCause::kUnexplained};
const char* ToString(LossCause cause);

// One robot's share of the table.
struct RobotDayFigures {
  double driving_s = 0.0;  // true speed above kMovingSpeedMps
  double max_speed_mps = 0.0;
  std::array<int, kLossCauses.size()> lost_by_cause{};  // by LossCause
  int lost_over_30s = 0;                                // interventions: lost too long
  double longest_lost_s = 0.0;
  int still_over_60s = 0;  // interventions: standing with a mission too long
  int missions_without_match_5s = 0;
  int missions_without_match_10s = 0;
  double longest_without_match_s = 0.0;
  // Kidnaps and staff pushes (disturbances), and how soon after each the
  // robot was localized within 0.2 m / 5 deg again, in motion time.
  int kidnaps = 0;
  int pushes = 0;
  int recovered = 0;                      // within kRecoveryMotionS of motion
  int unrecovered_at_end = 0;             // the run ended before the window did
  std::vector<double> recovery_motion_s;  // of the recovered, in order

  int lost_situations() const;
};

class RobotDayTracker {
 public:
  // One physics step ending at now_s, of dt_s, with the robot's true speed
  // at its end; still_s is how long its navigation has stood with a mission
  // (NavigationFigures::still_s; 0 without navigation).
  void OnStep(double now_s, double dt_s, double speed_mps, double still_s);
  // A kidnap at now_s: judged from its next cycle on.
  void OnKidnap(double now_s);
  // A push began at now_s; judged from now_s + duration_s on, or, with the
  // motors disengaged, from OnMotorsEngaged.
  void OnPush(double now_s, double duration_s, bool motors_disengaged);
  void OnMotorsEngaged(double now_s);
  // A contact of the robot with anything began.
  void OnCollision(double now_s);
  // An estimation cycle ended at now_s; in_lost_situation as the
  // LocalizationTracker judged it; mission_index counts the missions started.
  void OnCycle(double now_s, const LocalizationCycle& cycle, bool in_lost_situation,
               int mission_index);
  // The figures at the run's end at end_s.
  RobotDayFigures Figures(double end_s) const;

 private:
  struct Pending {
    bool kidnap = false;
    double judge_from_s = 0.0;  // the push's end (infinite until the motors engage)
    double motion_s = 0.0;      // after judge_from_s
  };
  void FinishMission(double now_s);

  RobotDayFigures f_;
  std::vector<Pending> pending_;
  std::optional<double> last_kidnap_s_, last_push_s_, last_collision_s_;
  bool still_counted_ = false;
  std::optional<double> lost_since_s_;
  std::optional<double> last_lost_end_s_;
  LossCause last_cause_ = LossCause::kUnexplained;
  bool lost_counted_ = false;
  int mission_index_ = 0;
  double last_match_s_ = 0.0;
  double mission_longest_gap_s_ = 0.0;
};

// The fleet's table: sums over the robots, the ratios over the sums.
struct RunTable {
  double hours = 0.0;
  int robots = 0;
  double robot_hours = 0.0;
  double distance_km = 0.0;
  double mean_speed_mps = 0.0;          // distance over robot time
  double mean_driving_speed_mps = 0.0;  // distance over driving time
  double max_speed_mps = 0.0;
  int missions_started = 0;
  int missions_completed = 0;
  int missions_aborted = 0;
  std::array<int, 4> missions_aborted_by_reason{};  // nav::kAbortReasons
  std::int64_t localization_cycles = 0;
  int lost_situations = 0;  // truth or declared (metrics.md)
  int declared_lost_situations = 0;
  std::array<int, kLossCauses.size()> lost_by_cause{};
  int missions_without_match_5s = 0;
  int missions_without_match_10s = 0;
  int kidnaps = 0;
  int pushes = 0;
  int recovered = 0;
  std::vector<double> recovery_motion_s;
  CollisionCounts collisions;
  int deadlocks_detected = 0;
  int deadlocks_resolved = 0;
  int deadlocks_unresolved = 0;
  int still_over_60s = 0;
  int lost_over_30s = 0;
  double intimate_s = 0.0, personal_s = 0.0, social_s = 0.0;

  int disturbances() const { return kidnaps + pushes; }
  int interventions() const { return still_over_60s + lost_over_30s; }
  double interventions_per_robot_hour() const;
  int missions_in_progress() const {
    return missions_started - missions_completed - missions_aborted;
  }
  // Of the missions that ended (completed or aborted): one still under way
  // when the run stops has not failed.
  double missions_completed_ratio() const;
  double recovered_ratio() const;           // of the disturbances
  double median_recovery_motion_s() const;  // 0 without a recovery
};

// The table of a run whose robots carry `day` figures; none without one.
std::optional<RunTable> MakeRunTable(const RunMetrics& metrics);
nlohmann::ordered_json RunTableToJson(const RunTable& table);
nlohmann::ordered_json RobotDayToJson(const RobotDayFigures& figures);

}  // namespace pavilion::scenarios
