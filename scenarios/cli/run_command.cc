#include "scenarios/cli/run_command.h"

#include <spdlog/spdlog.h>

#include <csignal>
#include <cstdio>
#include <filesystem>

#include "scenarios/config/scenario.h"
#include "scenarios/expect/expect_eval.h"
#include "scenarios/expect/junit.h"
#include "scenarios/run/scenario_runner.h"

namespace pavilion::cli {
namespace {

volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void OnStopSignal(int signal) { g_stop_signal = signal; }

// SIGINT and SIGTERM end the run cleanly while installed (the runner looks at
// the flag once per tick); the previous handlers come back after.
class StopSignals {
 public:
  StopSignals() {
    g_stop_signal = 0;
    struct sigaction action {};
    action.sa_handler = OnStopSignal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &old_int_);
    sigaction(SIGTERM, &action, &old_term_);
  }
  ~StopSignals() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
};

}  // namespace

CLI::App* AddRunCommand(CLI::App* app, RunArgs* args) {
  auto* run = app->add_subcommand("run", "Run a scenario headless and write its outputs");
  run->add_option("scenario", args->scenario, "Scenario file (YAML)")->required();
  run->add_option("--out", args->out, "Output folder (created if missing)")->required();
  run->add_option("--seed", args->seed, "Seed, replaces the scenario's")
      ->check(CLI::NonNegativeNumber);
  run->add_option("--duration", args->duration_s, "Simulated seconds, replaces the scenario's")
      ->check(CLI::PositiveNumber);
  run->add_option("--set", args->set, "Override a scenario key: key.path=value (repeatable)");
  run->add_option("--threads", args->threads,
                  "Threads for the robots' sensors and localization (0: all cores); the outputs "
                  "are the same for any count")
      ->check(CLI::Range(0, 256))
      ->capture_default_str();
  run->add_option("--junit", args->junit,
                  "Write the scenario's expectations as JUnit XML to this file");
  run->footer(
      "Exit codes: 0 done (every expectation passed), 1 bad input, 2 bad usage, 3 an "
      "expectation failed, 4 the simulated world failed (a robot left the floor; the files "
      "are valid up to then), 130/143 interrupted (the files are valid).\n"
      "Example:\n  pavilion run scenarios/expo_visitors.yaml --out out/demo --seed 3 "
      "--duration 20 --set physics.rate_hz=100");
  return run;
}

int RunRunCommand(const RunArgs& a) {
  scenarios::ScenarioOverrides overrides;
  if (a.seed >= 0) overrides.seed = static_cast<std::uint64_t>(a.seed);
  if (a.duration_s > 0) overrides.duration_s = a.duration_s;
  overrides.assignments = a.set;
  const scenarios::Scenario scenario = scenarios::LoadScenarioFile(a.scenario, overrides);
  spdlog::info("running '{}' in world '{}' for {} s, seed {}", scenario.name, scenario.world.name,
               scenario.duration_s, scenario.seed);
  for (const std::string& note : scenario.notes) spdlog::info("{}: {}", a.scenario, note);
  scenarios::RunOptions options;
  options.out_dir = a.out;
  options.progress = a.progress;
  options.threads = a.threads;
  options.stop_signal = &g_stop_signal;
  StopSignals signals;
  const scenarios::RunSummary s = scenarios::RunScenario(scenario, options);
  spdlog::info(
      "simulated {:.1f} s in {:.2f} s wall ({:.1f}x real time), {} events, peak RSS {:.0f} MB",
      s.sim_duration_s, s.wall_time_s, s.real_time_factor, s.events, s.peak_rss_mb);
  if (scenario.laser_backend == scenarios::LaserBackend::kPlanar && !scenario.robots.empty()) {
    spdlog::info("laser: planar casting, {} scans fell back to Bullet", s.laser_fallback_scans);
  }
  std::printf("report: %s\n",
              (std::filesystem::path(a.out) / "report.html").lexically_normal().c_str());
  if (s.interrupted_by != 0) {
    spdlog::warn(
        "interrupted by signal {} after {:.1f} simulated s; the outputs are complete up "
        "to then",
        s.interrupted_by, s.sim_duration_s);
    return 128 + s.interrupted_by;
  }
  if (!s.ended_early.empty()) {
    if (s.expectations)
      std::printf("%s", scenarios::FormatExpectationTable(*s.expectations).c_str());
    spdlog::error("{}: the run ended early: {}; the outputs are complete up to then", a.scenario,
                  s.ended_early);
    return kExitWorldFailed;
  }
  if (!s.expectations) return 0;
  std::printf("%s", scenarios::FormatExpectationTable(*s.expectations).c_str());
  if (!a.junit.empty()) {
    scenarios::JUnitSuite suite;
    suite.name = scenario.name;
    suite.file = scenario.source_file;
    suite.time_s = s.wall_time_s;
    suite.results = *s.expectations;
    scenarios::WriteJUnit(a.junit, {suite});
  }
  return s.expectations->passed() ? 0 : kExitExpectationFailed;
}

}  // namespace pavilion::cli
