#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/geometry/planar_section.h"
#include "core/types/pose2.h"
#include "sim/crowd/crowd.h"
#include "sim/robot/robot_description.h"
#include "sim/sensors/robot_sensors.h"
#include "sim/world/world_description.h"

namespace pavilion::sim {

struct WorldOptions {
  double physics_rate_hz = 200.0;  // fixed physics step rate, [10, 10000] Hz
  int solver_iterations = 10;      // sequential-impulse iterations per step, [1, 100]
  double gravity_mps2 = 9.81;      // magnitude, pointing down, [0, 100]
  // Laser rays meet the static geometry (walls, boxes, meshes) baked into one
  // bounding-volume tree of triangles in a separate ray world, and the dynamic
  // bodies in the physics world only up to that hit: several times faster than
  // ray-testing every primitive. false: every ray tests the physics world's
  // primitives (the reference the benchmark compares against).
  bool baked_static_rays = true;

  void Validate() const;  // throws std::invalid_argument naming the field
};

enum class BodyShapeType { kBox, kCylinder, kSphere };

// A dynamic body's collision shape in its own frame (z up, origin at its centre).
struct BodyShape {
  BodyShapeType type = BodyShapeType::kCylinder;
  Eigen::Vector3d box_size_m{0.5, 0.5, 0.5};  // full extents, for kBox
  double radius_m = 0.25;                     // for kCylinder and kSphere
  double height_m = 1.7;                      // for kCylinder

