#pragma once

// `pavilion test` (issue 17): a suite of scenarios run as tests, each as its
// own `pavilion run` process, several at a time; one summary table and one
// JUnit file. A run that exits 0 or 3 is judged by its expectations.json; any
// other end (bad input, a crash, a kill) is a JUnit <error> with its stderr tail.

#include <filesystem>
#include <string>
#include <vector>

#include "scenarios/expect/junit.h"

namespace pavilion::scenarios {

struct TestSuiteOptions {
  std::vector<std::string> inputs;    // scenario files and folders (their *.yaml, recursively)
  std::string out_dir = "out/test";   // each run writes into out_dir/<scenario stem>/
  int jobs = 1;                       // runs at a time
  std::string junit;                  // optional: the JUnit XML file
  std::string executable;             // the `pavilion` binary (default: this process')
  std::vector<std::string> run_args;  // added to every `pavilion run` (e.g. --threads 1)
};

struct TestRun {
  std::string file;
  std::string name;  // the file's stem, unique in the suite
  std::filesystem::path out;
  JUnitSuite suite;  // results, or an error
  int exit_code = -1;
};

struct TestSuiteResult {
  std::vector<TestRun> runs;  // in the order of the files
  int signal = 0;             // SIGINT/SIGTERM that stopped the suite; 0: it ran to its end
  bool passed() const;        // every run completed and every expectation passed
};

// The scenario files of the inputs, sorted within each folder; throws
// InputError for an input that does not exist or a folder with none, and for
// two files with the same stem.
std::vector<std::string> CollectScenarioFiles(const std::vector<std::string>& inputs);

// Runs the suite (the files are loaded and checked first by the caller).
TestSuiteResult RunTestSuite(const std::vector<std::string>& files,
                             const TestSuiteOptions& options);

// The summary table: scenario, result, expectations passed, wall time, first failure.
std::string FormatTestSummary(const TestSuiteResult& result);

}  // namespace pavilion::scenarios
