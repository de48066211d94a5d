#include "scenarios/cli/sweep_command.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <thread>

#include "scenarios/batch/child_process.h"
#include "scenarios/batch/sweep_aggregate.h"
#include "scenarios/batch/sweep_html.h"
#include "scenarios/batch/sweep_plan.h"
#include "scenarios/config/input_error.h"
#include "scenarios/config/scenario.h"
#include "scenarios/output/output_files.h"

namespace pavilion::cli {
namespace {

namespace fs = std::filesystem;
using scenarios::ChildResult;
using scenarios::SweepPlan;
using scenarios::SweepRun;

constexpr int kExitBadInput = 1;
constexpr int kExitBadUsage = 2;
// `pavilion run` exit codes that mean "the run finished" (3: an expectation failed).
constexpr int kExitRunOk = 0;
constexpr int kExitRunExpectationFailed = 3;
// Lines of a failed run's stderr shown and kept in failure.txt.
constexpr int kStderrTailLines = 20;
// Lines of its stderr shown as a run fails.
constexpr int kLiveTailLines = 3;
// Metrics printed per cell at the end (all are in sweep.html / sweep.json).
constexpr std::size_t kPrintedMetrics = 4;

int UsageError(const std::string& message) {
  std::fprintf(stderr, "pavilion: usage error: %s\n", message.c_str());
  return kExitBadUsage;
}

// This process's command line after the program (/proc/self/cmdline).
std::vector<std::string> OwnArguments() {
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  std::vector<std::string> args;
  for (std::string a; std::getline(in, a, '\0');) args.push_back(a);
  if (!args.empty()) args.erase(args.begin());
  return args;
}

// The plan of the command's arguments; std::invalid_argument for bad usage.
SweepPlan MakePlan(const SweepArgs& a) {
  if (!fs::is_regular_file(a.scenario)) {
    throw scenarios::InputError(scenarios::Diagnostic{a.scenario, 0, "", "no such scenario file"});
  }
  scenarios::SweepSpec spec;
  spec.scenario = fs::weakly_canonical(fs::absolute(a.scenario)).string();
  spec.scenario_digest = scenarios::ScenarioDigest(spec.scenario);
  spec.seeds = scenarios::ParseSeeds(a.seeds);
  for (const std::string& g : a.grid) spec.grid.push_back(scenarios::ParseGridAxis(g));
  for (const std::string& s : a.set) {
    if (s.find('=') == std::string::npos || s.front() == '=') {
      throw std::invalid_argument("--set '" + s + "': expected key.path=value");
    }
  }
  spec.set = a.set;
  spec.duration_s = a.duration_s;
  return scenarios::MakeSweepPlan(spec, OwnArguments());
}

// Loads the scenario with every cell's overrides: a bad key or value stops the
// sweep before anything runs (InputError, exit 1).
void CheckCellsLoad(const SweepPlan& plan) {
  for (const scenarios::SweepCell& cell : plan.cells) {
    scenarios::ScenarioOverrides overrides;
    overrides.seed = plan.spec.seeds.front();
    if (plan.spec.duration_s > 0) overrides.duration_s = plan.spec.duration_s;
    overrides.assignments = plan.spec.set;
    for (const auto& [key, value] : cell.settings)
      overrides.assignments.push_back(key + "=" + value);
    scenarios::LoadScenarioFile(plan.spec.scenario, overrides);
  }
}

// An exclusive lock on DIR/.sweep.lock while this process lives, so that two
// sweeps never share a folder. False when another process holds it.
bool LockSweepFolder(const fs::path& dir) {
  const int fd = ::open((dir / ".sweep.lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error("cannot create " + (dir / ".sweep.lock").string());
  return ::flock(fd, LOCK_EX | LOCK_NB) == 0;  // the descriptor stays open until exit
}

// Writes DIR/plan.json, or checks that the one there is this sweep's; an exit
// code when the sweep must not go on, else 0.
int WriteOrCheckPlan(const fs::path& dir, const SweepPlan& plan) {
  const fs::path path = dir / "plan.json";
  if (!fs::exists(path) && fs::is_directory(dir / "runs") && !fs::is_empty(dir / "runs")) {
    return UsageError((dir / "runs").string() +
                      " holds runs but there is no plan.json; choose another --out");
  }
  fs::create_directories(dir / "runs");
  if (!LockSweepFolder(dir)) {
    return UsageError("another `pavilion sweep` is running in " + dir.string());
  }
  if (!fs::exists(path)) {
    scenarios::WriteFileAtomically(path.string(), scenarios::PlanToJson(plan).dump(2) + "\n");
    return 0;
  }
  nlohmann::json existing;
  try {
    std::ifstream in(path);
    existing = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    existing = nullptr;
  }
  const std::string difference = scenarios::PlanDifference(existing, plan);
  if (difference.empty()) return 0;
  return UsageError(dir.string() + " holds another sweep (" + difference +
                    "); rerun the command in its plan.json or choose another --out");
}

fs::path RunFolder(const fs::path& dir, const SweepRun& run, const char* suffix = "") {
  return dir / "runs" / (run.id + suffix);
}

// `text`'s lines, each indented by four spaces; a note when it is empty.
std::string Indented(const std::string& text) {
  if (text.empty()) return "    (stderr was empty)\n";
  std::string out;
  std::size_t begin = 0;
  while (begin < text.size()) {
    const std::size_t end = std::min(text.find('\n', begin), text.size());
    out.append("    ").append(text, begin, end - begin).append("\n");
    begin = end + 1;
  }
  return out;
}

// The first line of a file; empty if unreadable.
std::string FirstLine(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

// The runs still to do. Removes stale temporary folders (a killed sweep) and
// lists earlier failures with their stderr tail before they are retried.
std::vector<std::size_t> RunsToDo(const fs::path& dir, const SweepPlan& plan) {
  std::vector<std::size_t> todo;
  std::string retried;
  for (std::size_t k = 0; k < plan.runs.size(); ++k) {
    const SweepRun& run = plan.runs[k];
    for (const char* stale : {".tmp", ".stdout.log", ".stderr.log"}) {  // never finished
      fs::remove_all(RunFolder(dir, run, stale));
    }
    const fs::path failed = RunFolder(dir, run, ".failed");
    if (fs::is_directory(RunFolder(dir, run))) {
      fs::remove_all(failed);
      continue;
    }
    if (fs::exists(failed)) {
      const std::string how = FirstLine(failed / "failure.txt");
      retried.append("retrying ").append(run.id).append(", which failed before");
      if (!how.empty()) retried.append(" (").append(how).append(")");
      retried.append("; its stderr ended:\n");
      retried.append(
          Indented(scenarios::TailOfFile((failed / "stderr.log").string(), kStderrTailLines)));
      fs::remove_all(failed);
    }
    todo.push_back(k);
  }
  std::printf("sweep: %zu runs planned (%zu cell%s x %zu seed%s), %zu done, %zu to run\n%s",
              plan.runs.size(), plan.cells.size(), plan.cells.size() == 1 ? "" : "s",
              plan.spec.seeds.size(), plan.spec.seeds.size() == 1 ? "" : "s",
              plan.runs.size() - todo.size(), todo.size(), retried.c_str());
  return todo;
}

std::string HowItEnded(const ChildResult& r) {
  if (r.signal != 0) return "killed by signal " + std::to_string(r.signal);
  return "exit " + std::to_string(r.exit_code);
}

// Whether a child's folder holds a finished run: a normal exit and a
// metrics.json that does not say "interrupted".
bool Finished(const ChildResult& r, const fs::path& folder) {
  if (r.signal != 0 || (r.exit_code != kExitRunOk && r.exit_code != kExitRunExpectationFailed)) {
    return false;
  }
  std::ifstream in(folder / "metrics.json");
  if (!in) return false;
  try {
    return !nlohmann::json::parse(in).value("interrupted", false);
  } catch (const nlohmann::json::exception&) {
    return false;
  }
}

// Moves a run's stdout and stderr logs (runs/<id>.stdout.log, .stderr.log)
// into `folder` as stdout.log and stderr.log.
void MoveLogs(const fs::path& dir, const SweepRun& run, const fs::path& folder) {
  fs::create_directories(folder);
  for (const auto& [suffix, name] :
       {std::pair{".stdout.log", "stdout.log"}, std::pair{".stderr.log", "stderr.log"}}) {
    const fs::path log = RunFolder(dir, run, suffix);
    if (fs::exists(log)) fs::rename(log, folder / name);
  }
}

// Keeps a failed run's outputs as runs/<id>.failed/ with failure.txt.
void RecordFailure(const fs::path& dir, const SweepRun& run, const ChildResult& r,
                   const std::vector<std::string>& argv) {
  const fs::path failed = RunFolder(dir, run, ".failed");
  fs::remove_all(failed);
  if (fs::exists(RunFolder(dir, run, ".tmp"))) fs::rename(RunFolder(dir, run, ".tmp"), failed);
  MoveLogs(dir, run, failed);
  std::string text = "run failed: ";
  text.append(HowItEnded(r)).append(" after ").append(std::to_string(r.wall_s));
  text.append(" s\ncommand:");
  for (const std::string& a : argv) text.append(" ").append(a);
  text.append("\nstderr (last lines):\n");
  text.append(scenarios::TailOfFile((failed / "stderr.log").string(), kStderrTailLines));
  scenarios::WriteFileAtomically((failed / "failure.txt").string(), text);
}

// Files a child's outcome: a finished run renamed to runs/<id>/, an interrupted
// one removed, a failure kept as runs/<id>.failed/.
void FileRun(const fs::path& dir, const SweepRun& run, const ChildResult& r,
             const std::vector<std::string>& argv, const std::string& progress) {
  const fs::path tmp = RunFolder(dir, run, ".tmp");
  if (Finished(r, tmp)) {
    MoveLogs(dir, run, tmp);
    fs::rename(tmp, RunFolder(dir, run));
    std::printf("%s %s done in %.1f s%s\n", progress.c_str(), run.id.c_str(), r.wall_s,
                r.exit_code == kExitRunExpectationFailed ? " (an expectation failed)" : "");
  } else if (r.interrupted) {
    fs::remove_all(tmp);
    fs::remove(RunFolder(dir, run, ".stdout.log"));
    fs::remove(RunFolder(dir, run, ".stderr.log"));
  } else {
    RecordFailure(dir, run, r, argv);
    const fs::path failed = RunFolder(dir, run, ".failed");
    std::printf(
        "%s %s FAILED (%s) in %.1f s: see %s\n%s", progress.c_str(), run.id.c_str(),
        HowItEnded(r).c_str(), r.wall_s, (failed / "failure.txt").c_str(),
        Indented(scenarios::TailOfFile((failed / "stderr.log").string(), kLiveTailLines)).c_str());
  }
  std::fflush(stdout);
}

// Runs `todo` as child processes; the signal that interrupted them, else 0.
int ExecuteRuns(const fs::path& dir, const SweepPlan& plan, const std::vector<std::size_t>& todo,
                int jobs) {
  const std::string self = scenarios::SelfExecutable();
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const std::string threads = std::to_string(std::max(1u, cores / static_cast<unsigned>(jobs)));
  std::vector<scenarios::ChildJob> children;
  for (const std::size_t k : todo) {
    const SweepRun& run = plan.runs[k];
    std::vector<std::string> argv = scenarios::RunArguments(plan, run);
    argv.insert(argv.begin() + 2, {"--out", RunFolder(dir, run, ".tmp").string()});
    argv.insert(argv.begin(), self);
    argv.insert(argv.end(), {"--threads", threads});
    children.push_back({argv, RunFolder(dir, run, ".stdout.log").string(),
                        RunFolder(dir, run, ".stderr.log").string()});
  }
  std::size_t reported = 0;
  return scenarios::RunChildren(children, jobs, [&](std::size_t i, const ChildResult& r) {
    std::string progress = "[";
    progress.append(std::to_string(++reported)).append("/");
    progress.append(std::to_string(todo.size())).append("]");
    FileRun(dir, plan.runs[todo[i]], r, children[i].argv, progress);
  });
}

// Reads the finished runs, writes sweep.json, sweep.csv and sweep.html; the
// status of the runs.
scenarios::SweepStatus Aggregate(const fs::path& dir, const SweepPlan& plan,
                                 scenarios::SweepAggregate* aggregate) {
  scenarios::SweepStatus status;
  status.planned = plan.runs.size();
  std::vector<scenarios::RunRecord> records;
  for (std::size_t k = 0; k < plan.runs.size(); ++k) {
    const SweepRun& run = plan.runs[k];
    if (fs::is_directory(RunFolder(dir, run))) {
      try {
        records.push_back(scenarios::ReadRunFolder(RunFolder(dir, run).string(), k));
        continue;
      } catch (const std::runtime_error& e) {
        std::fprintf(stderr, "pavilion: warning: %s: left out of the statistics\n", e.what());
      }
    }
    (fs::exists(RunFolder(dir, run, ".failed")) ? status.failed : status.not_run).push_back(run.id);
  }
  status.finished = records.size();
  *aggregate = scenarios::AggregateRuns(plan, records);
  scenarios::WriteFileAtomically(
      (dir / "sweep.json").string(),
      scenarios::AggregateToJson(plan, *aggregate, status).dump(2) + "\n");
  scenarios::WriteFileAtomically((dir / "sweep.csv").string(),
                                 scenarios::AggregateToCsv(plan, *aggregate));
  scenarios::WriteFileAtomically((dir / "sweep.html").string(),
                                 scenarios::SweepHtml(plan, *aggregate, status));
  return status;
}

// A few key metrics per cell: mean +- the interval's half width (n).
void PrintSummary(const SweepPlan& plan, const scenarios::SweepAggregate& aggregate) {
  for (const std::string& metric : scenarios::KeyMetrics(aggregate, kPrintedMetrics)) {
    std::printf("%s\n", metric.c_str());
    for (std::size_t c = 0; c < plan.cells.size(); ++c) {
      const auto it = aggregate.cells[c].metrics.find(metric);
      if (it == aggregate.cells[c].metrics.end()) continue;
      const scenarios::MetricSummary& s = it->second;
      std::string settings;
      for (const auto& [key, value] : plan.cells[c].settings) settings += " " + key + "=" + value;
      std::printf("  %s%s: %.4g", plan.cells[c].id.c_str(), settings.c_str(), s.mean);
      if (s.ci95_high) std::printf(" +- %.2g", *s.ci95_high - s.mean);
      std::printf(" (n=%zu)\n", s.n);
    }
  }
}

}  // namespace

CLI::App* AddSweepCommand(CLI::App* app, SweepArgs* args) {
  auto* sweep = app->add_subcommand(
      "sweep",
      "Run a scenario over seeds and a parameter grid, one process per run, and "
      "aggregate the metrics");
  sweep->add_option("scenario", args->scenario, "Scenario file (YAML)")->required();
  sweep->add_option("--seeds", args->seeds, "Seeds: 1-20, 1,4,9 or 1-5,10")->required();
  sweep->add_option("--grid", args->grid,
                    "A grid parameter: key.path=v1,v2,... (repeatable; cells are every "
                    "combination)");
  sweep->add_option("--set", args->set,
                    "Override a scenario key for every run: key.path=value "
                    "(repeatable)");
  sweep->add_option("--jobs", args->jobs, "Runs at a time")
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
  sweep->add_option("--out", args->out, "The sweep's folder (plan.json, runs/, sweep.*)")
      ->required();
  sweep->add_option("--duration", args->duration_s, "Simulated seconds, replaces the scenario's")
      ->check(CLI::PositiveNumber);
  sweep->footer(
      "Writes DIR/plan.json, runs each cell x seed as `pavilion run` into DIR/runs/<id>/, then\n"
      "DIR/sweep.json, sweep.csv and sweep.html: per cell n, mean, std, min, max and the 95 %\n"
      "t-interval of every metric (docs/sweep.md). Rerun the same command to continue after an\n"
      "interruption or to retry failed runs.\n"
      "Example:\n  pavilion sweep scenarios/office_tour.yaml --seeds 1-4 --duration 20 \\\n"
      "    --grid robots.0.route.max_speed_mps=0.4,0.6 --jobs 2 --out out/sweep");
  return sweep;
}

int RunSweepCommand(const SweepArgs& args) {
  SweepPlan plan;
  try {
    plan = MakePlan(args);
  } catch (const std::invalid_argument& e) {
    return UsageError(e.what());
  }
  CheckCellsLoad(plan);
  const fs::path dir(args.out);
  if (const int refused = WriteOrCheckPlan(dir, plan); refused != 0) return refused;
  const std::vector<std::size_t> todo = RunsToDo(dir, plan);
  std::fflush(stdout);
  const int signal_number = todo.empty() ? 0 : ExecuteRuns(dir, plan, todo, args.jobs);
  if (signal_number != 0) {
    std::fprintf(stderr, "pavilion: sweep interrupted; rerun the same command to continue\n");
    return 128 + signal_number;
  }
  scenarios::SweepAggregate aggregate;
  const scenarios::SweepStatus status = Aggregate(dir, plan, &aggregate);
  PrintSummary(plan, aggregate);
  std::printf("sweep: %zu of %zu runs finished -> %s\n", status.finished, status.planned,
              (dir / "sweep.html").lexically_normal().c_str());
  if (!status.failed.empty() || !status.not_run.empty()) {
    std::fprintf(stderr,
                 "pavilion: %zu of %zu runs did not finish (%s); rerun the same command to "
                 "retry them\n",
                 status.failed.size() + status.not_run.size(), status.planned,
                 (dir / "runs" / "<id>.failed" / "failure.txt").c_str());
    return kExitBadInput;
  }
  return 0;
}

}  // namespace pavilion::cli
