#pragma once

// sweep.html: one self-contained page (Chart.js inlined) with a sweep's
// statistics — plots of the main metrics against the first grid parameter
// (mean and its 95 % interval as a band, one line per combination of the other
// parameters), or, without a grid, the per-seed values of a few key metrics;
// the expectations' pass rates; and the table of every metric.

#include <string>
#include <vector>

#include "scenarios/batch/sweep_aggregate.h"
#include "scenarios/batch/sweep_plan.h"

namespace pavilion::scenarios {

// The metrics the page plots: those named like the key figures of
// ../shared/docs/metrics.md (position_rmse_m, anees, lost_situations, ...)
// first, then others; only metrics that differ between runs, at most `max_count`.
std::vector<std::string> KeyMetrics(const SweepAggregate& aggregate, std::size_t max_count);

// The page. Throws std::runtime_error when Chart.js is not installed.
std::string SweepHtml(const SweepPlan& plan, const SweepAggregate& aggregate,
                      const SweepStatus& status);

}  // namespace pavilion::scenarios
