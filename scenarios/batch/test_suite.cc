#include "scenarios/batch/test_suite.h"

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "scenarios/batch/child_process.h"
#include "scenarios/config/input_error.h"
#include "scenarios/expect/expect_eval.h"

namespace pavilion::scenarios {
namespace {

namespace fs = std::filesystem;

// The run's expectations.json; a run without `expect:` passes by completing.
ExpectationResults ReadResults(const fs::path& out) {
  ExpectationResults results;
  std::ifstream in(out / "expectations.json");
  if (!in) {
    results.results.push_back(
        {"run completes", ExpectationStatus::kPass, "exit 0", "exit 0", "", 0});
    return results;
  }
  return ExpectationsFromJson(nlohmann::json::parse(in));
}

std::string HowItEnded(const ChildResult& r) {
  if (r.interrupted) return "not run: the suite was interrupted";
  if (r.signal != 0) return "killed by signal " + std::to_string(r.signal);
  if (r.exit_code == 1) return "bad input (exit 1)";
  return "exit " + std::to_string(r.exit_code);
}

}  // namespace

bool TestSuiteResult::passed() const {
  if (signal != 0) return false;
  return std::all_of(runs.begin(), runs.end(), [](const TestRun& r) {
    return r.suite.error.empty() && r.suite.results.passed();
  });
}

std::vector<std::string> CollectScenarioFiles(const std::vector<std::string>& inputs) {
  std::vector<std::string> files;
  for (const std::string& input : inputs) {
    if (fs::is_directory(input)) {
      std::vector<std::string> found;
      for (const auto& e : fs::recursive_directory_iterator(input)) {
        if (e.is_regular_file() && e.path().extension() == ".yaml") found.push_back(e.path());
      }
      std::sort(found.begin(), found.end());
      if (found.empty()) throw InputError(Diagnostic{input, 0, "", "no *.yaml scenario in it"});
      files.insert(files.end(), found.begin(), found.end());
    } else if (fs::is_regular_file(input)) {
      files.push_back(input);
    } else {
      throw InputError(Diagnostic{input, 0, "", "no such file or folder"});
    }
  }
  std::map<std::string, std::string> by_stem;
  for (const std::string& f : files) {
    const std::string stem = fs::path(f).stem();
    if (auto [it, added] = by_stem.emplace(stem, f); !added) {
      throw InputError(Diagnostic{
          f, 0, "", "same name as " + it->second + " (runs are written to folders by name)"});
    }
  }
  return files;
}

TestSuiteResult RunTestSuite(const std::vector<std::string>& files,
                             const TestSuiteOptions& options) {
  TestSuiteResult result;
  std::vector<ChildJob> jobs;
  fs::create_directories(options.out_dir);
  const std::string exe = options.executable.empty() ? SelfExecutable() : options.executable;
  const int jobs_at_once = std::max(1, options.jobs);
  for (const std::string& file : files) {
    TestRun run;
    run.file = file;
    run.name = fs::path(file).stem();
    run.out = fs::path(options.out_dir) / run.name;
    run.suite.name = run.name;
    run.suite.file = file;
    std::vector<std::string> argv{exe, "run", file, "--out", run.out.string()};
    argv.insert(argv.end(), options.run_args.begin(), options.run_args.end());
    // The cores shared among the runs at a time, unless the caller chose.
    if (std::find(argv.begin(), argv.end(), "--threads") == argv.end()) {
      const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
      argv.insert(argv.end(), {"--threads", std::to_string(std::max(1, cores / jobs_at_once))});
    }
    const fs::path logs = fs::path(options.out_dir) / run.name;
    jobs.push_back(ChildJob{argv, logs.string() + ".stdout", logs.string() + ".stderr"});
    result.runs.push_back(std::move(run));
  }
  result.signal =
      RunChildren(jobs, std::max(1, options.jobs), [&](std::size_t i, const ChildResult& r) {
        TestRun& run = result.runs[i];
        run.exit_code = r.exit_code;
        run.suite.time_s = r.wall_s;
        const bool judged = r.signal == 0 && !r.interrupted &&
                            (r.exit_code == 0 || r.exit_code == kExitExpectationFailed);
        if (judged) {
          run.suite.results = ReadResults(run.out);
        } else {
          run.suite.error = HowItEnded(r);
          run.suite.error_text = TailOfFile(jobs[i].stderr_path, 20);
        }
        std::fprintf(stderr, "%-8s %s (%.1f s)\n",
                     !judged                      ? "error"
                     : run.suite.results.passed() ? "pass"
                                                  : "fail",
                     run.name.c_str(), r.wall_s);
      });
  if (!options.junit.empty()) {
    std::vector<JUnitSuite> suites;
    for (const TestRun& run : result.runs) suites.push_back(run.suite);
    WriteJUnit(options.junit, suites, "pavilion test");
  }
  return result;
}

std::string FormatTestSummary(const TestSuiteResult& result) {
  std::ostringstream out;
  std::size_t width = 8;
  for (const TestRun& r : result.runs) width = std::max(width, r.name.size());
  char line[1024];
  std::snprintf(line, sizeof line, "%-*s  %-7s %-12s %8s  %s\n", static_cast<int>(width),
                "scenario", "result", "expectations", "wall s", "first failure");
  out << line;
  int passed = 0;
  for (const TestRun& r : result.runs) {
    const ExpectationResults& e = r.suite.results;
    const bool error = !r.suite.error.empty();
    std::string first = r.suite.error;
    for (const ExpectationResult& x : e.results) {
      if (first.empty() && x.status != ExpectationStatus::kPass) {
        first = x.name + ": " +
                (x.status == ExpectationStatus::kMissing
                     ? "missing"
                     : "measured " + x.measured + ", expected " + x.bound);
      }
    }
    const bool ok = !error && e.passed();
    passed += ok ? 1 : 0;
    const std::string counts =
        error ? "-"
              : std::to_string(e.results.size() - static_cast<std::size_t>(e.failures())) + "/" +
                    std::to_string(e.results.size());
    std::snprintf(line, sizeof line, "%-*s  %-7s %-12s %8.1f  %s\n", static_cast<int>(width),
                  r.name.c_str(),
                  error ? "error"
                  : ok  ? "pass"
                        : "fail",
                  counts.c_str(), r.suite.time_s, first.c_str());
    out << line;
  }
  out << passed << " of " << result.runs.size() << " scenarios passed";
  if (result.signal != 0) out << " (interrupted by signal " << result.signal << ")";
  out << "\n";
  return out.str();
}

}  // namespace pavilion::scenarios
