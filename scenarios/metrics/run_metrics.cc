#include "scenarios/metrics/run_metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace pavilion::scenarios {
namespace {

using Json = nlohmann::ordered_json;

Json LocalizationJson(const LocalizationFigures& f) {
  const auto n = [](double v) { return RoundForJson(v); };
  return {{"cycles", f.cycles},
          {"position_rmse_m", n(f.position_rmse_m)},
          {"position_median_m", n(f.position_median_m)},
          {"position_max_m", n(f.position_max_m)},
          {"heading_rmse_deg", n(f.heading_rmse_deg)},
          {"heading_median_deg", n(f.heading_median_deg)},
          {"heading_max_deg", n(f.heading_max_deg)},
          {"two_sigma_frontal_m", n(f.two_sigma_frontal_m)},
          {"two_sigma_lateral_m", n(f.two_sigma_lateral_m)},
          {"two_sigma_heading_deg", n(f.two_sigma_heading_deg)},
          {"anees", n(f.anees)},
          {"nees_below_95_bound_ratio", n(f.nees_below_95_bound_ratio)},
          {"matched_lines_per_cycle", n(f.matched_lines_per_cycle)},
          {"matched_beacons_per_cycle", n(f.matched_beacons_per_cycle)},
          {"matched_edges_per_cycle", n(f.matched_edges_per_cycle)},
          {"cycles_without_match", f.cycles_without_match},
          {"lost_situations", f.lost_situations},
          {"declared_lost_situations", f.declared_lost_situations}};
}

Json KidnapJson(const KidnapOutcome& k) {
  const auto n = [](double v) { return RoundForJson(v, 4); };
  Json j = {{"at_s", n(k.at_s)},
            {"motion_s", n(k.motion_s)},
            {"distance_m", n(k.distance_m)},
            {"lost_declared", k.lost_declared}};
  if (k.lost_declared) j["motion_to_lost_s"] = n(k.motion_to_lost_s);
  j["recovered"] = k.recovered;
  if (k.recovered) {
    j["time_to_relocalize_s"] = n(k.motion_to_relocalize_s);
    j["distance_to_relocalize_m"] = n(k.distance_to_relocalize_m);
  }
  j["localized_correctly"] = k.localized_correctly;
  if (k.localized_correctly) j["motion_to_correct_s"] = n(k.motion_to_correct_s);
  j["fbt_recovered"] = k.fbt_recovered;
  if (k.fbt_recovered) j["fbt_recovery_s"] = n(k.fbt_recovery_s);
  return j;
}

// Times are motion time (relocalization_tracker.h) but fbt_mean_recovery_s.
Json RelocalizationJson(const RelocalizationFigures& f) {
  const auto n = [](double v) { return RoundForJson(v, 4); };
  Json kidnaps = Json::array();
  for (const KidnapOutcome& k : f.outcomes) kidnaps.push_back(KidnapJson(k));
  return {{"kidnaps", f.kidnaps},
          {"recovered", f.recovered},
          {"recovered_ratio", n(f.recovered_ratio)},
          {"lost_declared_within_10s_ratio", n(f.lost_declared_within_10s_ratio)},
          {"mean_time_to_lost_s", n(f.mean_time_to_lost_s)},
          {"median_time_to_lost_s", n(f.median_time_to_lost_s)},
          {"mean_time_to_relocalize_s", n(f.mean_time_to_relocalize_s)},
          {"median_time_to_relocalize_s", n(f.median_time_to_relocalize_s)},
          {"mean_distance_to_relocalize_m", n(f.mean_distance_to_relocalize_m)},
          {"median_distance_to_relocalize_m", n(f.median_distance_to_relocalize_m)},
          {"declared_losses", f.declared_losses},
          {"false_relocalizations", f.false_relocalizations},
          {"fbt_recovered_ratio", n(f.fbt_recovered_ratio)},
          {"fbt_mean_recovery_s", n(f.fbt_mean_recovery_s)},
          {"mean_hypotheses", n(f.mean_hypotheses)},
          {"max_hypotheses", f.max_hypotheses},
          {"per_kidnap", kidnaps}};
}

// The fleet's relocalization: counts summed, ratios over all kidnaps.
Json FleetRelocalizationJson(const RunMetrics& m) {
  int kidnaps = 0, recovered = 0, lost_in_time = 0, fbt = 0, false_relocalizations = 0;
  int declared = 0;
  for (const RobotMetrics& r : m.robots) {
    if (!r.relocalization) continue;
    const RelocalizationFigures& f = *r.relocalization;
    kidnaps += f.kidnaps;
    recovered += f.recovered;
    false_relocalizations += f.false_relocalizations;
    declared += f.declared_losses;
    for (const KidnapOutcome& k : f.outcomes) {
      lost_in_time += k.lost_declared && k.motion_to_lost_s <= kLostDeclaredMotionS ? 1 : 0;
      fbt += k.fbt_recovered ? 1 : 0;
    }
  }
  const auto ratio = [&](int count) {
    return kidnaps > 0 ? RoundForJson(static_cast<double>(count) / kidnaps, 4) : 0.0;
  };
  return {{"kidnaps", kidnaps},
          {"recovered", recovered},
          {"recovered_ratio", ratio(recovered)},
          {"lost_declared_within_10s_ratio", ratio(lost_in_time)},
          {"declared_losses", declared},
          {"false_relocalizations", false_relocalizations},
          {"fbt_recovered_ratio", ratio(fbt)}};
}

Json NavigationJson(const nav::NavigationFigures& f, const CollisionCounts& collisions) {
  const auto n = [](double v) { return RoundForJson(v, 4); };
  Json aborted;
  for (nav::AbortReason reason : nav::kAbortReasons) {
    aborted[nav::ToString(reason)] = f.missions_aborted[static_cast<std::size_t>(reason)];
  }
  const double completed = f.missions_completed;
  Json j = {
      {"missions_started", f.missions_started},
      {"missions_completed", f.missions_completed},
      {"missions_aborted", f.missions_aborted_total()},
      {"missions_aborted_by_reason", aborted},
      {"mean_mission_time_s", completed > 0 ? n(f.mission_time_s / completed) : 0.0},
      {"mean_mission_path_length_m", completed > 0 ? n(f.mission_path_length_m / completed) : 0.0},
      {"clearance_mean_m",
       f.clearance_samples > 0 ? n(f.clearance_sum_m / f.clearance_samples) : 0.0},
      {"clearance_min_m", f.clearance_samples > 0 ? n(f.min_clearance_m) : 0.0},
      {"time_blocked_s", n(f.time_blocked_s)},
      {"blocked_episodes", f.blocked_episodes},
      {"longest_blocked_s", n(f.longest_blocked_s)},
      {"replans", f.replans},
      {"band_snaps", f.band_snaps},
      {"global_plans", f.global_plans},
      {"dwa_cycles", f.dwa_cycles},
      {"dwa_no_admissible_cycles", f.no_admissible_cycles},
      {"band_updates", f.band_updates},
      {"escapes", f.escapes},
      {"uncertainty_holds", f.uncertainty_holds},
      {"uncertainty_hold_s", n(f.uncertainty_hold_s)}};
  if (f.fleet_replans > 0 || f.station_waits > 0 || f.deadlocks_detected > 0) {
    j["fleet_replans"] = f.fleet_replans;
    j["station_wait_cycles"] = f.station_waits;
    j["station_revisits"] = f.station_revisits;
    j["rest_missions"] = f.rest_missions;
    j["deadlocks_detected"] = f.deadlocks_detected;
    j["deadlocks_resolved"] = f.deadlocks_resolved;
    j["deadlocks_unresolved"] = f.deadlocks_unresolved;
    j["longest_deadlock_s"] = n(f.longest_deadlock_s);
    j["longest_still_with_mission_s"] = n(f.longest_still_s);
  }
  j["collisions"] = CollisionCountsToJson(collisions);
  return j;
}

// Hall's zones surface to surface (social_navigation.h); times in s, gaps in m.
Json SocialJson(const SocialNavigationFigures& f) {
  const auto n = [](double v) { return RoundForJson(v, 4); };
  return {{"intimate_time_s", n(f.intimate_time_s)},
          {"personal_time_s", n(f.personal_time_s)},
          {"social_time_s", n(f.social_time_s)},
          {"intimate_intrusions", f.intimate_intrusions},
          {"personal_intrusions", f.personal_intrusions},
          {"social_intrusions", f.social_intrusions},
          {"min_visitor_gap_m", n(f.min_visitor_gap_m)},
          {"closer_than_0_2_m_s", n(f.closer_than_0_2_m_time_s)}};
}

Json CrowdJson(const CrowdFigures& f) {
  const auto n = [](double v) { return RoundForJson(v, 4); };
  Json episodes = Json::object();
  for (const auto& [behaviour, count] : f.episodes) episodes[behaviour] = count;
  return {{"pool", f.pool},
          {"arrivals", f.arrivals},
          {"departures", f.departures},
          {"mean_present", n(f.mean_present)},
          {"max_present", f.max_present},
          {"max_overlap_m", n(f.max_overlap_m)},
          {"max_overlap_by",
           {{"people_m", n(f.max_overlap_people_m)},
            {"walls_m", n(f.max_overlap_walls_m)},
            {"robots_m", n(f.max_overlap_robots_m)}}},
          {"visitor_blocked_by_robot_s", n(f.visitor_blocked_by_robot_s)},
          {"pushes", f.pushes},
          {"episodes", episodes}};
}

Json ProximityJson(const ProximityFigures& f) {
  return {{"min_robot_distance_m",
           std::isfinite(f.min_distance_m) ? Json(RoundForJson(f.min_distance_m, 4)) : Json()},
          {"near_misses", f.near_misses},
          {"time_near_s", RoundForJson(f.time_near_s, 3)}};
}

// Issue 15's fleet figures: missions per hour, nearness, deadlocks, blocked
// time, stuck robots (still with a mission longer than kStuckS) and the bytes exchanged.
Json FleetCoordinationJson(const RunMetrics& m) {
  constexpr double kStuckS = 120.0;
  const FleetRunFigures& f = *m.fleet;
  int completed = 0, robots = 0, detected = 0, resolved = 0, unresolved = 0, stuck = 0;
  int fleet_replans = 0, revisits = 0, rests = 0, escapes = 0, holds = 0;
  double hold_s = 0.0;
  double longest_deadlock_s = 0.0, blocked_s = 0.0, longest_blocked_s = 0.0, distance_m = 0.0;
  double longest_still_s = 0.0;
  std::int64_t up = 0, down = 0;
  for (const RobotMetrics& r : m.robots) {
    if (!r.navigation) continue;
    const nav::NavigationFigures& n = *r.navigation;
    ++robots;
    completed += n.missions_completed;
    detected += n.deadlocks_detected;
    resolved += n.deadlocks_resolved;
    unresolved += n.deadlocks_unresolved;
    fleet_replans += n.fleet_replans;
    revisits += n.station_revisits;
    rests += n.rest_missions;
    escapes += n.escapes;
    holds += n.uncertainty_holds;
    hold_s += n.uncertainty_hold_s;
    longest_deadlock_s = std::max(longest_deadlock_s, n.longest_deadlock_s);
    blocked_s += n.time_blocked_s;
    longest_blocked_s = std::max(longest_blocked_s, n.longest_blocked_s);
    stuck += n.longest_still_s > kStuckS ? 1 : 0;
    longest_still_s = std::max(longest_still_s, n.longest_still_s);
    distance_m += r.distance_m;
    if (r.fleet) up += r.fleet->bytes_up;
    if (r.fleet) down += r.fleet->bytes_down;
  }
  const double hours = m.sim_duration_s / 3600.0;
  const auto per = [](double a, double b) { return b > 0.0 ? RoundForJson(a / b, 4) : 0.0; };
  Json j = {{"coordination", f.coordination},
            {"robots", robots},
            {"missions_per_hour", per(completed, hours)},
            {"missions_per_robot_hour", per(completed, hours * robots)},
            {"distance_m", RoundForJson(distance_m, 3)}};
  j.update(ProximityJson(f.proximity));
  j["station_conflicts"] = f.proximity.station_conflicts;
  j.update(
      Json{{"deadlocks_detected", detected},
           {"deadlocks_resolved", resolved},
           {"deadlocks_unresolved", unresolved},
           {"longest_deadlock_s", RoundForJson(longest_deadlock_s, 3)},
           {"time_blocked_s", RoundForJson(blocked_s, 3)},
           {"longest_blocked_s", RoundForJson(longest_blocked_s, 3)},
           {"longest_still_with_mission_s", RoundForJson(longest_still_s, 3)},
           {"stuck_robots", stuck},
           {"escapes", escapes},
           {"uncertainty_holds", holds},
           {"uncertainty_hold_s", RoundForJson(hold_s, 3)},
           {"fleet_replans", fleet_replans},
           {"station_revisits", revisits},
           {"rest_missions", rests},
           {"bytes_up", up},
           {"bytes_down", down},
           {"bytes_per_robot_tick",
            per(static_cast<double>(up + down), static_cast<double>(f.ticks) * robots)},
           {"bytes_per_robot_s", per(static_cast<double>(up + down), m.sim_duration_s * robots)}});
  return j;
}

Json FleetJson(const RunMetrics& m) {
  int started = 0;
  int completed = 0;
  int aborted = 0;
  CollisionCounts collisions;
  std::int64_t lost = 0;
  std::int64_t declared_lost = 0;
  for (const RobotMetrics& r : m.robots) {
    if (!r.navigation) continue;
    started += r.navigation->missions_started;
    completed += r.navigation->missions_completed;
    aborted += r.navigation->missions_aborted_total();
    collisions += r.collisions_by_class;
    if (r.localization) lost += r.localization->lost_situations;
    if (r.localization) declared_lost += r.localization->declared_lost_situations;
  }
  Json j = {{"missions_started", started},
            {"missions_completed", completed},
            {"missions_completed_ratio",
             started > 0 ? RoundForJson(static_cast<double>(completed) / started, 4) : 0.0},
            // Missions the run ended in the middle of are neither: the ratio
            // of those it saw to an end is the fair one for a short run.
            {"missions_in_progress", started - completed - aborted},
            {"missions_completed_of_ended_ratio",
             completed + aborted > 0
                 ? RoundForJson(static_cast<double>(completed) / (completed + aborted), 4)
                 : 0.0},
            {"collisions", CollisionCountsToJson(collisions)},
            {"lost_situations", lost},
            {"declared_lost_situations", declared_lost}};
  if (m.fleet) j["coordination"] = FleetCoordinationJson(m);
  return j;
}

Json RobotJson(const RobotMetrics& r) {
  Json j = {{"model", r.model},
            {"distance_m", RoundForJson(r.distance_m)},
            {"collisions", r.collisions},
            {"collisions_by_class", CollisionCountsToJson(r.collisions_by_class)},
            {"bumper_presses", r.bumper_presses},
            {"scans", r.scans},
            {"odometry_final_error",
             {{"position_m", RoundForJson(r.odometry_final_position_error_m)},
              {"heading_rad", RoundForJson(r.odometry_final_heading_error_rad)}}}};
  if (r.localization) j["localization"] = LocalizationJson(*r.localization);
  if (r.relocalization) j["relocalization"] = RelocalizationJson(*r.relocalization);
  if (!r.estimator_counters.empty()) {
    Json counters = Json::object();
    for (const auto& [name, count] : r.estimator_counters) counters[name] = count;
    j["estimator_counters"] = std::move(counters);
  }
  if (r.shadow) {
    Json shadow = {{"method", r.shadow->method},
                   {"localization", LocalizationJson(r.shadow->localization)}};
    if (r.shadow->relocalization) {
      shadow["relocalization"] = RelocalizationJson(*r.shadow->relocalization);
    }
    j["shadow"] = std::move(shadow);
  }
  if (r.route) {
    j["route"] = {
        {"stops", r.route->stops},
        {"length_m", RoundForJson(r.route->length_m, 3)},
        {"done", r.route->done},
        {"done_at_s", r.route->done ? RoundForJson(r.route->done_at_s, 3) : r.route->done_at_s}};
  }
  if (r.navigation) j["navigation"] = NavigationJson(*r.navigation, r.collisions_by_class);
  if (r.fleet) {
    Json fleet = ProximityJson(r.fleet->proximity);
    fleet["bytes_up"] = r.fleet->bytes_up;
    fleet["bytes_down"] = r.fleet->bytes_down;
    fleet["messages"] = r.fleet->messages;
    j["fleet"] = fleet;
  }
  if (r.social) j["social"] = SocialJson(*r.social);
  if (r.day) j["run_table"] = RobotDayToJson(*r.day);
  return j;
}

}  // namespace

