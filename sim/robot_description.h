#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/types/pose2.h"

namespace pavilion::sim {

// The physical model of a differential-drive robot, in its base frame
// (x forward, y left, z up, origin on the floor midway between the wheels).
// Filled from robot.urdf (sim::LoadUrdfRobot) and robot.yaml (scenarios/).

struct WheelSpec {
  std::string joint;                     // URDF joint name
  double radius_m = 0.1;                 // > 0
  double width_m = 0.04;                 // > 0 (collision uses a sphere of the radius)
  double mass_kg = 1.0;                  // > 0
  Eigen::Vector2d position_m{0.0, 0.2};  // axle centre in the base frame (x, y)
};

struct CasterSpec {
  std::string link;  // URDF link name
  Eigen::Vector2d position_m{0.0, 0.0};
  double radius_m = 0.03;  // a nearly frictionless sphere touching the floor
};

// A sensor mount: a URDF link's pose in the base frame.
struct MountSpec {
  std::string link;
  core::Pose2 pose;  // planar pose in the base frame
  double z_m = 0.0;  // height above the floor
};

struct RobotDescription {
  std::string model;                         // e.g. "robox"
  std::vector<Eigen::Vector2d> footprint_m;  // convex chassis outline, counter-clockwise
  double chassis_base_z_m = 0.05;            // ground clearance of the chassis, >= 0
  double chassis_height_m = 0.5;             // > 0
  double chassis_mass_kg = 50.0;             // > 0
  WheelSpec left_wheel;
  WheelSpec right_wheel;
  std::vector<CasterSpec> casters;
  std::vector<MountSpec> mounts;         // every fixed link that may carry a sensor
  double max_wheel_torque_nm = 20.0;     // motor torque limit, > 0
  double max_wheel_speed_radps = 20.0;   // > 0
  double max_wheel_accel_radps2 = 20.0;  // command ramp, > 0
  std::string material;                  // world material for the chassis

  double wheelbase_m() const { return left_wheel.position_m.y() - right_wheel.position_m.y(); }
  // The mount of a link; throws std::out_of_range naming it when missing.
  const MountSpec& Mount(const std::string& link) const;
};

}  // namespace pavilion::sim
