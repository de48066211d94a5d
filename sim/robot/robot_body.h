#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "core/geometry/planar_section.h"
#include "core/types/pose2.h"
#include "sim/world/element_table.h"
#include "sim/world/physics_world.h"
#include "sim/world/prism_registry.h"
#include "sim/world/world.h"
#include "sim/world/world_description.h"

namespace pavilion::sim {

// What a robot body is built into: parts of one sim::World's implementation,
// all outliving the body.
struct RobotBodyContext {
  const WorldDescription* description = nullptr;
  const WorldOptions* options = nullptr;
  ElementTable* elements = nullptr;
  PhysicsWorld* physics = nullptr;
  PrismRegistry* prisms = nullptr;  // the chassis hull is registered here
};

// One robot of a sim::World in its physics world (internal to the world): the
// chassis (a convex prism of the footprint with its attachments), two sphere
// wheels on hinge motors and caster spheres on ball joints, or with
// WheelModel::kRaycast the chassis alone on ray-cast wheels (RaycastDrive).
// Its parts share one element group; the chassis is its element and the
// attachments follow it. The physics world owns the Bullet objects.
class RobotBody {
 public:
  // Validates `spec` (std::invalid_argument naming the robot) and builds the
  // robot at spec.pose, at rest. `group` is the robot index.
  RobotBody(const RobotSpec& spec, int group, const RobotBodyContext& world);
  ~RobotBody();
  RobotBody(const RobotBody&) = delete;
  RobotBody& operator=(const RobotBody&) = delete;

  const RobotSpec& spec() const;
  int group() const;
  int element() const;

  RobotState State() const;
  // Targets of the motors (rad/s, positive forward), clamped to the speed limit.
  void SetWheelSpeeds(double left_radps, double right_radps);
  // See World::RobotContactPoints.
  std::vector<Eigen::Vector2d> ContactPoints(const btCollisionDispatcher& dispatcher) const;
  // A horizontal impulse where pushes act on the chassis.
  void ApplyImpulse(const Eigen::Vector2d& impulse_ns);
  // Puts the robot at `pose` at rest, its motor commands zeroed.
  void Teleport(const core::Pose2& pose);

  // Before a physics step of `dt_s`: ramps the motor commands towards their
  // targets and drives the hinge motors, or solves the ray-cast wheel contacts.
  void BeforeStep(double dt_s);
  // After the physics step: the wheel angles.
  void AfterStep(double dt_s);

  // Appends the cut of the chassis, its attachments and its wheel and caster
  // spheres by the plane z = height_m (see World::AppendDynamicSection).
  void AppendSection(double height_m, double max_cylinder_tilt_rad, const PrismRegistry& prisms,
                     core::PlanarSection* out, std::vector<UncutElement>* uncut) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pavilion::sim