double RoundForJson(double value, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, value == 0.0 ? 0.0 : value);  // no "-0.000"
  return std::stod(buf);
}

double RunMetrics::bodies_distance_m() const {
  double sum = 0.0;
  for (const BodyMetrics& b : bodies) sum += b.distance_m;
  return sum;
}

std::int64_t RunMetrics::bodies_collisions() const {
  std::int64_t sum = 0;
  for (const BodyMetrics& b : bodies) sum += b.collisions;
  return sum;
}

std::int64_t RunMetrics::scans() const {
  std::int64_t sum = 0;
  for (const RobotMetrics& r : robots) sum += r.scans;
  return sum;
}

std::int64_t RunMetrics::fallback_scans() const {
  std::int64_t sum = 0;
  for (const RobotMetrics& r : robots) sum += r.fallback_scans;
  return sum;
}

std::int64_t RunMetrics::events() const {
  std::int64_t sum = 0;
  for (const auto& [type, n] : event_counts) sum += n;
  return sum;
}

bool RunMetrics::any_relocalization() const {
  for (const RobotMetrics& r : robots) {
    if (r.relocalization) return true;
  }
  return false;
}

bool RunMetrics::any_navigation() const {
  for (const RobotMetrics& r : robots) {
    if (r.navigation) return true;
  }
  return false;
}

