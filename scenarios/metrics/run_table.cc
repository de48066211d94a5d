#include "scenarios/metrics/run_table.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "scenarios/metrics/relocalization_tracker.h"
#include "scenarios/metrics/run_metrics.h"

namespace pavilion::scenarios {
namespace {

using Json = nlohmann::ordered_json;

double Ratio(double part, double whole) { return whole > 0.0 ? part / whole : 0.0; }

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
  if (values.size() % 2 == 1) return values[mid];
  const double upper = values[mid];
  return 0.5 * (upper + *std::max_element(values.begin(),
                                          values.begin() + static_cast<std::ptrdiff_t>(mid)));
}

double Mean(const std::vector<double>& values) {
  double sum = 0.0;
  for (double v : values) sum += v;
  return values.empty() ? 0.0 : sum / static_cast<double>(values.size());
}

Json ByCause(const std::array<int, kLossCauses.size()>& counts) {
  Json j;
  for (LossCause cause : kLossCauses) j[ToString(cause)] = counts[static_cast<std::size_t>(cause)];
  return j;
}

int MatchedFeatures(const LocalizationCycle& c) {
  return c.matched_lines + c.matched_beacons + c.matched_edges + c.matched_other;
}

}  // namespace

const char* ToString(LossCause cause) {
  switch (cause) {
    case LossCause::kKidnap:
      return "kidnap";
    case LossCause::kPush:
      return "push";
    case LossCause::kCollision:
      return "collision";
    case LossCause::kUnexplained:
      return "unexplained";
  }
  return "?";
}

int RobotDayFigures::lost_situations() const {
  int n = 0;
  for (int c : lost_by_cause) n += c;
  return n;
}

void RobotDayTracker::OnStep(double now_s, double dt_s, double speed, double still_s) {
  f_.max_speed_mps = std::max(f_.max_speed_mps, speed);
  if (speed > kMovingSpeedMps) {
    f_.driving_s += dt_s;
    for (Pending& p : pending_) {
      if (now_s > p.judge_from_s) p.motion_s += dt_s;
    }
  }
  if (still_s > kInterventionStillS && !still_counted_) {
    ++f_.still_over_60s;
    still_counted_ = true;
  } else if (still_s <= kInterventionStillS) {
    still_counted_ = false;
  }
}

void RobotDayTracker::OnKidnap(double now_s) {
  ++f_.kidnaps;
  last_kidnap_s_ = now_s;
  pending_.push_back({true, now_s, 0.0});
}

void RobotDayTracker::OnPush(double now_s, double duration_s, bool motors_disengaged) {
  ++f_.pushes;
  last_push_s_ = now_s;
  pending_.push_back(
      {false, motors_disengaged ? std::numeric_limits<double>::infinity() : now_s + duration_s,
       0.0});
}

void RobotDayTracker::OnMotorsEngaged(double now_s) {
  last_push_s_ = now_s;  // the robot was rolling free until now
  for (Pending& p : pending_) {
    if (!p.kidnap && std::isinf(p.judge_from_s)) p.judge_from_s = now_s;
  }
}

void RobotDayTracker::OnCollision(double now_s) { last_collision_s_ = now_s; }

