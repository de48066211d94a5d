#include "scenarios/cli/realism_command.h"

#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace pavilion::cli {

CLI::App* AddRealismCommand(CLI::App* app, RealismArgs* args) {
  auto* realism =
      app->add_subcommand("realism", "Compare the simulated laser's errors with real logs");
  realism->require_subcommand(1);
  auto* report = realism->add_subcommand(
      "report", "Range step, no-returns and residuals of long walls of CARMEN logs and scans.bin");
  report->add_option("--log", args->logs, "CARMEN logs (.log, .log.gz)")->required();
  report->add_option("--scans", args->scans,
                     "Pavilion scans.bin files: statistics raw and requantized to each log's step");
  report->add_option("--json", args->json, "Also write the numbers to this JSON file");
  report->footer(
      "Per log: scans, the measured range step (largest of 0.1 mm ... 10 cm with >= 99% of the\n"
      "ranges on its grid), the fractions of no-return and isolated readings, and per range bin\n"
      "([0,2), [2,4), [4,8] m) the count, median and 90th percentile of the perpendicular\n"
      "residuals of the readings of long walls (runs of >= 20 points, >= 2 m, straight within\n"
      "5 cm) to their total-least-squares line, in mm (docs/carmen_logs.md). With --scans, each\n"
      "scans.bin once raw and once requantized to each log's step, beside that log.\n"
      "Example:\n"
      "  pavilion realism report --log ../shared/data/carmen/intel-corrected.log.gz "
      "--scans out/tour/scans.bin --json realism.json");
  return report;
}

int RunRealismCommand(const RealismArgs& args) {
  std::vector<scenarios::LogStatistics> real;
  for (const std::string& path : args.logs)
    real.push_back(scenarios::LoadCarmenLogStatistics(path));
  std::vector<scenarios::NamedScans> simulated;
  for (const std::string& path : args.scans) simulated.push_back(scenarios::LoadScanLogScans(path));
  const scenarios::RealismComparison comparison = scenarios::CompareResiduals(real, simulated);
  std::fputs(scenarios::FormatRealismReport(comparison).c_str(), stdout);
  if (!args.json.empty()) {
    std::ofstream out(args.json);
    out << scenarios::RealismReportJson(comparison).dump(2) << "\n";
    if (!out) throw std::runtime_error(args.json + ": cannot be written");
    std::printf("wrote %s\n", args.json.c_str());
  }
  return 0;
}

}  // namespace pavilion::cli
