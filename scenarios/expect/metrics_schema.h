#pragma once

// Which metrics.json paths exist, from the typed RunMetrics itself: a run's
// metrics with every optional section present, serialized by MetricsToJson,
// is the schema expectations are checked against (no hand-kept list).

#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

namespace pavilion::scenarios {

// Ids that may stand in a path where metrics.json keys a section by id.
struct MetricIds {
  std::set<std::string> robots;
  std::set<std::string> bodies;
  std::set<std::string> events;  // event types a run can emit
};

// The full metrics.json of a run with one robot, one body and every section,
// with "*" standing for the robot, body and estimator-counter ids.
const nlohmann::ordered_json& MetricsSchema();

// Empty when `path` names a figure (a number or a boolean) of metrics.json
// for these ids; else why not, e.g. "robots.robox_9: no robot robox_9 in the
// scenario" or "robots.*.localization: names a section, not a figure".
std::string CheckMetricPath(const std::vector<std::string>& path, const MetricIds& ids);

// The values at `path` in a run's metrics.json, with "*" expanded: one entry
// per matching key path; `found` false where the path stops early (a section
// the run left out).
struct MetricValue {
  std::string path;  // with the wildcards filled in
  bool found = false;
  double value = 0.0;  // booleans as 0 / 1
};
std::vector<MetricValue> LookUpMetric(const nlohmann::ordered_json& metrics,
                                      const std::vector<std::string>& path);

}  // namespace pavilion::scenarios
