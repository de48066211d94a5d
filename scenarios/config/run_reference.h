#pragma once

// A scenario's `reference:` block (issue 21): the figures of a real run the
// scenario re-enacts — thesis Table 4.3 for the Computer 2000 run, Expo.02's
// statistics for the exhibition day — keyed by the run table's paths
// (metrics.json `run_table`), so that the report sets ours beside them.
//
//   reference:
//     source: thesis Table 4.3 (Computer 2000, 28 h)
//     run_table: {hours: 28, distance_km: 5.013, missions.started: 724}

#include <string>
#include <utility>
#include <vector>

#include "scenarios/config/yaml_reader.h"

namespace pavilion::scenarios {

struct RunReference {
  std::string source;  // where the figures come from
  // A run_table path (dotted, as metrics.json holds it) and its value, in file order.
  std::vector<std::pair<std::string, double>> values;

  bool empty() const { return values.empty(); }
  // The value at `path`, if the reference gives one.
  const double* Find(const std::string& path) const;
};

// Reads `reference: {source, run_table}`; a path that is not a figure of the
// run table, or a value that is not a number, is an error naming its key.
void ReadRunReference(YamlDocument* doc, MapReader& top, RunReference* out);

// The numeric leaves of the run table, as dotted paths (for checking keys).
std::vector<std::string> RunTablePaths();

}  // namespace pavilion::scenarios
