#include "scenarios/cli/snapshot_command.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "scenarios/config/input_error.h"
#include "scenarios/config/scenario.h"
#include "scenarios/run/scenario_runner.h"

namespace pavilion::cli {
namespace {

std::string DefaultOut(const scenarios::Scenario& s, const SnapshotArgs& a) {
  char t[32];
  std::snprintf(t, sizeof t, "%g", a.at_s);
  return s.name + "_" + a.camera + "_" + t + "s.png";
}

// A scratch folder for the run's other outputs, removed when done.
class ScratchDir {
 public:
  ScratchDir() {
    const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
    path_ = std::filesystem::temp_directory_path() / ("pavilion-snapshot-" + std::to_string(stamp));
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace

CLI::App* AddSnapshotCommand(CLI::App* app, SnapshotArgs* args) {
  auto* snap = app->add_subcommand(
      "snapshot", "Render a robot's camera or a perspective overview at a simulation time");
  snap->add_option("scenario", args->scenario, "Scenario file (YAML)")->required();
  snap->add_option("--at", args->at_s, "Simulation time of the picture (s)")
      ->required()
      ->check(CLI::NonNegativeNumber);
  snap->add_option("--camera", args->camera, "A robot id (its first level camera) or 'overview'")
      ->capture_default_str();
  snap->add_option("--out", args->out, "PNG file to write (default: NAME_CAMERA_Ts.png)");
  snap->add_option("--seed", args->seed, "Seed, replaces the scenario's")
      ->check(CLI::NonNegativeNumber);
  snap->add_option("--set", args->set, "Override a scenario key: key.path=value (repeatable)");
  snap->add_option("--width", args->width_px, "Overview width (px)")
      ->check(CLI::Range(64, 4096))
      ->capture_default_str();
  snap->add_option("--height", args->height_px, "Overview height (px)")
      ->check(CLI::Range(64, 4096))
      ->capture_default_str();
  snap->footer(
      "Example:\n  pavilion snapshot scenarios/office_tour_vision.yaml --at 30 --camera pygmalion\n"
      "  pavilion snapshot scenarios/expo_tours.yaml --at 120 --camera overview --out hall.png");
  return snap;
}

int RunSnapshotCommand(const SnapshotArgs& a) {
  scenarios::ScenarioOverrides overrides;
  if (a.seed >= 0) overrides.seed = static_cast<std::uint64_t>(a.seed);
  overrides.duration_s = std::max(a.at_s, 1e-3);
  overrides.assignments = a.set;
  scenarios::Scenario scenario = scenarios::LoadScenarioFile(a.scenario, overrides);
  const bool robot = std::any_of(scenario.robots.begin(), scenario.robots.end(),
                                 [&](const scenarios::RobotEntry& r) { return r.id == a.camera; });
  if (a.camera != scenarios::kOverviewCamera && !robot) {
    throw scenarios::InputError(scenarios::Diagnostic{
        scenario.source_file, 0, "--camera",
        "expected 'overview' or a robot id of the scenario, not '" + a.camera + "'"});
  }
  scenario.snapshots = {};
  scenario.snapshots.at = {{a.at_s, a.camera}};
  scenario.snapshots.max = 1;
  scenario.snapshots.width_px = a.width_px;
  scenario.snapshots.height_px = a.height_px;
  scenario.expectations = {};
  const ScratchDir scratch;
  scenarios::RunOptions options;
  options.out_dir = scratch.path().string();
  scenarios::RunScenario(scenario, options);
  const std::filesystem::path shots = scratch.path() / "snapshots";
  for (const auto& entry : std::filesystem::directory_iterator(shots)) {
    if (entry.path().filename().string().rfind("camera_01_", 0) != 0) continue;
    const std::string out = a.out.empty() ? DefaultOut(scenario, a) : a.out;
    if (const auto parent = std::filesystem::path(out).parent_path(); !parent.empty()) {
      std::filesystem::create_directories(parent);
    }
    std::filesystem::copy_file(entry.path(), out,
                               std::filesystem::copy_options::overwrite_existing);
    std::printf("%s\n", out.c_str());
    return 0;
  }
  spdlog::error("{}: the run ended before t = {} s: no picture taken", a.scenario, a.at_s);
  return 1;
}

}  // namespace pavilion::cli