void RobotDayTracker::OnCycle(double now_s, const LocalizationCycle& cycle, bool in_lost_situation,
                              int mission_index) {
  // Recovered: localized again within 0.2 m / 5 deg (the relocalization
  // criterion of issue 18) within 30 s of motion after the disturbance ended.
  const bool good = cycle.mode == nav::LocalizationMode::kLocalized && !cycle.lost &&
                    cycle.position_error_m <= kRelocalizedPositionM &&
                    std::abs(cycle.heading_error_rad) <= kRelocalizedHeadingRad;
  std::erase_if(pending_, [&](const Pending& p) {
    if (now_s < p.judge_from_s) return false;
    if (p.motion_s > kRecoveryMotionS) return true;  // not recovered in time
    if (!good) return false;
    ++f_.recovered;
    f_.recovery_motion_s.push_back(p.motion_s);
    return true;
  });

  // Lost situations: their cause when they begin, their length when they end.
  if (in_lost_situation && !lost_since_s_) {
    lost_since_s_ = now_s;
    lost_counted_ = false;
    const auto recent = [&](const std::optional<double>& at) {
      return at && now_s - *at <= kLossCauseWindowS;
    };
    // One that begins soon after the last one ended (a false relocalization
    // between two spells of not being localized) carries on its cause.
    const LossCause cause = recent(last_lost_end_s_)    ? last_cause_
                            : recent(last_kidnap_s_)    ? LossCause::kKidnap
                            : recent(last_push_s_)      ? LossCause::kPush
                            : recent(last_collision_s_) ? LossCause::kCollision
                                                        : LossCause::kUnexplained;
    last_cause_ = cause;
    ++f_.lost_by_cause[static_cast<std::size_t>(cause)];
  }
  if (lost_since_s_) {
    const double lost_s = now_s - *lost_since_s_;
    f_.longest_lost_s = std::max(f_.longest_lost_s, lost_s);
    if (lost_s > kInterventionLostS && !lost_counted_) {
      ++f_.lost_over_30s;
      lost_counted_ = true;
    }
    if (!in_lost_situation) {
      lost_since_s_.reset();
      last_lost_end_s_ = now_s;
    }
  }

  // Table 4.3's missions without a match: the longest stretch of a mission
  // (from its start) between cycles with a matched feature.
  if (mission_index != mission_index_) {
    FinishMission(now_s);
    mission_index_ = mission_index;
    last_match_s_ = now_s;
    mission_longest_gap_s_ = 0.0;
  }
  if (MatchedFeatures(cycle) > 0) {
    last_match_s_ = now_s;
  } else if (mission_index_ > 0) {
    mission_longest_gap_s_ = std::max(mission_longest_gap_s_, now_s - last_match_s_);
    f_.longest_without_match_s = std::max(f_.longest_without_match_s, mission_longest_gap_s_);
  }
}

void RobotDayTracker::FinishMission(double /*now_s*/) {
  if (mission_index_ <= 0) return;
  if (mission_longest_gap_s_ >= kNoMatchShortS) ++f_.missions_without_match_5s;
  if (mission_longest_gap_s_ >= kNoMatchLongS) ++f_.missions_without_match_10s;
}

RobotDayFigures RobotDayTracker::Figures(double end_s) const {
  RobotDayTracker done = *this;
  done.FinishMission(end_s);
  for (const Pending& p : done.pending_) {
    if (p.motion_s <= kRecoveryMotionS) ++done.f_.unrecovered_at_end;
  }
  return done.f_;
}

double RunTable::interventions_per_robot_hour() const {
  return Ratio(interventions(), robot_hours);
}

double RunTable::missions_completed_ratio() const {
  return Ratio(missions_completed, missions_completed + missions_aborted);
}

double RunTable::recovered_ratio() const { return Ratio(recovered, disturbances()); }

double RunTable::median_recovery_motion_s() const { return Median(recovery_motion_s); }

std::optional<RunTable> MakeRunTable(const RunMetrics& m) {
  RunTable t;
  t.hours = m.sim_duration_s / 3600.0;
  double driving_s = 0.0, distance_m = 0.0;
  bool any = false;
  for (const RobotMetrics& r : m.robots) {
    if (!r.day) continue;
    any = true;
    const RobotDayFigures& d = *r.day;
    ++t.robots;
    distance_m += r.distance_m;
    driving_s += d.driving_s;
    t.max_speed_mps = std::max(t.max_speed_mps, d.max_speed_mps);
    if (r.navigation) {
      const nav::NavigationFigures& n = *r.navigation;
      t.missions_started += n.missions_started;
      t.missions_completed += n.missions_completed;
      t.missions_aborted += n.missions_aborted_total();
      for (std::size_t k = 0; k < n.missions_aborted.size(); ++k) {
        t.missions_aborted_by_reason[k] += n.missions_aborted[k];
      }
      t.deadlocks_detected += n.deadlocks_detected;
      t.deadlocks_resolved += n.deadlocks_resolved;
      t.deadlocks_unresolved += n.deadlocks_unresolved;
    }
    if (r.localization) {
      t.localization_cycles += r.localization->cycles;
      t.lost_situations += r.localization->lost_situations;
      t.declared_lost_situations += r.localization->declared_lost_situations;
    }
    for (std::size_t k = 0; k < kLossCauses.size(); ++k) t.lost_by_cause[k] += d.lost_by_cause[k];
    t.missions_without_match_5s += d.missions_without_match_5s;
    t.missions_without_match_10s += d.missions_without_match_10s;
    t.kidnaps += d.kidnaps;
    t.pushes += d.pushes;
    t.recovered += d.recovered;
    t.recovery_motion_s.insert(t.recovery_motion_s.end(), d.recovery_motion_s.begin(),
                               d.recovery_motion_s.end());
    t.collisions += r.collisions_by_class;
    t.still_over_60s += d.still_over_60s;
    t.lost_over_30s += d.lost_over_30s;
    if (r.social) {
      t.intimate_s += r.social->intimate_time_s;
      t.personal_s += r.social->personal_time_s;
      t.social_s += r.social->social_time_s;
    }
  }
  if (!any) return std::nullopt;
  t.robot_hours = t.hours * t.robots;
  t.distance_km = distance_m / 1000.0;
  t.mean_speed_mps = Ratio(distance_m, t.robot_hours * 3600.0);
  t.mean_driving_speed_mps = Ratio(distance_m, driving_s);
  return t;
}

