#include "scenarios/realism/scan_residuals.h"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pavilion::scenarios {
namespace {

// Candidate range steps of DetectRangeStep, metres, largest first: the 1-2-2.5-5
// series from 10 cm down to 0.1 mm (SICK LMS 200: 1 mm or 1 cm in mm mode, 5 cm
// in some loggers' cm output; simulated scans: the laser's range_resolution_m).
constexpr std::array<double, 12> kCandidateStepsM = {0.1,   0.05,  0.025, 0.02,   0.01, 0.005,
                                                     0.002, 0.001, 5e-4,  2.5e-4, 2e-4, 1e-4};
// A range is on a step's grid within max(this, kOnGridRelativeTolerance·step).
constexpr double kOnGridAbsoluteToleranceM = 2e-6;
constexpr double kOnGridRelativeTolerance = 0.01;
// Percentiles reported per bin.
constexpr double kMedian = 0.5;
constexpr double kP90 = 0.9;

bool OnGrid(double range_m, double step_m) {
  const double tolerance = std::max(kOnGridAbsoluteToleranceM, kOnGridRelativeTolerance * step_m);
  return std::abs(range_m - step_m * std::round(range_m / step_m)) <= tolerance;
}

// The p-quantile of `values` (reordered), by linear interpolation between order
// statistics; 0 for no values.
double Quantile(std::vector<double>* values, double p) {
  if (values->empty()) return 0.0;
  const double position = p * static_cast<double>(values->size() - 1);
  const auto lower = static_cast<std::size_t>(std::floor(position));
  std::nth_element(values->begin(), values->begin() + static_cast<std::ptrdiff_t>(lower),
                   values->end());
  const double low = (*values)[lower];
  if (lower + 1 >= values->size()) return low;
  const double high =
      *std::min_element(values->begin() + static_cast<std::ptrdiff_t>(lower) + 1, values->end());
  return low + (position - static_cast<double>(lower)) * (high - low);
}

// Summarizes the absolute residuals `abs_m` and their sum of squares.
ResidualBin Summarize(double min_range_m, double max_range_m, std::vector<double>* abs_m,
                      double sum_squares) {
  ResidualBin bin;
  bin.min_range_m = min_range_m;
  bin.max_range_m = max_range_m;
  bin.count = static_cast<std::int64_t>(abs_m->size());
  if (abs_m->empty()) return bin;
  bin.rms_m = std::sqrt(sum_squares / static_cast<double>(bin.count));
  bin.median_abs_m = Quantile(abs_m, kMedian);
  bin.p90_abs_m = Quantile(abs_m, kP90);
  return bin;
}

Eigen::Vector2d PointOf(const core::LaserReading& r) {
  return {r.range_m * std::cos(r.bearing_rad), r.range_m * std::sin(r.bearing_rad)};
}

// Signed perpendicular residuals of the total-least-squares line through the
// readings `indices` of `readings` (the normal is the eigenvector of the
// scatter matrix's smaller eigenvalue).
void LineResiduals(const std::vector<core::LaserReading>& readings, const std::vector<int>& indices,
                   std::vector<double>* residuals_m) {
  residuals_m->clear();
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (int i : indices) mean += PointOf(readings[static_cast<std::size_t>(i)]);
  mean /= static_cast<double>(indices.size());
  double sxx = 0.0, syy = 0.0, sxy = 0.0;
  for (int i : indices) {
    const Eigen::Vector2d d = PointOf(readings[static_cast<std::size_t>(i)]) - mean;
    sxx += d.x() * d.x();
    syy += d.y() * d.y();
    sxy += d.x() * d.y();
  }
  // Direction of the line: angle of the larger eigenvector; the normal is
  // perpendicular to it.
  const double direction_rad = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
  const Eigen::Vector2d normal(-std::sin(direction_rad), std::cos(direction_rad));
  for (int i : indices) {
    residuals_m->push_back(normal.dot(PointOf(readings[static_cast<std::size_t>(i)]) - mean));
  }
}

// Whether readings[i] (valid) has a valid neighbour j within `jump_m` in range.
bool HasCloseNeighbour(const std::vector<core::LaserReading>& readings, std::size_t i,
                       double jump_m) {
  const auto close = [&](std::size_t j) {
    return readings[j].valid && std::abs(readings[j].range_m - readings[i].range_m) <= jump_m;
  };
  return (i > 0 && close(i - 1)) || (i + 1 < readings.size() && close(i + 1));
}

// The bin of a reading at `range_m`, or -1 beyond the edges.
int BinOf(const std::vector<double>& edges_m, double range_m) {
  if (range_m < edges_m.front() || range_m > edges_m.back()) return -1;
  const auto upper = std::upper_bound(edges_m.begin(), edges_m.end(), range_m);
  const int bin = static_cast<int>(upper - edges_m.begin()) - 1;
  return std::min(bin, static_cast<int>(edges_m.size()) - 2);
}

}  // namespace

