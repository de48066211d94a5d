#include "scenarios/cli/realism_command.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>

#include "scenarios/config/scenario.h"
#include "scenarios/run/scenario_runner.h"

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
  report->add_option("--scenario", args->scenario,
                     "Also run this scenario under realism: ideal and realistic: its scans join "
                     "the comparison, its localization is printed beside thesis Table 4.2");
  report->add_option("--seed", args->seed, "With --scenario: the seed of both runs")
      ->capture_default_str();
  report->add_option("--out", args->out_dir, "With --scenario: outputs under OUT/<profile>")
      ->capture_default_str();
  report->add_option("--set", args->assignments,
                     "With --scenario: key.path=value overrides for both runs (repeatable), e.g. "
                     "the localization's line_floor_r_m");
  report
      ->add_option("--scan-minutes", args->scan_minutes,
                   "With --scenario: robot-minutes of scans logged per profile (~18 MB each)")
      ->check(CLI::Range(0.1, 1000.0))
      ->capture_default_str();
  report->footer(
      "Per log: scans, the measured range step (largest of 0.1 mm ... 10 cm with >= 99% of the\n"
      "ranges on its grid), the fractions of no-return and isolated readings, and per range bin\n"
      "([0,2), [2,4), [4,8] m) the count, median and 90th percentile of the perpendicular\n"
      "residuals of the readings of long walls (runs of >= 20 points, >= 2 m, straight within\n"
      "5 cm) to their total-least-squares line, in mm (docs/carmen_logs.md). With --scans, each\n"
      "scans.bin once raw and once requantized to each log's step, beside that log.\n"
      "Example:\n"
      "  pavilion realism report --log ../shared/data/carmen/intel-corrected.log.gz "
      "--scans out/tour/scans.bin --json realism.json\n"
      "  pavilion realism report --log ../shared/data/carmen/intel-corrected.log.gz "
      "--scenario scenarios/office_tour.yaml");
  return report;
}

namespace {

// Thesis Table 4.2, laser only (Pygmalion, office floor, on the fly).
constexpr double kTableFrontalM = 0.0131, kTableLateralM = 0.0135, kTableHeadingDeg = 0.92,
                 kTableLinesPerCycle = 2.73;

struct ProfileRun {
  std::string profile;
  std::optional<scenarios::LocalizationFigures> figures;
  std::string scans;
};

// Runs the scenario under one profile, scans logged for its first
// args.scan_minutes robot-minutes.
ProfileRun RunProfile(const RealismArgs& args, const std::string& profile) {
  scenarios::ScenarioOverrides overrides;
  overrides.seed = args.seed;
  overrides.assignments = {"realism=" + profile, "outputs.scan_log=auto",
                           "outputs.scan_log_robot_minutes=" + std::to_string(args.scan_minutes)};
  overrides.assignments.insert(overrides.assignments.end(), args.assignments.begin(),
                               args.assignments.end());
  const scenarios::Scenario s = scenarios::LoadScenarioFile(args.scenario, overrides);
  const std::string out = (std::filesystem::path(args.out_dir) / profile).string();
  const scenarios::RunSummary run = scenarios::RunScenario(s, scenarios::RunOptions{out, false});
  ProfileRun result{profile, std::nullopt, out + "/scans.bin"};
  for (const scenarios::RobotMetrics& r : run.metrics.robots) {
    if (r.localization) {
      result.figures = *r.localization;
      break;
    }
  }
  return result;
}

void PrintTable42(const std::vector<ProfileRun>& runs) {
  std::printf(
      "\nLocalization beside thesis Table 4.2 (laser only), first robot; ratio = sim / thesis\n");
  std::printf("%-22s %10s", "figure", "thesis");
  for (const ProfileRun& r : runs) std::printf(" %12s %6s", r.profile.c_str(), "ratio");
  std::printf("\n");
  const auto row = [&](const char* name, double thesis, auto get, double scale) {
    if (thesis > 0.0) {
      std::printf("%-22s %10.3g", name, thesis * scale);
    } else {
      std::printf("%-22s %10s", name, "-");  // the real robot had no ground truth
    }
    for (const ProfileRun& r : runs) {
      const double v = r.figures ? get(*r.figures) : 0.0;
      if (thesis > 0.0) {
        std::printf(" %12.3g %6.2f", v * scale, v / thesis);
      } else {
        std::printf(" %12.3g %6s", v * scale, "");
      }
    }
    std::printf("\n");
  };
  using F = scenarios::LocalizationFigures;
  row(
      "2 sigma frontal (mm)", kTableFrontalM, [](const F& f) { return f.two_sigma_frontal_m; },
      1e3);
  row(
      "2 sigma lateral (mm)", kTableLateralM, [](const F& f) { return f.two_sigma_lateral_m; },
      1e3);
  row(
      "2 sigma heading (deg)", kTableHeadingDeg, [](const F& f) { return f.two_sigma_heading_deg; },
      1.0);
  row(
      "matched lines/cycle", kTableLinesPerCycle,
      [](const F& f) { return f.matched_lines_per_cycle; }, 1.0);
  row(
      "position RMSE (mm)", 0.0, [](const F& f) { return f.position_rmse_m; }, 1e3);
  row(
      "heading RMSE (deg)", 0.0, [](const F& f) { return f.heading_rmse_deg; }, 1.0);
  row(
      "ANEES (3 consistent)", 0.0, [](const F& f) { return f.anees; }, 1.0);
}

}  // namespace

int RunRealismCommand(const RealismArgs& args) {
  std::vector<scenarios::LogStatistics> real;
  for (const std::string& path : args.logs)
    real.push_back(scenarios::LoadCarmenLogStatistics(path));
  std::vector<scenarios::NamedScans> simulated;
  for (const std::string& path : args.scans) simulated.push_back(scenarios::LoadScanLogScans(path));
  std::vector<ProfileRun> runs;
  if (!args.scenario.empty()) {
    for (const std::string profile : {"ideal", "realistic"}) {
      runs.push_back(RunProfile(args, profile));
      scenarios::NamedScans scans = scenarios::LoadScanLogScans(runs.back().scans);
      scans.name = args.scenario + " (" + profile + ")";
      simulated.push_back(std::move(scans));
    }
  }
  const scenarios::RealismComparison comparison = scenarios::CompareResiduals(real, simulated);
  std::fputs(scenarios::FormatRealismReport(comparison).c_str(), stdout);
  if (!runs.empty()) PrintTable42(runs);
  if (!args.json.empty()) {
    std::ofstream out(args.json);
    out << scenarios::RealismReportJson(comparison).dump(2) << "\n";
    if (!out) throw std::runtime_error(args.json + ": cannot be written");
    std::printf("wrote %s\n", args.json.c_str());
  }
  return 0;
}

}  // namespace pavilion::cli
