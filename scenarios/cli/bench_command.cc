#include "scenarios/cli/bench_command.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "scenarios/config/data_paths.h"
#include "scenarios/config/scenario.h"
#include "scenarios/output/output_files.h"
#include "scenarios/run/scenario_runner.h"
#include "scenarios/version.h"
#include "sim/runtime/worker_pool.h"

namespace pavilion::cli {
namespace {

using Json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

// The benchmark's laser: 361 readings per scan, 10 scans per second
// (hall_bench.md); rays/s = N x 361 x 10 x RTF is how the peers were compared.
constexpr double kRaysPerRobotSimSecond = 361.0 * 10.0;

struct RunFigures {
  double sim_s = 0.0;
  double load_s = 0.0;      // reading and validating the scenario, world and robot files
  double startup_s = 0.0;   // load_s + building the world and robots
  double loop_s = 0.0;      // the stepping loop, wall s
  double loop_cpu_s = 0.0;  // the stepping loop, CPU s
  double rtf = 0.0;
  double cpu_rtf = 0.0;  // sim_s / loop_cpu_s: what an otherwise idle core would give
  double physics_s = 0.0;
  double sensors_s = 0.0;
  double nominal_rays_per_s = 0.0;   // N x 361 x 10 x RTF
  double measured_rays_per_s = 0.0;  // the world's ray counter / loop_s
  std::int64_t rays = 0;
  double peak_rss_mb = 0.0;
  double load_average = -1.0;  // 1-minute load average before the run (-1: unknown)
};

double LoadAverage() {
  double load[1];
  return getloadavg(load, 1) == 1 ? load[0] : -1.0;
}

Json ToJson(const RunFigures& f) {
  return Json{{"sim_s", f.sim_s},
              {"wall_stepping_s", f.loop_s},
              {"real_time_factor", f.rtf},
              {"cpu_s_stepping", f.loop_cpu_s},
              {"cpu_real_time_factor", f.cpu_rtf},
              {"rays_per_s", f.nominal_rays_per_s},
              {"measured_rays_per_s", f.measured_rays_per_s},
              {"rays", f.rays},
              {"startup_s", f.startup_s},
              {"load_s", f.load_s},
              {"physics_s", f.physics_s},
              {"sensors_s", f.sensors_s},
              {"peak_rss_mb", f.peak_rss_mb},
              {"load_average_1min", f.load_average}};
}

void Print(const char* label, const RunFigures& f) {
  const double other_s = f.loop_s - f.physics_s - f.sensors_s;
  std::printf(
      "%-8s sim %.1f s  stepping %.2f s wall  RTF %.3gx (CPU %.3gx)  rays/s %.3f M (counted "
      "%.3f M)  start-up %.2f s  peak RSS %.0f MB  [physics %.0f%%, sensors+control %.0f%%, "
      "other %.0f%%]  load %.1f\n",
      label, f.sim_s, f.loop_s, f.rtf, f.cpu_rtf, f.nominal_rays_per_s * 1e-6,
      f.measured_rays_per_s * 1e-6, f.startup_s, f.peak_rss_mb, 100.0 * f.physics_s / f.loop_s,
      100.0 * f.sensors_s / f.loop_s, 100.0 * other_s / f.loop_s, f.load_average);
}

}  // namespace

CLI::App* AddBenchCommand(CLI::App* app, BenchArgs* args) {
  auto* bench = app->add_subcommand("bench", "Run a benchmark workload and report its speed");
  bench->require_subcommand(1);
  auto* hall = bench->add_subcommand(
      "hall", "The hall benchmark: N wandering robots with one 361-beam laser each");
  hall->add_option("--robots", args->robots, "Robot count (the layouts the peers ran)")
      ->check(CLI::IsMember({1, 10, 100, 1000}))
      ->required();
  hall->add_option("--runs", args->runs, "Runs, one at a time")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  hall->add_option("--duration", args->duration_s,
                   "Simulated seconds (default: the benchmark's, 600/600/60/5 s for N = "
                   "1/10/100/1000)")
      ->check(CLI::PositiveNumber);
  hall->add_option("--seed", args->seed, "Seed, replaces the scenario's")
      ->check(CLI::NonNegativeNumber);
  hall->add_option("--set", args->set, "Override a scenario key: key.path=value (repeatable)");
  hall->add_option("--laser-backend", args->laser_backend, "planar or bullet (default: planar)")
      ->check(CLI::IsMember({"planar", "bullet"}));
  hall->add_option("--wheel-model", args->wheel_model,
                   "articulated (hinged sphere wheels, the reference) or raycast (one body)")
      ->check(CLI::IsMember({"articulated", "raycast"}));
  hall->add_option("--physics-rate", args->physics_rate_hz,
                   "Physics steps per second (default 200)")
      ->check(CLI::Range(10.0, 10000.0));
  hall->add_option("--threads", args->threads, "Threads for the robots' work (0: all cores)")
      ->check(CLI::Range(0, 256));
  hall->add_option("--json", args->json, "Also write the figures to this JSON file");
  hall->add_option("--out", args->out, "Keep each run's outputs in DIR/run_<k>");
  hall->footer(
      "Runs scenarios/hall_bench/hall_bench_<N>.yaml (docs/benchmarks.md). RTF = simulated s /\n"
      "wall s of the stepping loop; start-up (loading files, building the world) is reported\n"
      "apart; rays/s = N x 361 x 10 x RTF, and as counted by the world. On a shared machine\n"
      "the CPU-time RTF (simulated s / CPU s of the loop) is the steadier figure.\n"
      "Example:\n  pavilion bench hall --robots 10 --runs 3 --json hall_10.json");
  bench->footer("Example:\n  pavilion bench hall --robots 100 --duration 20");
  return hall;
}

namespace {

namespace fs = std::filesystem;

// The scenario overrides of the command line's options.
scenarios::ScenarioOverrides BenchOverrides(const BenchArgs& args) {
  scenarios::ScenarioOverrides overrides;
  if (args.seed >= 0) overrides.seed = static_cast<std::uint64_t>(args.seed);
  if (args.duration_s > 0) overrides.duration_s = args.duration_s;
  overrides.assignments = args.set;
  if (!args.laser_backend.empty()) {
    overrides.assignments.push_back("laser_backend=" + args.laser_backend);
  }
  if (!args.wheel_model.empty()) {
    overrides.assignments.push_back("physics.wheel_model=" + args.wheel_model);
  }
  if (args.physics_rate_hz > 0.0) {
    overrides.assignments.push_back("physics.rate_hz=" + std::to_string(args.physics_rate_hz));
  }
  return overrides;
}

// The bench scenario.
struct BenchScenario {
  std::string file;
  scenarios::ScenarioOverrides overrides;
  double duration_s = 0.0;  // as loaded (set by the runs)
  std::uint64_t seed = 0;
};

// Loads and runs the scenario once, its outputs written to `out_dir` (kept
// when `keep`); the figures of the run.
RunFigures BenchRun(const BenchArgs& args, const fs::path& out_dir, bool keep,
                    BenchScenario* bench) {
  RunFigures f;
  f.load_average = LoadAverage();
  const auto t_load = Clock::now();
  const scenarios::Scenario scenario = scenarios::LoadScenarioFile(bench->file, bench->overrides);
  f.load_s = std::chrono::duration<double>(Clock::now() - t_load).count();
  bench->duration_s = scenario.duration_s;
  bench->seed = scenario.seed;
  scenarios::RunOptions options;
  options.out_dir = out_dir.string();
  options.progress = args.progress;
  options.threads = args.threads;
  const scenarios::RunSummary s = scenarios::RunScenario(scenario, options);
  if (!keep) fs::remove_all(options.out_dir);
  f.sim_s = s.sim_duration_s;
  f.startup_s = f.load_s + s.startup_s;
  f.loop_s = s.loop_s;
  f.rtf = s.real_time_factor;
  f.loop_cpu_s = s.loop_cpu_s;
  f.cpu_rtf = s.loop_cpu_s > 0 ? s.sim_duration_s / s.loop_cpu_s : 0.0;
  f.physics_s = s.physics_s;
  f.sensors_s = s.sensors_s;
  f.rays = s.laser_rays;
  f.nominal_rays_per_s = static_cast<double>(args.robots) * kRaysPerRobotSimSecond * f.rtf;
  f.measured_rays_per_s = s.loop_s > 0 ? static_cast<double>(s.laser_rays) / s.loop_s : 0.0;
  f.peak_rss_mb = s.peak_rss_mb;
  return f;
}

void WriteBenchJson(const BenchArgs& args, const BenchScenario& bench,
                    const std::vector<RunFigures>& runs, const RunFigures& best,
                    const RunFigures& median) {
  Json j;
  j["benchmark"] = "hall";
  j["pavilion_version"] = kVersion;
  j["scenario"] = bench.file;
  j["robots"] = args.robots;
  j["duration_s"] = bench.duration_s;
  j["seed"] = bench.seed;
  j["settings"] = bench.overrides.assignments;
  j["threads"] = args.threads > 0 ? args.threads : sim::WorkerPool::HardwareThreads();
  j["hardware_threads"] = std::thread::hardware_concurrency();
  Json list = Json::array();
  for (const RunFigures& f : runs) list.push_back(ToJson(f));
  j["runs"] = list;
  j["best"] = ToJson(best);
  j["median"] = ToJson(median);
  j["peak_rss_mb"] = scenarios::PeakRssMb();
  scenarios::WriteFileAtomically(args.json, j.dump(2) + "\n");
  std::printf("%s\n", args.json.c_str());
}

}  // namespace

int RunBenchCommand(const BenchArgs& args) {
  BenchScenario bench;
  bench.file = (fs::path(scenarios::DataRoot()) / "scenarios" / "hall_bench" /
                ("hall_bench_" + std::to_string(args.robots) + ".yaml"))
                   .string();
  bench.overrides = BenchOverrides(args);

  // Outputs are written (after the stepping loop, outside the measured time)
  // to a scratch folder unless the user wants them.
  const bool keep = !args.out.empty();
  const fs::path out_root =
      keep ? fs::path(args.out)
           : fs::temp_directory_path() / ("pavilion_bench_" + std::to_string(::getpid()));

  std::printf("hall benchmark: %d robot%s, %s, %d run%s, one at a time, %u hardware threads\n",
              args.robots, args.robots == 1 ? "" : "s", bench.file.c_str(), args.runs,
              args.runs == 1 ? "" : "s", std::thread::hardware_concurrency());
  for (const std::string& s : bench.overrides.assignments) {
    std::printf("  setting %s\n", s.c_str());
  }
  std::printf("  threads %d\n",
              args.threads > 0 ? args.threads : sim::WorkerPool::HardwareThreads());
  std::fflush(stdout);

  std::vector<RunFigures> runs;
  for (int k = 0; k < args.runs; ++k) {
    runs.push_back(BenchRun(args, out_root / ("run_" + std::to_string(k + 1)), keep, &bench));
    char label[32];
    std::snprintf(label, sizeof label, "run %d", k + 1);
    Print(label, runs.back());
    std::fflush(stdout);
  }
  if (!keep) fs::remove_all(out_root);

  // Best = highest real-time factor; median by real-time factor (the lower
  // middle run for an even count).
  std::vector<RunFigures> sorted = runs;
  std::sort(sorted.begin(), sorted.end(),
            [](const RunFigures& a, const RunFigures& b) { return a.rtf > b.rtf; });
  const RunFigures& best = sorted.front();
  const RunFigures& median = sorted[sorted.size() / 2];
  Print("best", best);
  Print("median", median);
  std::printf("peak RSS of the process: %.0f MB (getrusage; every run has the same size)\n",
              scenarios::PeakRssMb());
  if (!args.json.empty()) WriteBenchJson(args, bench, runs, best, median);
  return 0;
}

}  // namespace pavilion::cli