RangeStepEstimate DetectRangeStep(std::span<const core::LaserScan> scans) {
  std::vector<double> ranges_m;
  for (const core::LaserScan& scan : scans) {
    for (const core::LaserReading& r : scan.readings) {
      if (r.valid && std::isfinite(r.range_m)) ranges_m.push_back(r.range_m);
    }
  }
  RangeStepEstimate estimate;
  estimate.valid_readings = static_cast<std::int64_t>(ranges_m.size());
  if (ranges_m.empty()) return estimate;
  for (const double step_m : kCandidateStepsM) {
    const auto on_grid = std::count_if(ranges_m.begin(), ranges_m.end(),
                                       [&](double r) { return OnGrid(r, step_m); });
    const double fraction = static_cast<double>(on_grid) / static_cast<double>(ranges_m.size());
    if (fraction >= kRangeStepMinOnGridFraction) {
      estimate.step_m = step_m;
      estimate.on_grid_fraction = fraction;
      return estimate;
    }
  }
  return estimate;
}

void ScanResidualOptions::Validate() const {
  straightness.Validate();
  if (!std::isfinite(requantize_step_m) || requantize_step_m < 0.0) {
    throw std::invalid_argument("ScanResidualOptions.requantize_step_m must be finite and >= 0");
  }
  if (keep_every < 1) throw std::invalid_argument("ScanResidualOptions.keep_every must be >= 1");
  if (std::isnan(max_range_m) || max_range_m <= 0.0) {
    throw std::invalid_argument("ScanResidualOptions.max_range_m must be > 0");
  }
  if (!std::isfinite(isolated_jump_m) || isolated_jump_m <= 0.0) {
    throw std::invalid_argument("ScanResidualOptions.isolated_jump_m must be finite and > 0");
  }
  if (bin_edges_m.size() < 2 || !std::isfinite(bin_edges_m.front()) || bin_edges_m.front() < 0.0) {
    throw std::invalid_argument(
        "ScanResidualOptions.bin_edges_m must hold at least two edges, the first >= 0");
  }
  for (std::size_t k = 1; k < bin_edges_m.size(); ++k) {
    if (!std::isfinite(bin_edges_m[k]) || bin_edges_m[k] <= bin_edges_m[k - 1]) {
      throw std::invalid_argument(
          "ScanResidualOptions.bin_edges_m must be finite and strictly ascending");
    }
  }
}

core::LaserScan PrepareScanForResiduals(const core::LaserScan& scan,
                                        const ScanResidualOptions& options) {
  core::LaserScan out = scan;
  if (options.keep_every > 1) {
    out.readings.clear();
    for (std::size_t i = 0; i < scan.readings.size(); i += options.keep_every) {
      out.readings.push_back(scan.readings[i]);
    }
  }
  for (core::LaserReading& r : out.readings) {
    if (!r.valid) continue;
    if (!std::isfinite(r.range_m) || r.range_m <= 0.0 || r.range_m >= options.max_range_m) {
      r.valid = false;
      continue;
    }
    if (options.requantize_step_m > 0.0) {
      r.range_m = options.requantize_step_m * std::round(r.range_m / options.requantize_step_m);
      if (r.range_m <= 0.0) r.valid = false;
    }
  }
  return out;
}

ScanResidualStatistics ComputeScanResiduals(std::span<const core::LaserScan> scans,
                                            const ScanResidualOptions& options) {
  options.Validate();
  const std::size_t num_bins = options.bin_edges_m.size() - 1;
  std::vector<std::vector<double>> abs_per_bin(num_bins);
  std::vector<double> squares_per_bin(num_bins, 0.0);
  std::vector<double> residuals_m;
  ScanResidualStatistics stats;
  for (const core::LaserScan& raw : scans) {
    const core::LaserScan scan = PrepareScanForResiduals(raw, options);
    const std::vector<core::LaserReading>& readings = scan.readings;
    ++stats.scans;
    stats.readings += static_cast<std::int64_t>(readings.size());
    for (std::size_t i = 0; i < readings.size(); ++i) {
      if (!readings[i].valid) {
        ++stats.no_returns;
      } else if (!HasCloseNeighbour(readings, i, options.isolated_jump_m)) {
        ++stats.isolated;
      }
    }
    for (const std::vector<int>& run : FindStraightRuns(scan, options.straightness)) {
      ++stats.runs;
      stats.run_readings += static_cast<std::int64_t>(run.size());
      LineResiduals(readings, run, &residuals_m);
      for (std::size_t k = 0; k < run.size(); ++k) {
        const int bin =
            BinOf(options.bin_edges_m, readings[static_cast<std::size_t>(run[k])].range_m);
        if (bin < 0) continue;
        abs_per_bin[static_cast<std::size_t>(bin)].push_back(std::abs(residuals_m[k]));
        squares_per_bin[static_cast<std::size_t>(bin)] += residuals_m[k] * residuals_m[k];
      }
    }
  }
  if (stats.readings > 0) {
    stats.no_return_fraction =
        static_cast<double>(stats.no_returns) / static_cast<double>(stats.readings);
    stats.isolated_fraction =
        static_cast<double>(stats.isolated) / static_cast<double>(stats.readings);
  }
  std::vector<double> all_abs;
  double all_squares = 0.0;
  for (std::size_t b = 0; b < num_bins; ++b) {
    all_abs.insert(all_abs.end(), abs_per_bin[b].begin(), abs_per_bin[b].end());
    all_squares += squares_per_bin[b];
    stats.bins.push_back(Summarize(options.bin_edges_m[b], options.bin_edges_m[b + 1],
                                   &abs_per_bin[b], squares_per_bin[b]));
  }
  stats.all =
      Summarize(options.bin_edges_m.front(), options.bin_edges_m.back(), &all_abs, all_squares);
  return stats;
}

}  // namespace pavilion::scenarios
