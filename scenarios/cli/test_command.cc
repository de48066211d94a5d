#include "scenarios/cli/test_command.h"

#include <cstdio>

#include "scenarios/config/input_error.h"
#include "scenarios/config/scenario.h"

namespace pavilion::cli {

CLI::App* AddTestCommand(CLI::App* app, scenarios::TestSuiteOptions* args) {
  auto* test = app->add_subcommand(
      "test", "Run scenarios as tests: each as its own process, judged by its expect: block");
  test->add_option("inputs", args->inputs, "Scenario files or folders (their *.yaml)")->required();
  test->add_option("--jobs,-j", args->jobs, "Runs at a time")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  test->add_option("--junit", args->junit, "Write one JUnit XML file for the suite");
  test->add_option("--out", args->out_dir, "Folder of the runs' outputs, one folder per scenario")
      ->capture_default_str();
  test->add_option("--run-arg", args->run_args,
                   "An argument for every `pavilion run` (repeatable), e.g. --run-arg=--threads "
                   "--run-arg=1");
  test->footer(
      "Exit codes: 0 every scenario passed, 3 some failed or did not complete, 1 bad input.\n"
      "Example:\n  pavilion test scenarios/ci --jobs 2 --junit out/ci/junit.xml --out out/ci");
  return test;
}

int RunTestCommand(const scenarios::TestSuiteOptions& args) {
  const std::vector<std::string> files = scenarios::CollectScenarioFiles(args.inputs);
  // Every scenario loads before any runs: bad input is exit 1, as for `run`.
  for (const std::string& f : files) (void)scenarios::LoadScenarioFile(f);
  std::fprintf(stderr, "pavilion test: %zu scenarios, %d at a time\n", files.size(), args.jobs);
  const scenarios::TestSuiteResult result = scenarios::RunTestSuite(files, args);
  std::printf("%s", scenarios::FormatTestSummary(result).c_str());
  if (!args.junit.empty()) std::printf("junit: %s\n", args.junit.c_str());
  if (result.signal != 0) return 128 + result.signal;
  return result.passed() ? 0 : scenarios::kExitExpectationFailed;
}

}  // namespace pavilion::cli
