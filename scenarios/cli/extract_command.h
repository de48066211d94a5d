#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>

namespace pavilion::cli {

// `pavilion extract --log FILE [--scan K] [--png out.png] [--preset NAME]
// [--robot ID] [--sensor ID]`: runs the probabilistic line extraction (thesis
// §3.2) on every scan of a CARMEN log or a Pavilion scan log (scans.bin) and
// prints a timing summary, or the lines of scan K; --png draws one scan with
// its segments and their endpoints' 95% ellipses.
struct ExtractArgs {
  std::string log;                     // CARMEN .log/.log.gz or Pavilion scans.bin
  std::int64_t scan = -1;              // scan to list (0-based, after filtering); -1: summary
  std::string png;                     // optional picture of scan K (0 when no --scan)
  std::string preset = "sick_lms200";  // LineExtractionOptions preset
  std::string robot;                   // scans.bin only: keep this robot's scans
  std::string sensor;                  // scans.bin only: keep this laser's scans
};

CLI::App* AddExtractCommand(CLI::App* app, ExtractArgs* args);
// Throws scenarios::InputError / std::runtime_error for bad files or an
// out-of-range --scan; returns the exit code.
int RunExtractCommand(const ExtractArgs& args);

}  // namespace pavilion::cli