  double HalfHeight() const;
};

// A dynamic body added to a world at start-up by a scenario.
struct BodySpec {
  std::string id;  // unique among world elements and bodies
  BodyShape shape;
  double mass_kg = 1.0;  // > 0
  core::Pose2 pose;      // initial footprint pose, resting on the floor
  std::string material;  // a material of the world
  bool upright = true;   // rotates about z only (visitor-like), never tips over
  bool driven = false;   // velocity is set every step (scripted motion)
  // How a driven body holds its set velocity: 0, against any force (a
  // motorized cart); > 0, by the driving force m (v0 - v) / tau of Helbing &
  // Molnar (1995), tau this relaxation time in seconds: a walker's finite
  // force, which a heavier body that resists (a robot on its braked wheels)
  // withstands instead of being bulldozed. >= 0.
  double drive_relaxation_s = 0.0;
};

struct BodyState {
  core::Pose2 pose;       // planar pose of the body frame
  double z_m = 0.0;       // height of the body centre
  double tilt_rad = 0.0;  // angle between the body z axis and the world z axis
  Eigen::Vector2d velocity_mps{0, 0};
  double yaw_rate_radps = 0.0;
};

// How a robot's wheels meet the floor.
enum class WheelModel {
  // The reference: chassis, two sphere wheels on hinge motors and caster
  // spheres on ball joints, each a rigid body in contact with the floor.
  kArticulated,
  // The fast path: the chassis is the only body; each wheel and caster is a
  // sphere under it whose floor contact a vertical ray finds, with traction
  // from ideal motors, lateral friction and frictionless casters solved on the
  // chassis (sim/robot/raycast_drive.h). The body carries the reference's part
  // masses welded together, so pushes tip and slide it as they do the
  // reference. Its wheels meet only the floor plane (a robot that must drive
  // onto other objects needs the reference) and are not bodies: rays and
  // sections meet its chassis and attachments only.
  kRaycast,
};

// "articulated" or "raycast".
const char* WheelModelName(WheelModel model);

// Where and how a robot enters the world: the world builds its body from the
// robot's model (RobotDescription) with the physical robot's systematic errors
// applied (mean radius and nominal wheelbase scaled), so odometry computed from
// the nominal model drifts as a real robot's does. The model's markers become
// upright cylinders fixed on the chassis (Robox's retro-reflective posts,
// §6.3.5.1); their materials, like the model's, are materials of the world.
struct RobotPlacement {
  std::string id;    // unique among world elements and bodies
  core::Pose2 pose;  // initial pose of the base frame
  WheelModel wheel_model = WheelModel::kArticulated;
};

// The true state of a robot.
struct RobotState {
  core::Pose2 pose;                    // base frame: on the floor, midway between the wheels
  double tilt_rad = 0.0;               // angle between the chassis z axis and the world z axis
  Eigen::Vector2d velocity_mps{0, 0};  // of the base origin, world frame
  double yaw_rate_radps = 0.0;
  // Wheel rotation relative to the chassis, unwrapped, positive forward (rad).
  double left_wheel_rad = 0.0;
  double right_wheel_rad = 0.0;
  double left_wheel_radps = 0.0;
  double right_wheel_radps = 0.0;
};

// An immutable view of the world after a step: what per-robot work of a tick
// reads. Such work writes only its own outputs, which are then merged in body
// order, so it can run in parallel without changing results.
struct TickSnapshot {
  std::int64_t tick = 0;
  double time_s = 0.0;
  std::vector<BodyState> bodies;           // indexed by body index
  std::vector<RobotState> robots;          // indexed by robot index
  std::vector<crowd::PersonState> people;  // the crowd's pool, by person index
};

// A crowd of visitors (sim/crowd/): people who walk by the social force
// model among the world's static geometry and its robots, seen by lasers as
// legs and a torso, pushing robots with bounded contact forces. The world
// supplies the walls (its static geometry cut near the floor and at body
// height); the rest comes from the scenario.
struct CrowdSpec {
  crowd::CrowdOptions options;
  core::Polygon2 entrance;   // where arrivals appear
  core::Polygon2 exit;       // where visitors leave
  core::Polygon2 roam_area;  // where watch spots and initial visitors go; empty: the floor
  std::vector<crowd::Attraction> attractions;  // exhibits' stations with their weights
  std::string material;                        // a material of the world, for every person
  std::string id_prefix = "visitor_";  // people's element ids: prefix + 3-digit number from 001
};

// The first surface a ray meets.
struct RayHit {
  bool hit = false;
  double distance_m = 0.0;  // from the ray's origin
  Eigen::Vector3d point_m{0, 0, 0};
  Eigen::Vector3d normal{0, 0, 0};  // unit surface normal, facing the ray
  int element = -1;                 // element index hit
};

// A dynamic element that a horizontal plane does not cut into circles or a
// convex polygon (a cylinder tilted too far, a box or chassis cut through its
// top or bottom face): the planar laser caster's fallback case. Every point of
// the element lies within radius_m of center_m horizontally.
struct UncutElement {
  int element = -1;
  Eigen::Vector2d center_m{0, 0};
  double radius_m = 0.0;
};

// The phases of a contact episode between two elements: they come within
// 5 mm (kContactDistanceM, contact_tracker.h; kBegin), they touch — a contact point at or below
// zero distance, or an impulse exchanged (kTouch, at most once per episode: a collision) — and they
// part again (kEnd). A pass within a few millimetres begins and ends without touching.
enum class ContactPhase { kBegin, kTouch, kEnd };

// A change of contact between two elements (static elements or bodies); the
// floor is not reported. `a` < `b` are element indices of PlanarSection order.
struct ContactChange {
  ContactPhase phase = ContactPhase::kBegin;
  int a = -1;
  int b = -1;
  Eigen::Vector3d point_m{0, 0, 0};  // a contact point, for begins and touches
  double impulse_ns = 0.0;           // largest normal impulse of the step, for begins and touches
  // The smallest distance between the pair's contact points (m, negative
  // inside): of the step for begins and touches, of the whole episode for ends.
  double distance_m = 0.0;
  bool touched = false;  // for ends: the episode held a touch
};

// The Bullet world of a simulation: static geometry from a WorldDescription, the
// floor, and dynamic bodies. Steps at a fixed rate and is deterministic: the
// same calls in the same order give the same states bit for bit.
//
// Element indices: 0 is the floor, then walls, boxes, cylinders, meshes and doors
// in description order, then bodies in the order they were added. Sections,
// contacts and ground truth all use these indices.
class World {
 public:
  // Builds the world; throws std::runtime_error (mesh files) or
  // std::invalid_argument (options, unknown material).
  World(WorldDescription description, const WorldOptions& options);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  // Adds a dynamic body; returns its body index (0, 1, ...).
  int AddBody(const BodySpec& spec);
  int body_count() const;
  const BodySpec& body_spec(int body) const;
  int body_element(int body) const;
  BodyState body_state(int body) const;

  // Adds a robot: chassis (a convex prism of the footprint, with its
  // attachments), two sphere wheels on hinge motors and frictionless caster
  // spheres, or with WheelModel::kRaycast the chassis alone on ray-cast wheels.
  // Its parts share one element group, which its own sensors ignore.
  // Throws std::invalid_argument for an inconsistent model. Returns the robot index.
  int AddRobot(const RobotDescription& model, const SystematicErrors& systematic,
               const RobotPlacement& placement);
  int robot_count() const;
  const RobotDescription& robot_model(int robot) const;
  const RobotPlacement& robot_placement(int robot) const;
  RobotState robot_state(int robot) const;
  // The element group of a robot's parts (pass to CastRay to skip them).
  int robot_group(int robot) const;
  // The chassis element (reported in contacts; the robot's own id).
  int robot_element(int robot) const;
  // Commands wheel speeds (rad/s, positive forward). The motors ramp towards
  // them at the model's acceleration limit, clamp them to its speed limit and
  // push with at most its torque limit.
  void SetWheelSpeeds(int robot, double left_radps, double right_radps);
  // Points (base frame, x and y) where the chassis touches anything but the
  // floor and the robot's own parts now: what tactile bumpers feel.
  std::vector<Eigen::Vector2d> RobotContactPoints(int robot) const;
  // The floor's normal force on the drive wheels (left, right) in the last
  // step, N (what their friction holds a push with).
  std::array<double, 2> DriveWheelLoads(int robot) const;
  // Switches a robot's drive motors on or off. Off, its wheels roll freely
  // with the floor whatever it commands (staff at Expo.02 pushed robots with
  // the motors disengaged, §6.5): a push rolls it away, and its encoders see
  // the rolling part of the motion.
  void SetMotorsEngaged(int robot, bool engaged);
  bool motors_engaged(int robot) const;
  // A horizontal impulse at the chassis' centre of mass (a push or a collision).
  void ApplyRobotImpulse(int robot, const Eigen::Vector2d& impulse_ns);
  // Stops a robot where it stands, at rest (staff holding it before a push);
  // its wheel angles, and so its encoders, are kept.
  void HaltRobot(int robot);
  // Moves a robot to a new pose at rest (a kidnap).
  void TeleportRobot(int robot, const core::Pose2& pose);

