#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace pavilion::cli {

// `pavilion snapshot SCENARIO --at T --camera ROBOT_ID|overview [--out FILE.png]
// [--seed N] [--set k=v ...] [--width W --height H]`: runs the scenario
// headless up to simulation time T and writes one picture: the robot's camera
// (what its software gets: grey levels through its lens) or a perspective
// overview of the world (issue 19).
struct SnapshotArgs {
  std::string scenario;
  double at_s = 0.0;
  std::string camera = "overview";
  std::string out;  // default: <scenario name>_<camera>_<T>s.png
  std::int64_t seed = -1;
  std::vector<std::string> set;
  int width_px = 960;  // the overview's size
  int height_px = 540;
};

CLI::App* AddSnapshotCommand(CLI::App* app, SnapshotArgs* args);
// Throws scenarios::InputError for bad files; returns the exit code.
int RunSnapshotCommand(const SnapshotArgs& args);

}  // namespace pavilion::cli
