#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace pavilion::cli {

// `pavilion sweep SCENARIO --seeds 1-20 [--grid key=v1,v2 ...] [--set key=value ...]
// --jobs N --out DIR [--duration S]` (docs/sweep.md): writes the plan
// DIR/plan.json (grid cells x seeds), runs each as its own `pavilion run`
// process into DIR/runs/<id>/ (a temporary folder renamed when the run
// finished), then aggregates every numeric metric per cell into sweep.json,
// sweep.csv and sweep.html. Rerunning the same command continues the sweep;
// another command on the same DIR is refused.
struct SweepArgs {
  std::string scenario;
  std::string seeds;              // "1-20", "1,4,9", "1-5,10"
  std::vector<std::string> grid;  // "key.path=v1,v2,..." (repeatable)
  std::vector<std::string> set;   // "key.path=value" for every run
  int jobs = 1;                   // runs at a time, >= 1
  std::string out;                // the sweep's folder
  double duration_s = -1.0;       // simulated s; <= 0: the scenario's
};

CLI::App* AddSweepCommand(CLI::App* app, SweepArgs* args);
// Exit code: 0 every run finished, 1 bad input or some runs failed, 2 bad
// usage (or DIR holds another sweep), 128 + signal when interrupted.
// Throws scenarios::InputError for a bad scenario or override.
int RunSweepCommand(const SweepArgs& args);

}  // namespace pavilion::cli
