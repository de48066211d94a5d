#pragma once

// The figures a run reports (../shared/docs/metrics.md): one typed value that
// the runner fills, metrics.json serializes (schema 1, in one place), and the
// report, the tests, scenario expectations and sweeps read.

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "nav/mission/mission.h"
#include "scenarios/metrics/collision_classes.h"
#include "scenarios/metrics/localization_tracker.h"
#include "scenarios/metrics/relocalization_tracker.h"
#include "scenarios/metrics/robot_proximity.h"
#include "scenarios/metrics/run_table.h"
#include "scenarios/metrics/social_navigation.h"

namespace pavilion::scenarios {

struct BodyMetrics {
  std::string id;
  double distance_m = 0.0;      // path length of the body's centre
  std::int64_t collisions = 0;  // contact begins with anything
};

struct RouteMetrics {
  std::vector<std::string> stops;
  double length_m = 0.0;
  bool done = false;
  double done_at_s = 0.0;  // the run's end when not done
};

// A fleet robot's share of the coordination (issue 15): how near it came to
// the others and the bytes it exchanged with the coordinator.
struct RobotFleetFigures {
  ProximityFigures proximity;
  std::int64_t bytes_up = 0;    // sent to the coordinator
  std::int64_t bytes_down = 0;  // received: the others' changed messages
  std::int64_t messages = 0;
};

// The fleet's (runs with two or more mission robots).
struct FleetRunFigures {
  bool coordination = false;  // a coordinator ran
  ProximityFigures proximity;
  std::int64_t ticks = 0;  // physics ticks, for bytes per robot and tick
};

struct RobotMetrics {
  std::string id;
  std::string model;
  double distance_m = 0.0;
  std::int64_t collisions = 0;
  CollisionCounts collisions_by_class;  // the same contacts by what was hit
  std::int64_t bumper_presses = 0;      // bumper readings with a zone pressed
  std::int64_t scans = 0;
  std::int64_t fallback_scans = 0;  // planar backend: scans cast partly with Bullet
  double odometry_final_position_error_m = 0.0;
  double odometry_final_heading_error_rad = 0.0;  // |wrapped|
  std::optional<LocalizationFigures> localization;
  // Robots that localize, in runs with a kidnap or a declared loss.
  std::optional<RelocalizationFigures> relocalization;
  // The estimator run in shadow on the same readings (`shadow: mcl`), judged
  // the same way.
  struct Shadow {
    std::string method;  // "mcl"
    LocalizationFigures localization;
    std::optional<RelocalizationFigures> relocalization;
  };
  std::optional<Shadow> shadow;
  std::optional<RouteMetrics> route;
  std::optional<nav::NavigationFigures> navigation;  // robots with a mission
  std::optional<RobotFleetFigures> fleet;            // robots of a fleet run
  // Runs with a crowd, once a visitor was on the floor (social_navigation.h).
  std::optional<SocialNavigationFigures> social;
  // Robots that localize: their share of the run table (run_table.h).
  std::optional<RobotDayFigures> day;
  // The estimator's own counts (global localization: tree nodes, limit hits,
  // falsifications), in its order; empty for estimators that keep none.
  std::vector<std::pair<std::string, std::int64_t>> estimator_counters;
};

struct RunMetrics {
  static constexpr int kSchemaVersion = 1;
  std::string scenario;
  std::uint64_t seed = 0;
  std::string pavilion_version;
  std::string world;
  double sim_duration_s = 0.0;
  double physics_rate_hz = 0.0;
  std::int64_t ticks = 0;
  // Ended early by SIGINT/SIGTERM: the figures cover sim_duration_s only.
  bool interrupted = false;
  // Ended early by the simulated world (ScenarioRun: a robot left the floor).
  std::string ended_early;
  std::vector<BodyMetrics> bodies;   // in world order
  std::vector<RobotMetrics> robots;  // in scenario order
  std::string laser_backend;
  std::map<std::string, std::int64_t> event_counts;  // by type
  std::optional<CrowdFigures> crowd;                 // runs with a crowd
  std::optional<FleetRunFigures> fleet;              // runs with two or more mission robots
  // `realism: realistic` runs (issue 20): what the profile added to the
  // surveyed world; absent under `ideal` (whose outputs stay as they were).
  struct RealismFigures {
    int clutter_objects = 0;
    std::vector<std::string> doors_opened;
    int carpet_squares = 0;
  };
  std::optional<RealismFigures> realism;

  double bodies_distance_m() const;
  std::int64_t bodies_collisions() const;
  std::int64_t scans() const;
  std::int64_t fallback_scans() const;
  std::int64_t events() const;
  bool any_navigation() const;
  bool any_relocalization() const;
};

// metrics.json (schema 1): numbers rounded as the file has always had them.
nlohmann::ordered_json MetricsToJson(const RunMetrics& metrics);
// A number as metrics.json holds it: rounded to `decimals` places.
double RoundForJson(double value, int decimals = 6);

}  // namespace pavilion::scenarios
