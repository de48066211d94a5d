#pragma once

// Judging a run by its scenario's expectations (expectation.h): the metric
// ones on metrics.json at the end, the event ones (never, within) on the
// events as the run emits them, with each robot's motion time.

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scenarios/expect/expectation.h"
#include "scenarios/expect/expectation_result.h"

namespace pavilion::scenarios {

// Watches a run's events for the `never` and `within` expectations.
class EventExpectationMonitor {
 public:
  // `robot_ids` in the order AddMotion indexes them.
  EventExpectationMonitor(const std::vector<Expectation>& expectations,
                          std::vector<std::string> robot_ids);
  // Every event record of the run, in order (fields after time_s and type).
  void OnEvent(double time_s, const std::string& type, const nlohmann::ordered_json& fields);
  // Robot `k` moved (true speed above kMovingSpeedMps) for dt_s.
  void AddMotion(std::size_t k, double dt_s) { motion_s_[k] += dt_s; }

  // The event expectation at `index` of the list, judged at the run's end.
  ExpectationResult Judge(std::size_t index, const Expectation& e) const;

 private:
  struct Anchor {
    double time_s = 0.0;
    double clock_s = 0.0;  // motion or simulated time at the anchor
  };
  struct State {
    std::int64_t matches = 0;  // never: offending events
    std::string first;         // never: the first one; within: the first late or missed anchor
    std::int64_t anchors = 0;  // within
    std::int64_t met = 0;
    double worst_s = 0.0;                             // within: the longest wait that was met
    std::map<std::string, std::vector<Anchor>> open;  // within: by robot
  };
  double Clock(const std::string& robot, bool motion, double time_s) const;

  const std::vector<Expectation>& expectations_;
  std::vector<std::string> robot_ids_;
  std::vector<double> motion_s_;
  std::vector<State> states_;  // by expectation index
  double last_time_s_ = 0.0;
};

// Every expectation's result, in the list's order.
ExpectationResults EvaluateExpectations(const std::vector<Expectation>& expectations,
                                        const nlohmann::ordered_json& metrics,
                                        const EventExpectationMonitor& monitor);

// expectations.json: {"passed": bool, "failures": n, "results": [...]}.
nlohmann::ordered_json ExpectationsToJson(const ExpectationResults& results);
// Its inverse (pavilion test and sweeps read the runs' files); throws
// nlohmann::json::exception for a file of another shape.
ExpectationResults ExpectationsFromJson(const nlohmann::json& json);

// The pass/fail table `pavilion run` prints: status, expectation, measured, bound.
std::string FormatExpectationTable(const ExpectationResults& results);

// A figure for people: up to 4 significant digits ("0.0312", "17.5", "1200").
std::string FormatFigure(double value);

}  // namespace pavilion::scenarios
