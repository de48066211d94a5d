#pragma once

// A scenario's `expect:` block (issue 17): what a run must show for the
// scenario, as a test, to pass. Three kinds:
//
//   - robots.robox_1.localization.position_rmse_m < 0.05     a metrics.json figure
//   - {any: "robots.*.navigation.missions_completed >= 3"}    ... over a wildcard (all by default)
//   - {never: {event: collision, with: visitor}}              no such event in the run
//   - {within: {after: kidnap, motion_s: 30, event: relocalized, correct: true}}
//
// `within` pairs each `after` event with the first matching `event` of the same
// robot, counting the robot's motion time (true speed above kMovingSpeedMps, as
// the relocalization figures count it) or simulated time (`time_s`).
// Metric paths are checked at load time against the typed RunMetrics
// (metrics_schema.h); event names against the types a run emits.

#include <nlohmann/json.hpp>
#include <string>
#include <variant>
#include <vector>

namespace pavilion::scenarios {

enum class Comparison { kLess, kLessEqual, kGreater, kGreaterEqual, kEqual, kNotEqual };
const char* ToString(Comparison c);  // "<", "<=", ...
bool Compare(double measured, Comparison c, double bound);

// Fields an event record must have, each equal to the given JSON value
// (`robot: robox_1`, `with: visitor`, `correct: true`).
struct EventFilter {
  std::string type;
  nlohmann::ordered_json fields = nlohmann::ordered_json::object();
  bool Matches(const std::string& type, const nlohmann::ordered_json& record) const;
  std::string ToString() const;  // "collision with=visitor"
};

struct MetricExpectation {
  std::vector<std::string> path;  // "robots", "*", "localization", "position_rmse_m"
  Comparison comparison = Comparison::kLess;
  double bound = 0.0;  // booleans compare as 0 / 1
  bool any = false;    // over the wildcards: any match passes (default: all must)
};

struct NeverExpectation {
  EventFilter event;
};

struct WithinExpectation {
  EventFilter after;  // the anchor; its record names the robot
  EventFilter event;  // what must follow for the same robot
  double limit_s = 0.0;
  bool motion_time = true;  // motion_s (true) or time_s (false)
};

struct Expectation {
  std::string text;  // as written, for tables and JUnit
  int line = 0;      // in the scenario file
  std::variant<MetricExpectation, NeverExpectation, WithinExpectation> kind;
};

}  // namespace pavilion::scenarios
