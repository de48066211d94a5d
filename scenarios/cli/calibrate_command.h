#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>

namespace pavilion::cli {

// `pavilion calibrate ROBOT`: the odometry calibration scenario
// (scenarios/calibration/odometry_calibration.h, docs/calibration.md).
struct CalibrateArgs {
  std::string robot;  // robots/<name> name or path to a robot file
  int runs = 5;       // runs of each kind
  std::int64_t seed = 1;
  std::string out;  // folder for calibration.json; none when empty
  bool encoder_noise = false;
};

// Registers the subcommand on `app`, filling `args`.
CLI::App* AddCalibrateCommand(CLI::App* app, CalibrateArgs* args);

// Runs it: prints the table and the `odometry:` block, writes calibration.json.
// Throws scenarios::InputError for a bad robot file.
int RunCalibrateCommand(const CalibrateArgs& args);

}  // namespace pavilion::cli
