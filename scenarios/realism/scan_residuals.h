#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "core/types/sensor_data.h"
#include "scenarios/datasets/carmen_log.h"

namespace pavilion::scenarios {

// Error statistics of a laser's scans measured from the scans alone, without
// ground truth, to compare a real SICK log with simulated scans (issue 20,
// docs/carmen_logs.md "Residuals of long walls"). The thesis (§2.2.1) lists the
// laser's errors: range noise and quantization (§2.2.1.1), mixed pixels at
// depth discontinuities and missing returns on dark, specular or distant
// surfaces (§2.2.1.2), and systematic, surface-dependent errors correlated
// along a wall (§2.2.1.3). Long straight walls show the first and the last as
// the scatter of their readings about a fitted line; the no-return and
// isolated-reading fractions show the second.

// The range quantization of a set of scans, measured from the data.
struct RangeStepEstimate {
  // The largest candidate step s (metres; the 1-2-2.5-5 series from 0.1 mm to
  // 10 cm) such that at least kRangeStepMinOnGridFraction (99 %) of the valid
  // ranges are integer multiples of s within max(2 µm, 1 % of s); 0 when no
  // candidate qualifies (ranges finer than 0.1 mm, or unquantized).
  double step_m = 0.0;
  // Fraction of the valid ranges on the grid of step_m (0 when step_m is 0).
  double on_grid_fraction = 0.0;
  std::int64_t valid_readings = 0;  // valid readings examined
};

// Minimum fraction of valid ranges on a step's grid for DetectRangeStep to accept it.
inline constexpr double kRangeStepMinOnGridFraction = 0.99;

// Measures the range step of `scans` (see RangeStepEstimate). Deterministic.
// A random, unquantized range lands on a grid with probability 2·tolerance/s
// (≤ 4 %), far below the 99 % required; ranges stored as 32-bit floats (as in
// scans.bin: rounding error ≤ 2 µm below 32 m) stay within the tolerance.
RangeStepEstimate DetectRangeStep(std::span<const core::LaserScan> scans);

struct ScanResidualOptions {
  // Segmentation of each scan into long walls (defaults: chains broken at
  // 0.3 m, iterative end-point fit split above 5 cm, >= 20 points, >= 2 m).
  CarmenStraightnessOptions straightness;
  // Every valid range is rounded to the nearest multiple of this before the
  // analysis (to compare 1 mm simulated scans with a log's 5 cm step); a range
  // that rounds to 0 becomes a no-return. Metres, finite, >= 0; 0: no rounding.
  double requantize_step_m = 0.0;
  // Only every keep_every-th reading is kept (0, k, 2k, ...): simulated 0.5°
  // scans thinned to a log's 1° spacing, so that runs, gaps and isolated
  // readings are counted at the same angular resolution. >= 1; 1: all.
  int keep_every = 1;
  // Readings with range_m >= this are no-returns (in addition to those the
  // reader marked invalid; CARMEN's reader already drops >= 30 m). Metres, > 0,
  // may be +infinity (no extra cut). Applied before requantization.
  double max_range_m = std::numeric_limits<double>::infinity();
  // A valid reading is isolated when neither neighbour (the readings just
  // before and after it in the scan) is a valid reading within this range
  // difference: each neighbour is missing (scan edge), invalid, or differs in
  // range by more than this. Metres, > 0; the default is the segmentation's
  // break distance.
  double isolated_jump_m = 0.3;
  // Edges of the range bins, ascending, first >= 0, at least two: bin k holds
  // the run readings with edges[k] <= range < edges[k+1], the last bin also
  // range == its upper edge. Readings beyond the last edge are in no bin.
  std::vector<double> bin_edges_m = {0.0, 2.0, 4.0, 8.0};

  // Throws std::invalid_argument naming the field.
  void Validate() const;
};

// Perpendicular residuals of the readings of long walls within a range bin.
struct ResidualBin {
  double min_range_m = 0.0;  // bin edges (see ScanResidualOptions::bin_edges_m)
  double max_range_m = 0.0;
  std::int64_t count = 0;     // wall readings in the bin
  double median_abs_m = 0.0;  // median of |residual| (0 when empty)
  double p90_abs_m = 0.0;     // 90th percentile of |residual| (0 when empty)
  double rms_m = 0.0;         // sqrt(mean residual²) (0 when empty)
};

// The statistics of ComputeScanResiduals. Definitions:
// - no-return: a reading that is not valid (after max_range_m and
//   requantization); no_return_fraction = no-returns / all readings.
// - isolated: see ScanResidualOptions::isolated_jump_m; isolated_fraction =
//   isolated readings / all readings (the same denominator as no-returns).
//   Mixed pixels, stray returns and lone hits through clutter are isolated.
// - wall residual: in each scan, FindStraightRuns (carmen_log.h) gives the long
//   straight runs; a total-least-squares line (minimizing perpendicular
//   distances, thesis eqs. 3.4-3.5 with equal weights) is fitted to each run's
//   points (range, bearing in the sensor frame), and each reading's residual is
//   its signed perpendicular distance to its run's line. A fit absorbs two
//   degrees of freedom: for a run of N readings with independent noise the
//   residuals' variance is about (N-2)/N of the noise's along the normal, i.e.
//   the range noise times cos(incidence).
// - percentiles: linear interpolation between order statistics (the p-th
//   percentile of sorted x_0..x_{n-1} is at fractional index p·(n-1)).
struct ScanResidualStatistics {
  std::int64_t scans = 0;
  std::int64_t readings = 0;    // all readings, valid or not
  std::int64_t no_returns = 0;  // invalid readings
  std::int64_t isolated = 0;    // isolated valid readings
  double no_return_fraction = 0.0;
  double isolated_fraction = 0.0;
  std::int64_t runs = 0;          // long walls found
  std::int64_t run_readings = 0;  // readings in them, in a bin or not
  std::vector<ResidualBin> bins;  // one per bin of ScanResidualOptions::bin_edges_m
  ResidualBin all;                // every run reading within the bins' span
};

// Computes the statistics above over all `scans`. Deterministic; the scans'
// own bearings are used (set a CARMEN log's angle step first). Throws
// std::invalid_argument for invalid options.
ScanResidualStatistics ComputeScanResiduals(std::span<const core::LaserScan> scans,
                                            const ScanResidualOptions& options = {});

// The scan with `options`' keep_every, max_range_m and requantize_step_m applied: the
// readings ComputeScanResiduals analyses.
core::LaserScan PrepareScanForResiduals(const core::LaserScan& scan,
                                        const ScanResidualOptions& options);

}  // namespace pavilion::scenarios
