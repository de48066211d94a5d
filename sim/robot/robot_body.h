#pragma once

#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

#include "core/geometry/planar_section.h"
#include "core/types/pose2.h"
#include "sim/robot/raycast_drive.h"
#include "sim/world/element_table.h"
#include "sim/world/physics_world.h"
#include "sim/world/prism_registry.h"
#include "sim/world/world.h"
#include "sim/world/world_description.h"

// Bullet types are only declared here (the layer lint keeps Bullet includes out
// of every sim/ header); robot_body.cc and its users include Bullet.
class btCollisionShape;
class btCompoundShape;
class btConvexHullShape;
class btHingeConstraint;
class btRigidBody;

namespace pavilion::sim {

// What a robot body is built into: parts of one sim::World's implementation,
// all outliving the body.
struct RobotBodyContext {
  const WorldDescription* description = nullptr;
  const WorldOptions* options = nullptr;
  ElementTable* elements = nullptr;
  PhysicsWorld* physics = nullptr;
  PrismRegistry* prisms = nullptr;  // the chassis' slabs are registered here
};

// One robot of a sim::World in its physics world (internal to the world): the
// chassis (a stack of convex prisms, RobotDescription::ChassisPrisms, with its
// attachments), two sphere wheels on hinge motors and caster spheres on ball
// joints, or with WheelModel::kRaycast the chassis alone on ray-cast wheels (RaycastDrive).
// Its parts share one element group; the chassis is its element and the
// attachments follow it. The physics world owns the Bullet objects; the body
// holds its state by value, so that a world's robots lie side by side in
// memory (World::Step and the sections visit them all every tick).
class RobotBody {
 public:
  // Validates the robot (std::invalid_argument naming it) and builds it at
  // placement.pose, at rest. `group` is the robot index.
  RobotBody(const RobotDescription& model, const SystematicErrors& systematic,
            const RobotPlacement& placement, int group, const RobotBodyContext& world);
  ~RobotBody();
  RobotBody(RobotBody&&) noexcept;
  RobotBody& operator=(RobotBody&&) noexcept;

  const RobotDescription& model() const { return model_; }
  const RobotPlacement& placement() const { return placement_; }
  int group() const { return group_; }
  int element() const { return element_; }

  RobotState State() const;
  // Targets of the motors (rad/s, positive forward), clamped to the speed limit.
  void SetWheelSpeeds(double left_radps, double right_radps);
  // See World::RobotContactPoints.
  std::vector<Eigen::Vector2d> ContactPoints(const btCollisionDispatcher& dispatcher) const;
  // The floor's normal force on each drive wheel (left, right) over the
  // last step, N: what their friction can hold against a push.
  std::array<double, 2> DriveWheelLoads(const btCollisionDispatcher& dispatcher) const;
  // A horizontal impulse where pushes act on the chassis.
  void ApplyImpulse(const Eigen::Vector2d& impulse_ns);
  // A horizontal impulse at a point of the chassis' outline (world x, y), at
  // the height pushes act at: it also turns the robot.
  void ApplyImpulseAt(const Eigen::Vector2d& impulse_ns, const Eigen::Vector2d& point_m);
  // Engages or disengages the drive motors (see World::SetMotorsEngaged).
  void SetMotorsEngaged(bool engaged);
  bool motors_engaged() const { return motors_engaged_; }
  // Puts the robot at `pose` at rest, its motor commands zeroed.
  void Teleport(const core::Pose2& pose);
  // Stops the robot where it stands: every part at rest, its wheels' angles
  // (the encoders) kept, its motor commands zeroed.
  void Halt();

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
  // A rigid part and where it sits in the robot's base frame (robot_body.cc).
  struct Part;
  // The masses of the articulated reference's bodies; they add up to the
  // model's total mass.
  struct PartMasses {
    double chassis_kg = 0.0;
    double wheel_kg[2] = {0.0, 0.0};  // left, right: the drive units lumped at the axles
    double caster_kg = 0.0;
  };
  // Where the physical robot's parts go: the drive wheels' radii and wheelbase
  // carry the systematic errors (mean radius and the wheel positions' midpoint
  // kept).
  struct PartLayout {
    double radius[2] = {0, 0};   // left, right drive wheel
    double wheel_y[2] = {0, 0};  // base frame
    // The chassis' centre of mass from the model, kept on the base's z axis
    // (the drive is symmetric) and inside the chassis' height.
    double chassis_com_z_m = 0.0;
    // Centre of mass of the body that carries the chassis: the chassis', or
    // the reference's parts welded together with WheelModel::kRaycast.
    double com_z_m = 0.0;
    PartMasses masses;
  };

  static PartMasses ReferencePartMasses(const RobotDescription& m);
  PartLayout LayOutParts() const;
  std::unique_ptr<btConvexHullShape> PrismHull(const ChassisPrism& prism) const;
  void AddMarkerCylinders(btCompoundShape* compound, int first_marker_element,
                          std::vector<std::unique_ptr<btCollisionShape>>* shapes) const;
  std::unique_ptr<btCompoundShape> BuildChassisShape(int first_marker_element);
  btVector3 ChassisInertia(double mass_kg) const;
  btVector3 WeldedInertia(const PartLayout& layout) const;
  void AddRaycastParts(std::unique_ptr<btCompoundShape> compound,
                       const btTransform& base_from_chassis, const PartLayout& layout,
                       const Material& material);
  void AddRaycastDrive(const PartLayout& layout);
  void AddArticulatedParts(std::unique_ptr<btCompoundShape> compound,
                           const btTransform& base_from_chassis, const PartLayout& layout,
                           const Material& material);
  void Place(const core::Pose2& pose);
  btTransform WorldFromBase() const;
  void SolveRaycastContacts(double dt);
  void UpdateWheelAngles();
  bool raycast() const { return drive_ != nullptr; }
  btRigidBody* chassis() const;
  btRigidBody* wheel(int side) const;

  RobotBodyContext world_;
  RobotDescription model_;
  SystematicErrors systematic_;
  RobotPlacement placement_;
  int group_ = -1;
  int element_ = -1;         // chassis (and attachments' object)
  int chassis_prisms_ = 1;   // the chassis compound's slabs, its first children
  std::vector<Part> parts_;  // chassis first, then left, right wheel, casters
  btHingeConstraint* hinge_[2] = {nullptr, nullptr};
  double com_z_m_ = 0.0;  // chassis centre of mass above the base origin
  double target_radps_[2] = {0, 0};
  double command_radps_[2] = {0, 0};
  double wheel_rad_[2] = {0, 0};  // unwrapped, positive forward
  double last_step_s_ = 0.0;
  bool motors_engaged_ = true;
  double last_hinge_rad_[2] = {0, 0};
  // WheelModel::kRaycast: the contact solver (left, right wheel, then
  // casters) and its per-wheel commands; parts_ then holds the chassis alone.
  std::unique_ptr<RaycastDrive> drive_;
  std::vector<double> drive_command_radps_;
  double push_height_m_ = 0.0;  // where pushes act, above the chassis body's centre of mass
};

}  // namespace pavilion::sim
