#include "scenarios/cli/calibrate_command.h"

#include <spdlog/spdlog.h>

#include <cstdio>
#include <filesystem>

#include "scenarios/calibration/calibration_report.h"
#include "scenarios/config/data_paths.h"
#include "scenarios/config/robot_loader.h"
#include "scenarios/output/output_files.h"

namespace pavilion::cli {

CLI::App* AddCalibrateCommand(CLI::App* app, CalibrateArgs* args) {
  auto* calibrate = app->add_subcommand(
      "calibrate", "Calibrate a robot's odometry: UMBmark squares, straight runs, k_L/k_R");
  calibrate->add_option("robot", args->robot, "Robot name (under robots/) or path to robot.yaml")
      ->required();
  calibrate->add_option("--runs", args->runs, "Runs of each kind (squares per direction, ...)")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  calibrate->add_option("--seed", args->seed, "Seed of the encoder noise")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  calibrate->add_option("--out", args->out, "Output folder for calibration.json");
  calibrate->add_flag("--encoder-noise", args->encoder_noise,
                      "Switch the robot's configured k_L, k_R encoder noise on");
  calibrate->footer(
      "Prints the runs, the estimates and the `odometry:` block for robot.yaml.\n"
      "Example:\n  pavilion calibrate pygmalion --runs 5 --seed 1 --out out/calib_pygmalion");
  return calibrate;
}

int RunCalibrateCommand(const CalibrateArgs& a) {
  sim::RobotConfig config = scenarios::LoadRobotFile(scenarios::ResolveRobotPath(a.robot));
  if (a.encoder_noise) config.encoders.noise = true;
  scenarios::OdometryCalibrationOptions options;
  options.runs = a.runs;
  options.seed = static_cast<std::uint64_t>(a.seed);
  spdlog::info("calibrating '{}': {} runs of each kind at {} Hz physics", config.description.model,
               options.runs, options.physics_rate_hz);
  const scenarios::OdometryCalibrationReport report = scenarios::CalibrateOdometry(config, options);
  std::printf("%s\n", scenarios::CalibrationTable(report).c_str());
  std::string command = "pavilion calibrate " + a.robot + " --runs " + std::to_string(a.runs) +
                        " --seed " + std::to_string(a.seed);
  if (a.encoder_noise) command += " --encoder-noise";
  char summary[200];
  std::snprintf(summary, sizeof summary,
                "UMBmark E_d %.5f, turn factor %.5f, straight scale %.5f; k from %d dof.",
                report.umbmark.radius_ratio_factor, report.umbmark.turn_factor,
                report.straight_scale, report.k_dof);
  std::printf("%s", scenarios::OdometryYamlBlock(report, "Calibrated by `" + command +
                                                             "` (docs/calibration.md):\n" + summary)
                        .c_str());
  if (!a.out.empty()) {
    const std::string path =
        (std::filesystem::path(a.out) / "calibration.json").lexically_normal().string();
    scenarios::WriteFileAtomically(path, scenarios::CalibrationJson(report));
    std::printf("wrote %s\n", path.c_str());
  }
  return 0;
}

}  // namespace pavilion::cli
