#include "scenarios/config/run_reference.h"

#include <algorithm>

#include "scenarios/metrics/run_table.h"

namespace pavilion::scenarios {
namespace {

void Leaves(const nlohmann::ordered_json& node, const std::string& prefix,
            std::vector<std::string>* out) {
  if (node.is_object()) {
    for (const auto& [key, child] : node.items()) {
      Leaves(child, prefix.empty() ? key : prefix + "." + key, out);
    }
  } else if (node.is_number()) {
    out->push_back(prefix);
  }
}

}  // namespace

const double* RunReference::Find(const std::string& path) const {
  for (const auto& [key, value] : values) {
    if (key == path) return &value;
  }
  return nullptr;
}

std::vector<std::string> RunTablePaths() {
  std::vector<std::string> paths;
  Leaves(RunTableToJson(RunTable{}), "", &paths);
  return paths;
}

void ReadRunReference(YamlDocument* doc, MapReader& top, RunReference* out) {
  YAML::Node node = top.Child("reference");
  if (!node.IsDefined() || node.IsNull()) return;
  MapReader m(doc, node, top.PathOf("reference"));
  if (!m.valid()) return;
  out->source = m.RequiredString("source").value_or("");
  YAML::Node table = m.Child("run_table", true);
  if (table.IsDefined() && !table.IsMap()) {
    doc->Error(table, m.PathOf("run_table"), "expected a mapping of run table figures");
  } else if (table.IsDefined()) {
    MapReader figures(doc, table, m.PathOf("run_table"));
    const std::vector<std::string> known = RunTablePaths();
    for (const auto& item : table) {
      const std::string key = item.first.as<std::string>();
      if (std::find(known.begin(), known.end(), key) == known.end()) {
        doc->Error(item.first, figures.PathOf(key),
                   "not a figure of the run table (metrics.json run_table, e.g. "
                   "distance_km, missions.started, collisions.visitor)");
        figures.Child(key);  // reported here, not again as an unknown key
        continue;
      }
      if (auto value = figures.RequiredNumber(key, -1e15, 1e15))
        out->values.emplace_back(key, *value);
    }
    figures.Finish();
  }
  m.Finish();
}

}  // namespace pavilion::scenarios