nlohmann::ordered_json MetricsToJson(const RunMetrics& m) {
  Json j;
  j["schema_version"] = RunMetrics::kSchemaVersion;
  j["scenario"] = m.scenario;
  j["seed"] = m.seed;
  j["pavilion_version"] = m.pavilion_version;
  j["world"] = m.world;
  j["sim_duration_s"] = m.sim_duration_s;
  j["physics"] = {{"rate_hz", m.physics_rate_hz}, {"ticks", m.ticks}};
  if (m.interrupted) j["interrupted"] = true;
  if (!m.ended_early.empty()) j["ended_early"] = m.ended_early;
  if (!m.bodies.empty()) {
    Json bodies;
    for (const BodyMetrics& b : m.bodies) {
      bodies[b.id] = {{"distance_m", RoundForJson(b.distance_m)}, {"collisions", b.collisions}};
    }
    j["bodies_summary"] = {{"count", static_cast<int>(m.bodies.size())},
                           {"distance_m", RoundForJson(m.bodies_distance_m())},
                           {"collisions", m.bodies_collisions()}};
    j["bodies"] = bodies;
  }
  if (!m.robots.empty()) {
    Json robots;
    for (const RobotMetrics& r : m.robots) robots[r.id] = RobotJson(r);
    j["robots"] = robots;
    // Scans the planar backend handed to Bullet (tilted beam planes, bodies
    // the plane does not cut exactly); a function of scenario and seed.
    j["laser"] = {
        {"backend", m.laser_backend}, {"scans", m.scans()}, {"fallback_scans", m.fallback_scans()}};
  }
  if (m.any_navigation()) j["fleet"] = FleetJson(m);
  if (m.any_relocalization()) j["fleet"]["relocalization"] = FleetRelocalizationJson(m);
  if (const std::optional<RunTable> table = MakeRunTable(m))
    j["run_table"] = RunTableToJson(*table);
  if (m.crowd) j["crowd"] = CrowdJson(*m.crowd);
  if (m.realism) {
    j["realism"] = {{"profile", "realistic"},
                    {"clutter_objects", m.realism->clutter_objects},
                    {"doors_opened", m.realism->doors_opened},
                    {"carpet_squares", m.realism->carpet_squares}};
  }
  j["events"] = m.event_counts;
  return j;
}

}  // namespace pavilion::scenarios