  // For driven bodies: the planar velocity (world frame) held during the next steps.
  void SetPlanarVelocity(int body, const Eigen::Vector2d& velocity_mps, double yaw_rate_radps);
  // A driven upright body that yields is not driven while it does: it stands
  // and gives way when pressed, sliding with the floor's Coulomb friction like
  // an undriven upright body (a person making room for a machine pushing
  // them), instead of holding its set velocity against any force.
  void SetYielding(int body, bool yielding);
  // Applies a horizontal impulse at the body's centre (a push).
  void ApplyImpulse(int body, const Eigen::Vector2d& impulse_ns);
  // Moves a body to a new pose at rest (a kidnap).
  void Teleport(int body, const core::Pose2& pose);

  // Adds the crowd (at most one); its pool of people become elements after
  // the bodies and robots added so far. Throws std::invalid_argument for bad
  // options or an unknown material.
  void AddCrowd(const CrowdSpec& spec, std::uint64_t seed);
  // The crowd, or null.
  const crowd::Crowd* crowd() const;
  crowd::Crowd* mutable_crowd();
  // The element of person i of the crowd's pool.
  int person_element(int person) const;

  // Swings a door of the description open or closed; throws std::out_of_range
  // for an unknown door id.
  void SetDoorOpen(const std::string& door_id, bool open);

  // The state of every body now.
  TickSnapshot Snapshot() const;

  // Advances one fixed physics step.
  void Step();
  std::int64_t tick() const;
  double time_s() const;
  double step_s() const;

  // The world cut at height z: static elements and the bodies at their current
  // poses. Element indices as above. Bodies the plane does not cut exactly
  // (see AppendDynamicSection) are approximated: cylinders cut through a cap
  // as circles, boxes cut through a cap as their upright extrusion.
  core::PlanarSection SectionAt(double height_m) const;
  // The static elements alone (walls, boxes, cylinders, meshes, doors in their
  // current state), with every element of the world listed.
  core::PlanarSection StaticSectionAt(double height_m) const;
  // Appends the cut of every body and robot part at its current pose: spheres
  // as circles; boxes and robot chassis exactly, at any tilt, while the plane
  // crosses only their sides; cylinders whose sides alone it crosses as
  // circles about the point where their axis meets the plane while tilted up
  // to max_cylinder_tilt_rad, as their ellipses beyond (CutCylinder). Other
  // elements the plane reaches are listed in `uncut`.
  void AppendDynamicSection(double height_m, double max_cylinder_tilt_rad, core::PlanarSection* out,
                            std::vector<UncutElement>* uncut) const;
  // Changes of the static geometry so far (door moves), from 0.
  std::int64_t static_revision() const;
  // Casts a ray from `from_m` to `to_m` and returns the closest hit, ignoring
  // the elements of `ignore_group` (the casting robot's parts) and, unless
  // `hit_transparent`, elements whose material is laser-transparent.
  // Thread-safe while the world does not change (between steps): with
  // WorldOptions::baked_static_rays (and not hit_transparent) rays are cast
  // in parallel; otherwise calls from several threads are serialized
  // (Bullet's world ray test is not made for concurrent use).
  RayHit CastRay(const Eigen::Vector3d& from_m, const Eigen::Vector3d& to_m, int ignore_group = -1,
                 bool hit_transparent = false) const;

  // Rays cast since the world was built (a performance figure).
  std::int64_t rays_cast() const;

  // Element ids and flags, indexed by element index.
  const std::vector<core::SectionElement>& elements() const;

  // Contact begins and ends since the last call, in a deterministic order:
  // Bullet's contacts, then people touching robots (not people touching
  // walls or each other, which the crowd model handles alone).
  std::vector<ContactChange> TakeContactChanges();

  const WorldDescription& description() const;

 private:
  // The crowd's step: people move, and their contact forces act on the robots.
  void StepCrowd(double dt);

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pavilion::sim
