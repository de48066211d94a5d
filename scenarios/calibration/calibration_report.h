#pragma once

// What `pavilion calibrate` prints and writes from an odometry calibration:
// calibration.json, the robot.yaml block and the terminal table.

#include <string>

#include "scenarios/calibration/odometry_calibration.h"

namespace pavilion::scenarios {

// calibration.json: options, truth, estimates and per-run errors (deterministic).
std::string CalibrationJson(const OdometryCalibrationReport& report);

// The `odometry:` block of robot.yaml with the calibrated values; each line of
// `comment` becomes a comment line at its top.
std::string OdometryYamlBlock(const OdometryCalibrationReport& report, const std::string& comment);

// A plain-text table of the runs and the estimates, for the terminal.
std::string CalibrationTable(const OdometryCalibrationReport& report);

}  // namespace pavilion::scenarios