Json RunTableToJson(const RunTable& t) {
  const auto r = [](double v, int decimals) { return RoundForJson(v, decimals); };
  Json aborted;
  for (nav::AbortReason reason : nav::kAbortReasons) {
    aborted[nav::ToString(reason)] = t.missions_aborted_by_reason[static_cast<std::size_t>(reason)];
  }
  const std::vector<double>& rec = t.recovery_motion_s;
  return Json{
      {"hours", r(t.hours, 4)},
      {"robots", t.robots},
      {"robot_hours", r(t.robot_hours, 4)},
      {"distance_km", r(t.distance_km, 4)},
      {"mean_speed_mps", r(t.mean_speed_mps, 4)},
      {"mean_driving_speed_mps", r(t.mean_driving_speed_mps, 4)},
      {"max_speed_mps", r(t.max_speed_mps, 4)},
      {"missions",
       {{"started", t.missions_started},
        {"completed", t.missions_completed},
        {"aborted", t.missions_aborted},
        {"in_progress", t.missions_in_progress()},
        {"completed_ratio", r(t.missions_completed_ratio(), 4)},
        {"aborted_by_reason", aborted}}},
      {"localization_cycles", t.localization_cycles},
      {"lost_situations", t.lost_situations},
      {"declared_lost_situations", t.declared_lost_situations},
      {"lost_by_cause", ByCause(t.lost_by_cause)},
      {"missions_without_match_5s", t.missions_without_match_5s},
      {"missions_without_match_10s", t.missions_without_match_10s},
      {"disturbances",
       {{"kidnaps", t.kidnaps},
        {"pushes", t.pushes},
        {"recovered", t.recovered},
        {"recovered_ratio", r(t.recovered_ratio(), 4)},
        {"mean_recovery_motion_s", r(Mean(rec), 3)},
        {"median_recovery_motion_s", r(t.median_recovery_motion_s(), 3)},
        {"max_recovery_motion_s",
         r(rec.empty() ? 0.0 : *std::max_element(rec.begin(), rec.end()), 3)}}},
      {"collisions", CollisionCountsToJson(t.collisions)},
      {"deadlocks",
       {{"detected", t.deadlocks_detected},
        {"resolved", t.deadlocks_resolved},
        {"unresolved", t.deadlocks_unresolved}}},
      {"interventions",
       {{"still_over_60s", t.still_over_60s},
        {"lost_over_30s", t.lost_over_30s},
        {"total", t.interventions()},
        {"per_robot_hour", r(t.interventions_per_robot_hour(), 4)}}},
      {"social_zone_s",
       {{"intimate", r(t.intimate_s, 3)},
        {"personal", r(t.personal_s, 3)},
        {"social", r(t.social_s, 3)}}},
  };
}

Json RobotDayToJson(const RobotDayFigures& d) {
  const auto r = [](double v, int decimals) { return RoundForJson(v, decimals); };
  return Json{
      {"driving_s", r(d.driving_s, 3)},
      {"max_speed_mps", r(d.max_speed_mps, 4)},
      {"lost_by_cause", ByCause(d.lost_by_cause)},
      {"longest_lost_s", r(d.longest_lost_s, 3)},
      {"lost_over_30s", d.lost_over_30s},
      {"still_over_60s", d.still_over_60s},
      {"missions_without_match_5s", d.missions_without_match_5s},
      {"missions_without_match_10s", d.missions_without_match_10s},
      {"longest_without_match_s", r(d.longest_without_match_s, 3)},
      {"kidnaps", d.kidnaps},
      {"pushes", d.pushes},
      {"recovered", d.recovered},
      {"unrecovered_at_end", d.unrecovered_at_end},
  };
}

}  // namespace pavilion::scenarios
