#pragma once

// Aggregation of a sweep's runs (docs/sweep.md): every numeric leaf of the runs'
// metrics.json per grid cell — n, mean, sample standard deviation, min, max and
// the 95 % Student-t interval of the mean — and the pass rates of the runs'
// expectations. Written to sweep.json and sweep.csv; sweep_html.h draws them.

#include <cstddef>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "scenarios/batch/sweep_plan.h"

namespace pavilion::scenarios {

// The regularized incomplete beta function I_x(a, b), a, b > 0, x in [0, 1]
// (continued fraction, Numerical Recipes §6.4). Throws std::invalid_argument.
double RegularizedIncompleteBeta(double a, double b, double x);

// The CDF of Student's t distribution with `dof` > 0 degrees of freedom.
double StudentTCdf(double t, double dof);

// The p-quantile of Student's t distribution (p in (0, 1), dof > 0), by
// inverting StudentTCdf to double precision: t(0.975, 4) = 2.776.
double StudentTQuantile(double p, double dof);

// The statistics of one metric over the runs of one cell.
struct MetricSummary {
  std::size_t n = 0;
  double mean = 0.0;
  std::optional<double> std;  // sample standard deviation (n - 1); none for n = 1
  double min = 0.0;
  double max = 0.0;
  std::optional<double> ci95_low;  // mean -+ t(0.975, n-1) std / sqrt(n); none for n = 1
  std::optional<double> ci95_high;
};

// Statistics of `values` (n >= 1).
MetricSummary Summarize(const std::vector<double>& values);

// The numeric leaves of a metrics.json, by path ("robots.robox_1.distance_m").
// Objects nest by key; arrays by each element's "id" when every element is an
// object with a string or integer id, else by index. Booleans, strings and
// nulls are left out, as are the top-level "schema_version" and "seed" (not
// measurements).
std::map<std::string, double> FlattenMetrics(const nlohmann::json& metrics);

// What a finished run left in DIR/runs/<id>/.
struct RunRecord {
  std::size_t run = 0;                         // index into SweepPlan::runs
  std::map<std::string, double> metrics;       // FlattenMetrics of its metrics.json
  std::optional<nlohmann::json> expectations;  // its expectations.json, when written
};

// Reads a run folder's metrics.json and expectations.json. Throws
// std::runtime_error naming the file when metrics.json is missing or bad.
RunRecord ReadRunFolder(const std::string& folder, std::size_t run_index);

// One expectation's outcomes over a cell's runs.
struct ExpectationTally {
  std::string name;
  int line = 0;  // in the scenario file, 0 when not given
  int pass = 0;
  int fail = 0;
  int missing = 0;
};

struct CellAggregate {
  std::vector<std::size_t> runs;  // indices into SweepPlan::runs of the finished runs
  std::map<std::string, MetricSummary> metrics;
  std::map<std::string, std::vector<double>> values;  // per metric, in the order of `runs`
                                                      // (NaN where a run lacks it)
  int runs_with_expectations = 0;                     // runs that wrote expectations.json
  int runs_passed = 0;                                // of those, "passed": true
  std::vector<ExpectationTally> expectations;         // in the order first seen
};

struct SweepAggregate {
  std::vector<CellAggregate> cells;       // as SweepPlan::cells
  std::vector<std::string> metric_names;  // every metric of any cell, sorted
  bool any_expectations = false;          // some run wrote expectations.json
};

// Aggregates the finished runs (any order) cell by cell.
SweepAggregate AggregateRuns(const SweepPlan& plan, const std::vector<RunRecord>& runs);

// How the runs went, for sweep.json.
struct SweepStatus {
  std::size_t planned = 0;
  std::size_t finished = 0;
  std::vector<std::string> failed;   // run ids
  std::vector<std::string> not_run;  // run ids (interrupted or never started)
};

// sweep.json (docs/sweep.md).
nlohmann::ordered_json AggregateToJson(const SweepPlan& plan, const SweepAggregate& aggregate,
                                       const SweepStatus& status);

// sweep.csv: a header, then one row per cell x metric.
std::string AggregateToCsv(const SweepPlan& plan, const SweepAggregate& aggregate);

}  // namespace pavilion::scenarios
