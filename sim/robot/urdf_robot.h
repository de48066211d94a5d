#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "sim/robot/robot_description.h"

namespace pavilion::sim {

// The URDF names a differential-drive robot is built from (robot.yaml gives them).
struct UrdfDriveNames {
  std::string base_link = "base_link";  // root link: on the floor, midway between the wheels
  std::string left_wheel_joint = "left_wheel_joint";    // continuous, axis +y in base_link
  std::string right_wheel_joint = "right_wheel_joint";  // continuous, axis +y in base_link
  std::string chassis_link = "chassis";                 // fixed to base_link, mass > 0
  std::vector<std::string> caster_links;                // fixed, sphere collision on the floor
};

// A URDF that cannot be read or does not describe a differential-drive robot.
// what() is one line naming the file, the line and element where known
// ("robot.urdf:12: joint 'left_wheel_joint': continuous joint has no <axis>").
class UrdfError : public std::runtime_error {
 public:
  // Which name of UrdfDriveNames does not resolve in the URDF, so that a caller
  // can point at where it was given; kNone for problems of the URDF itself.
  enum class Name {
    kNone,
    kBaseLink,
    kLeftWheelJoint,
    kRightWheelJoint,
    kChassisLink,
    kCasterLink
  };

  explicit UrdfError(const std::string& message, Name name = Name::kNone, int caster_index = -1)
      : std::runtime_error(message), name_(name), caster_index_(caster_index) {}
  Name unresolved_name() const { return name_; }
  int caster_index() const { return caster_index_; }  // for kCasterLink

 private:
  Name name_;
  int caster_index_;
};

// Reads a robot from a URDF file (urdfdom) into a RobotDescription: every
// link's pose in base_link by chaining fixed joint origins; the wheels' radius
// and width from their cylinder (or sphere) collision, position from the joint
// origin, mass from the inertial; casters; every fixed link as a mount; the
// chassis assembly's mass, centre of mass, inertia and collision shapes; and the
// footprint as the convex hull of that collision geometry seen from above, and
// its height range. Meshes (relative to the URDF's folder) are read with assimp.
// Fields the URDF does not hold (model name, motor limits, material, markers)
// keep their defaults. Throws UrdfError.
RobotDescription LoadUrdfRobot(const std::string& urdf_path, const UrdfDriveNames& names);

}  // namespace pavilion::sim
