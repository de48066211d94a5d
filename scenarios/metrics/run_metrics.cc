#include "scenarios/metrics/run_metrics.h"

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
          {"cycles_without_match", f.cycles_without_match},
          {"lost_situations", f.lost_situations}};
}

Json RobotJson(const RobotMetrics& r) {
  Json j = {{"model", r.model},
            {"distance_m", RoundForJson(r.distance_m)},
            {"collisions", r.collisions},
            {"bumper_presses", r.bumper_presses},
            {"scans", r.scans},
            {"odometry_final_error",
             {{"position_m", RoundForJson(r.odometry_final_position_error_m)},
              {"heading_rad", RoundForJson(r.odometry_final_heading_error_rad)}}}};
  if (r.localization) j["localization"] = LocalizationJson(*r.localization);
  if (r.route) {
    j["route"] = {
        {"stops", r.route->stops},
        {"length_m", RoundForJson(r.route->length_m, 3)},
        {"done", r.route->done},
        {"done_at_s", r.route->done ? RoundForJson(r.route->done_at_s, 3) : r.route->done_at_s}};
  }
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

nlohmann::ordered_json MetricsToJson(const RunMetrics& m) {
  Json j;
  j["schema_version"] = RunMetrics::kSchemaVersion;
  j["scenario"] = m.scenario;
  j["seed"] = m.seed;
  j["pavilion_version"] = m.pavilion_version;
  j["world"] = m.world;
  j["sim_duration_s"] = m.sim_duration_s;
  j["physics"] = {{"rate_hz", m.physics_rate_hz}, {"ticks", m.ticks}};
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
  j["events"] = m.event_counts;
  return j;
}

}  // namespace pavilion::scenarios
