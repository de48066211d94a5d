#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "scenarios/realism/realism_comparison.h"

namespace pavilion::cli {

// `pavilion realism report --log LOG... [--scans SCANS_BIN...] [--scenario FILE]
// [--json FILE]`
// (issue 20, docs/carmen_logs.md "Residuals of long walls"): the range step,
// no-return and isolated fractions and the residuals of long walls per range
// bin of each real CARMEN log, and of each Pavilion scans.bin raw and
// requantized to every log's step, side by side with the logs.
struct RealismArgs {
  std::vector<std::string> logs;   // CARMEN .log/.log.gz files
  std::vector<std::string> scans;  // Pavilion scans.bin files
  std::string json;                // optional JSON output file
  // --scenario: runs it under `realism: ideal` and `realistic` (seed `seed`,
  // outputs under out_dir/<profile>), adds both runs' scans to the residual
  // comparison and prints their localization beside the thesis' Table 4.2.
  std::string scenario;
  std::uint64_t seed = 1;
  std::string out_dir = "out/realism";
  double scan_minutes = 2.0;  // robot-minutes of scans logged per profile (about 18 MB each)
  std::vector<std::string> assignments;  // --set key.path=value, applied under both profiles
};

// Adds `realism` with its `report` subcommand; returns `report`.
CLI::App* AddRealismCommand(CLI::App* app, RealismArgs* args);

// Prints the report (and writes --json); returns the exit code. Throws for
// unreadable files (one-line message naming the file).
int RunRealismCommand(const RealismArgs& args);

}  // namespace pavilion::cli
