#pragma once

#include <numbers>
#include <string>
#include <vector>

#include "core/localization/encoder_odometry.h"
#include "core/types/pose2.h"
#include "sim/robot/robot_description.h"
#include "sim/sensors/laser_scanner.h"
#include "sim/sensors/robot_sensors.h"

namespace pavilion::sim {

// A laser scanner on a robot: its options and the pose of its (level) mount link.
struct LaserMount {
  std::string id;    // unique on the robot, names the sensor stream
  std::string link;  // URDF link
  LaserScannerOptions options;
  core::Pose2 robot_from_sensor;  // planar pose in the base frame
  double z_m = 0.0;               // height of the scan plane above the floor
};

// A camera on a robot; it looks along its link's +x axis (y left, z up in the image).
struct CameraMount {
  std::string id;
  std::string link;
  MountSpec mount;                         // the link's pose in the base frame
  int width_px = 640;                      // px, [1, 100000]
  int height_px = 480;                     // px, [1, 100000]
  double hfov_rad = std::numbers::pi / 3;  // horizontal field of view (pinhole), rad, (0, π)
  double rate_hz = 10.0;                   // images per second, Hz, (0, 1000]
  bool grayscale = false;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// Everything a robot file (robots/<name>/robot.yaml) defines: the physical
// model (from its URDF), sensors and the calibrated odometry. One robot's
// types, file to simulation: RobotDescription (its URDF) within RobotConfig
// (its robot.yaml) within scenarios::RobotEntry (a scenario's robot), built
// into a world as a SimRobot.
struct RobotConfig {
  std::string source_file;  // the robot.yaml
  RobotDescription description;
  EncoderOptions encoders;
  SystematicErrors systematic;  // how the simulated physical robot differs from the URDF
  // The calibrated odometry the robot's software uses (the calibration
  // scenario estimates it from the simulated robot).
  core::EncoderOdometryOptions odometry;
  std::vector<LaserMount> lasers;
  std::vector<BumperZone> bumpers;  // at most 32 (BumperReading's bit mask)
  double bumper_rate_hz = 50.0;     // bumper polling rate, a divisor of the physics rate
  std::vector<CameraMount> cameras;
};

}  // namespace pavilion::sim
