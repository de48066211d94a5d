#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <map>
#include <string>
#include <vector>

#include "core/types/pose2.h"
#include "sim/world/world_description.h"

namespace pavilion::sim {

// The physical model of a differential-drive robot, in its base frame
// (x forward, y left, z up, origin on the floor midway between the wheels).
// Filled from robot.urdf (sim::LoadUrdfRobot) and robot.yaml (scenarios/).

struct WheelSpec {
  std::string joint;                     // URDF joint name
  double radius_m = 0.1;                 // > 0
  double width_m = 0.04;                 // > 0 (the articulated model rolls a sphere
                                         // of the radius that touches the floor alone)
  double mass_kg = 1.0;                  // > 0
  Eigen::Vector2d position_m{0.0, 0.2};  // axle centre in the base frame (x, y)
};

struct CasterSpec {
  std::string link;  // URDF link name
  Eigen::Vector2d position_m{0.0, 0.0};
  double radius_m = 0.03;  // a nearly frictionless sphere touching the floor
  // A caster on a spring suspension (the robot file's `suspension`): its
  // vertical stiffness and damping, N/m and N·s/m; 0: rigid.
  double stiffness_npm = 0.0;
  double damping_nspm = 0.0;
};

// A sensor mount: a URDF link's pose in the base frame. The link's orientation
// is yaw (pose.theta_rad) after pitch after roll, as URDF's rpy.
struct MountSpec {
  std::string link;
  core::Pose2 pose;        // planar pose in the base frame
  double z_m = 0.0;        // height above the floor
  double roll_rad = 0.0;   // about x; 0 for a level mount
  double pitch_rad = 0.0;  // about y; -π/2 points the link's x axis straight up
};

// One collision primitive of the chassis assembly (the chassis link and every
// link fixed to it, casters and wheels excluded), placed in the base frame.
struct CollisionShape {
  enum class Type { kBox, kCylinder, kSphere, kMesh };
  Type type = Type::kBox;
  std::string link;                                                   // URDF link it belongs to
  Eigen::Isometry3d base_from_shape = Eigen::Isometry3d::Identity();  // shape centre/frame
  Eigen::Vector3d box_size_m{0.1, 0.1, 0.1};                          // kBox: full extents
  double radius_m = 0.0;                                              // kCylinder, kSphere
  double length_m = 0.0;                      // kCylinder: along the shape's z axis
  std::string mesh_file;                      // kMesh: absolute path
  Eigen::Vector3d mesh_scale{1.0, 1.0, 1.0};  // kMesh
};

// An upright cylindrical marker on the robot (Robox's retro-reflective beacons
// in the blind zones between its two scanners, thesis §6.3.5.1).
struct MarkerSpec {
  std::string id;
  std::string link;                  // URDF link giving its axis, or empty
  Eigen::Vector2d position_m{0, 0};  // axis in the base frame (x, y)
  double radius_m = 0.02;            // > 0
  double base_z_m = 0.0;             // bottom above the floor, >= 0
  double height_m = 0.1;             // > 0
  std::string material;  // a material of `RobotDescription::materials` (or, scoped, of the world)
};

// A horizontal slab of the chassis assembly: a vertical prism over a convex
// counter-clockwise outline (base frame), from z0_m to z1_m above the floor.
struct ChassisPrism {
  std::vector<Eigen::Vector2d> outline_m;
  double z0_m = 0.0;
  double z1_m = 0.0;
};

struct RobotDescription {
  std::string model;                         // e.g. "robox"
  std::vector<Eigen::Vector2d> footprint_m;  // convex chassis outline, counter-clockwise
  double chassis_base_z_m = 0.05;            // ground clearance of the chassis, >= 0
  double chassis_height_m = 0.5;             // > 0
  double chassis_mass_kg = 50.0;  // > 0: chassis link and every link fixed to it, casters included
  WheelSpec left_wheel;
  WheelSpec right_wheel;
  std::vector<CasterSpec> casters;
  std::vector<MountSpec> mounts;         // every fixed link that may carry a sensor
  double max_wheel_torque_nm = 20.0;     // motor torque limit, > 0
  double max_wheel_speed_radps = 20.0;   // > 0
  double max_wheel_accel_radps2 = 20.0;  // command ramp, > 0
  std::string material;  // chassis material: a key of `materials` (or of the world's materials)

  // Filled by LoadUrdfRobot and the robot file (appended; the fields above are
  // what the Bullet world needs, these add detail).
  std::string urdf_file;  // the URDF it was read from, empty when built in code
  // Centre of mass and inertia (about the centre of mass, base axes) of the
  // chassis assembly whose total mass is chassis_mass_kg.
  Eigen::Vector3d chassis_com_m{0.0, 0.0, 0.3};
  Eigen::Matrix3d chassis_inertia_kgm2 = Eigen::Matrix3d::Identity();
  std::vector<CollisionShape> chassis_shapes;  // the URDF's collision geometry, base frame
  // The chassis as slabs stacked bottom to top (LoadUrdfRobot): a new slab
  // wherever a collision shape begins or ends, each the hull seen from above of
  // the shapes it crosses. Empty for robots built in code.
  std::vector<ChassisPrism> chassis_prisms;
  std::vector<MarkerSpec> markers;
  // Materials the robot's parts name (chassis `material`, markers), defined by
  // the robot file so that a robot looks the same in every world.
  std::map<std::string, Material> materials;

  double wheelbase_m() const { return left_wheel.position_m.y() - right_wheel.position_m.y(); }
  // The outline seen from above with the wheels (their tyres, 2 radius_m long
  // and width_m wide) and casters (their spheres' discs, as 16-gons): what
  // must clear an obstacle at any height, counter-clockwise, convex (the
  // navigation's robot polygon).
  std::vector<Eigen::Vector2d> OutlineWithWheels() const;
  // The slabs the simulator builds the chassis of (collisions, laser rays,
  // sections): chassis_prisms while footprint_m is the hull of their outlines;
  // otherwise (none, or a footprint given in place of the derived one, as
  // robot.yaml's chassis.footprint) one prism of footprint_m over the chassis'
  // height range.
  std::vector<ChassisPrism> ChassisPrisms() const;
  // Chassis assembly plus both wheels (kg).
  double total_mass_kg() const {
    return chassis_mass_kg + left_wheel.mass_kg + right_wheel.mass_kg;
  }
  // The mount of a link; throws std::out_of_range naming it when missing.
  const MountSpec& Mount(const std::string& link) const;
};

}  // namespace pavilion::sim
