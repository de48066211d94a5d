#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>

namespace pavilion::cli {

// `pavilion extract --log FILE [--scan K] [--png out.png] [--preset NAME]
// [--robot ID] [--sensor ID] [--score WORLD [--beam-height H]] [--compare]`:
// runs the probabilistic line extraction (thesis §3.2) on every scan of a
// CARMEN log or a Pavilion scan log (scans.bin) and prints a timing summary, or
// the lines of scan K. --score rates the lines against the ground truth of a
// scans.bin (docs/metrics.md, "Feature extraction"); --compare runs the
// split-and-merge baseline on the same scans and prints both side by side;
// --png draws one scan with its segments, their endpoints' 95% ellipses, a
// caption and the scene description (§3.5).
struct ExtractArgs {
  std::string log;                     // CARMEN .log/.log.gz or Pavilion scans.bin
  std::int64_t scan = -1;              // scan to list (0-based, after filtering); -1: summary
  std::string png;                     // optional picture of scan K (0 when no --scan)
  std::string preset = "sick_lms200";  // LineExtractionOptions preset
  std::string robot;                   // scans.bin only: keep this robot's scans
  std::string sensor;                  // scans.bin only: keep this laser's scans
  std::string score_world;             // scans.bin only: WORLD to score against; empty: no score
  double beam_height_m = 0.5;          // height of the scan plane (m), (0, 10]
  bool compare = false;                // also run the split-and-merge baseline
};

CLI::App* AddExtractCommand(CLI::App* app, ExtractArgs* args);
// Throws scenarios::InputError / std::runtime_error for bad files, an
// out-of-range --scan, --score on a log without ground truth; returns the exit
// code.
int RunExtractCommand(const ExtractArgs& args);

}  // namespace pavilion::cli
