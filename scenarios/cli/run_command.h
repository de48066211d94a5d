#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "scenarios/expect/expectation_result.h"

namespace pavilion::cli {

// Exit codes of `pavilion run` and `pavilion test` (conventions.md): 1 bad
// input, 2 bad usage, 3 an expectation of the scenario failed; a run ended
// by SIGINT or SIGTERM exits 128 + the signal (130, 143) with its files valid.
using scenarios::kExitExpectationFailed;
// `pavilion run`: the simulated world ended the run early (a robot left the
// floor); its files are valid up to then.
inline constexpr int kExitWorldFailed = 4;

// `pavilion run SCENARIO --out DIR [--seed N] [--duration S] [--set k=v ...]
// [--threads N] [--junit FILE]`.
struct RunArgs {
  std::string scenario;
  std::string out;
  std::int64_t seed = -1;
  double duration_s = -1.0;
  std::vector<std::string> set;
  int threads = 0;
  std::string junit;      // optional: the expectations as JUnit XML
  bool progress = false;  // a live progress line on stderr
};

CLI::App* AddRunCommand(CLI::App* app, RunArgs* args);
// Throws scenarios::InputError for bad files; returns the exit code.
int RunRunCommand(const RunArgs& args);

}  // namespace pavilion::cli
