#pragma once

#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "core/types/sensor_data.h"
#include "scenarios/realism/scan_residuals.h"

namespace pavilion::scenarios {

// The range step and wall residuals of one real log (issue 20).
struct LogStatistics {
  std::string name;  // short name, e.g. "intel"
  int beams = 0;     // readings per scan (the most in any scan)
  RangeStepEstimate range_step;
  ScanResidualStatistics residuals;
};

// Computes a log's statistics: its measured range step and
// ComputeScanResiduals with `options` (requantize_step_m is used as given).
LogStatistics ComputeLogStatistics(const std::string& name, std::span<const core::LaserScan> scans,
                                   const ScanResidualOptions& options = {});

// The statistics of the CARMEN log at `path` with the angle step that
// DecideCarmenAngleStep picks, named by the file name without
// "-corrected", ".log" and ".gz" ("…/intel-corrected.log.gz" -> "intel").
// Throws InputError / std::runtime_error naming the file when it cannot be
// read or holds no FLASER scan.
LogStatistics LoadCarmenLogStatistics(const std::string& path,
                                      const ScanResidualOptions& options = {});

// Scans to compare with the real logs, e.g. a Pavilion scans.bin or the scans
// of a simulation run just made.
struct NamedScans {
  std::string name;
  std::vector<core::LaserScan> scans;
};

// Every scan of a Pavilion scans.bin (all robots and sensors), named by its
// path. Throws std::runtime_error naming the file when it cannot be read or
// holds no scan.
NamedScans LoadScanLogScans(const std::string& path);

// One set of simulated scans against every real log.
struct SimulatedStatistics {
  std::string name;
  RangeStepEstimate range_step;  // of the scans as they are
  ScanResidualStatistics raw;    // no requantization
  // [k]: requantized to real[k]'s measured step (none when that step is 0,
  // i.e. the log is not quantized coarser than 0.1 mm) and thinned to its
  // beam spacing (every round(beams / real[k].beams)-th reading).
  std::vector<ScanResidualStatistics> requantized;
};

struct RealismComparison {
  std::vector<LogStatistics> real;
  std::vector<SimulatedStatistics> simulated;
};

// The simulated scans' statistics, raw and requantized to each real log's step;
// `options` (with requantize_step_m = 0) is the analysis of the real logs.
// Throws std::invalid_argument for invalid options.
RealismComparison CompareResiduals(const std::vector<LogStatistics>& real,
                                   const std::vector<NamedScans>& simulated,
                                   const ScanResidualOptions& options = {});

// The text tables of `comparison`: one row per real log (and per simulated set,
// raw) with scans, range step, no-return and isolated fractions and, per range
// bin, count, median and p90 of |residual| in mm; then per simulated set a
// table with a column group per real log: real, simulated (requantized to that
// log's step) and the ratio simulated / real of the median and p90.
std::string FormatRealismReport(const RealismComparison& comparison);

// The same numbers as JSON (metres and fractions, as in the structs).
nlohmann::json RealismReportJson(const RealismComparison& comparison);

}  // namespace pavilion::scenarios
