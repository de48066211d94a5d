#pragma once

#include <numbers>
#include <string>
#include <vector>

#include "core/features/camera_model.h"
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
  // The lens: k1..k4 of eq. 3.23's correction (core::CameraIntrinsics::radial);
  // all zero, an ideal pinhole. Each finite, |k| <= 10.
  double radial_k1 = 0.0;
  double radial_k2 = 0.0;
  double radial_k3 = 0.0;
  double radial_k4 = 0.0;
  double noise_grey = 0.0;  // the electronics' grey-level noise, one sigma, [0, 100]
  // The calibration's error of an edge's column, which all pixels of the edge
  // share (core::VerticalEdgeOptions::calibration_sigma_px), px, [0, 100].
  // 0.3 px: the renderer draws without anti-aliasing, so a silhouette lands
  // on the pixel boundary nearest its true column, the same on every row
  // (uniform within +-0.5 px: 0.29 px).
  double calibration_sigma_px = 0.3;
  // The frame grabber (§4.5.2.2): an image arrives this long after its
  // exposure; the robot's software takes the mean as known and stamps the
  // image at arrival minus the mean. s, [0, 1]; sigma [0, 0.1].
  double grabber_delay_s = 0.0;
  double grabber_delay_sigma_s = 0.0;

  // The camera's intrinsics: a centred pinhole of hfov_rad with the lens' coefficients.
  core::CameraIntrinsics Intrinsics() const;

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
