#include "scenarios/expect/metrics_schema.h"

#include "scenarios/metrics/run_metrics.h"

namespace pavilion::scenarios {
namespace {

using Json = nlohmann::ordered_json;

std::string Join(const std::vector<std::string>& path, std::size_t n) {
  std::string s;
  for (std::size_t i = 0; i < n && i < path.size(); ++i) s += (i ? "." : "") + path[i];
  return s;
}

// Sections of metrics.json keyed by id, with the ids that may stand there.
const std::set<std::string>* IdsFor(const std::string& section, const MetricIds& ids) {
  if (section == "robots") return &ids.robots;
  if (section == "bodies") return &ids.bodies;
  if (section == "events") return &ids.events;
  return nullptr;
}

void LookUp(const Json& node, const std::vector<std::string>& path, std::size_t i,
            std::string prefix, std::vector<MetricValue>* out) {
  if (i == path.size()) {
    MetricValue v{prefix, false, 0.0};
    if (node.is_boolean()) {
      v.found = true;
      v.value = node.get<bool>() ? 1.0 : 0.0;
    } else if (node.is_number()) {
      v.found = true;
      v.value = node.get<double>();
    }
    out->push_back(v);
    return;
  }
  const std::string sep = prefix.empty() ? "" : ".";
  if (path[i] == "*" && node.is_object()) {
    if (node.empty()) out->push_back({prefix + sep + "*", false, 0.0});
    for (const auto& [key, child] : node.items()) {
      LookUp(child, path, i + 1, prefix + sep + key, out);
    }
    return;
  }
  if (!node.is_object() || !node.contains(path[i])) {
    std::string rest;
    for (std::size_t k = i; k < path.size(); ++k) rest += (rest.empty() ? "" : ".") + path[k];
    // An event type the run never emitted was counted zero times.
    const bool uncounted_event = i == 1 && path[0] == "events" && path.size() == 2;
    out->push_back({prefix + sep + rest, uncounted_event, 0.0});
    return;
  }
  LookUp(node.at(path[i]), path, i + 1, prefix + sep + path[i], out);
}

}  // namespace

const Json& MetricsSchema() {
  static const Json schema = [] {
    RunMetrics m;
    m.interrupted = true;
    m.ended_early.assign(1, '*');  // (GCC 12, -Wrestrict: as r.id below)
    m.bodies.push_back(BodyMetrics{"*"});
    RobotMetrics r;
    r.id.assign(1, '*');  // (GCC 12 warns falsely, -Wrestrict, on = "*")
    r.localization.emplace();
    r.relocalization.emplace();
    r.shadow = RobotMetrics::Shadow{"mcl", {}, RelocalizationFigures{}};
    r.route.emplace();
    r.navigation.emplace();
    r.social.emplace();
    r.day.emplace();
    r.estimator_counters = {{"*", 0}};
    m.robots.push_back(std::move(r));
    m.crowd.emplace();
    m.event_counts["*"] = 0;
    return MetricsToJson(m);
  }();
  return schema;
}

std::string CheckMetricPath(const std::vector<std::string>& path, const MetricIds& ids) {
  const Json* node = &MetricsSchema();
  for (std::size_t i = 0; i < path.size(); ++i) {
    const std::string here = Join(path, i + 1);
    if (!node->is_object()) {
      return Join(path, i) + (node->is_array() ? ": is a list; its items cannot be addressed"
                                               : ": is a figure; nothing lies below it");
    }
    const std::string& key = path[i];
    if (node->size() == 1 && node->contains("*")) {
      // A section keyed by id: robots, bodies, events, estimator counters.
      const std::set<std::string>* known = i > 0 ? IdsFor(path[i - 1], ids) : nullptr;
      if (key != "*" && known && !known->contains(key)) {
        return here + ": no " + path[i - 1] + " entry '" + key + "' in the scenario";
      }
      node = &node->at("*");
      continue;
    }
    if (key == "*") return here + ": '*' stands only for robot, body or event ids";
    if (!node->contains(key)) {
      std::string names;
      for (const auto& [name, child] : node->items()) names += (names.empty() ? "" : ", ") + name;
      return here + ": unknown metric (known here: " + names + ")";
    }
    node = &node->at(key);
  }
  if (node->is_object() || node->is_array()) {
    return Join(path, path.size()) + ": names a section, not a figure";
  }
  if (!node->is_number() && !node->is_boolean()) {
    return Join(path, path.size()) + ": is text, not a number";
  }
  return "";
}

std::vector<MetricValue> LookUpMetric(const Json& metrics, const std::vector<std::string>& path) {
  std::vector<MetricValue> out;
  LookUp(metrics, path, 0, "", &out);
  return out;
}

}  // namespace pavilion::scenarios
