#include "sim/robot/robot_body.h"

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/robot/raycast_drive.h"
#include "sim/world/bullet_conversions.h"
#include "sim/world/contact_tracker.h"
#include "sim/world/shape_sections.h"

namespace pavilion::sim {
namespace {

// Robots (chosen, not from the thesis): friction coefficient of the drive
// wheels' tread (combined by product with the floor's) and the casters' mass
// (taken from the chassis' so that the robot weighs what its model says).
constexpr double kWheelTreadFriction = 1.0;
constexpr double kCasterMassKg = 0.5;
// Each drive wheel body carries at least this fraction of the chassis' mass:
// the drive unit (wheel, gearbox, motor) lumped at the axle, taken from the
// chassis so that the total stays as modelled. Bullet's sequential-impulse
// solver converges poorly across large mass ratios: with Robox's 2.5 kg wheels
// under a 110 kg chassis and 10 iterations, wheel-floor friction slipped by
// 72 mm over a 0.6 m/s half circle and 15 mm in each 0.5 s start; at 1/8 of the
// chassis the slip falls to ≈ 1 cm and a few millimetres (measured with the
// same half circle; tests/sim/robot/robot_world_test.cc holds the straight drive).
constexpr double kMinWheelMassFraction = 1.0 / 8.0;
// Sign relating Bullet's hinge angle and motor velocity (B relative to A about
// the axis in A) to "positive forward" wheel rotation; established by the
// forward-drive test in tests/sim/robot/robot_world_test.cc.
constexpr double kHingeSign = -1.0;

// The masses of the articulated reference's bodies; they add up to the model's
// total mass.
struct PartMasses {
  double chassis_kg = 0.0;
  double wheel_kg[2] = {0.0, 0.0};  // left, right: the drive units lumped at the axles
  double caster_kg = kCasterMassKg;
};

PartMasses ReferencePartMasses(const RobotDescription& m) {
  PartMasses p;
  p.chassis_kg =
      std::max(0.5 * m.chassis_mass_kg,
               m.chassis_mass_kg - kCasterMassKg * static_cast<double>(m.casters.size()));
  p.wheel_kg[0] = m.left_wheel.mass_kg;
  p.wheel_kg[1] = m.right_wheel.mass_kg;
  const double min_wheel_mass_kg = kMinWheelMassFraction * p.chassis_kg;
  for (double& mass : p.wheel_kg) {
    const double lumped = std::max(mass, min_wheel_mass_kg);
    p.chassis_kg -= lumped - mass;
    mass = lumped;
  }
  return p;
}

double WrapAngle(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }

// True when the polygon is convex and counter-clockwise with non-zero area.
bool IsConvexCcw(const std::vector<Eigen::Vector2d>& p) {
  if (p.size() < 3) return false;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Eigen::Vector2d a = p[(i + 1) % p.size()] - p[i];
    const Eigen::Vector2d b = p[(i + 2) % p.size()] - p[(i + 1) % p.size()];
    if (a.x() * b.y() - a.y() * b.x() <= 0.0) return false;
  }
  return true;
}

// Throws std::invalid_argument naming the robot for an inconsistent spec.
void ValidateRobotSpec(const RobotSpec& spec, const ElementTable& elements) {
  const RobotDescription& m = spec.model;
  const auto fail = [&](const std::string& what) {
    throw std::invalid_argument("robot '" + spec.id + "': " + what);
  };
  if (spec.id.empty()) throw std::invalid_argument("robot id must not be empty");
  if (elements.Contains(spec.id)) fail("id is already used by a world element or body");
  if (!IsConvexCcw(m.footprint_m)) fail("footprint must be a convex counter-clockwise polygon");
  if (!(m.chassis_height_m > 0.0)) fail("chassis height must be > 0");
  if (!(m.chassis_base_z_m >= 0.0)) fail("chassis base height must be >= 0");
  if (!(m.chassis_mass_kg > 0.0)) fail("chassis mass must be > 0");
  if (!(m.wheelbase_m() > 0.0)) fail("left wheel must be left of the right wheel");
  for (const WheelSpec* w : {&m.left_wheel, &m.right_wheel}) {
    if (!(w->radius_m > 0.0) || !(w->mass_kg > 0.0)) {
      fail("wheel '" + w->joint + "' needs radius > 0 and mass > 0");
    }
  }
  for (const CasterSpec& c : m.casters) {
    if (!(c.radius_m > 0.0)) fail("caster '" + c.link + "' needs radius > 0");
  }
  if (!(m.max_wheel_torque_nm > 0.0 && m.max_wheel_speed_radps > 0.0 &&
        m.max_wheel_accel_radps2 > 0.0)) {
    fail("motor torque, speed and acceleration limits must be > 0");
  }
  for (const RobotAttachment& a : spec.attachments) {
    if (!(a.radius_m > 0.0 && a.height_m > 0.0 && a.base_z_m >= 0.0)) {
      fail("attachment '" + a.name + "' needs radius > 0, height > 0 and base >= 0");
    }
  }
  try {
    spec.systematic.Validate();
  } catch (const std::invalid_argument& e) {
    fail(std::string("systematic errors: ") + e.what());
  }
}

// Where the physical robot's parts go: the drive wheels' radii and wheelbase
// carry the systematic errors (mean radius and the wheel positions' midpoint
// kept).
struct PartLayout {
  double radius[2] = {0, 0};   // left, right drive wheel
  double wheel_y[2] = {0, 0};  // base frame
  // The chassis' centre of mass from the model, kept on the base's z axis (the
  // drive is symmetric) and inside the chassis' height.
  double chassis_com_z_m = 0.0;
  // Centre of mass of the body that carries the chassis: the chassis', or the
  // reference's parts welded together with WheelModel::kRaycast.
  double com_z_m = 0.0;
  PartMasses masses;
};

PartLayout LayOutParts(const RobotSpec& spec) {
  const RobotDescription& m = spec.model;
  PartLayout layout;
  layout.com_z_m =
      std::clamp(m.chassis_com_m.z(), m.chassis_base_z_m, m.chassis_base_z_m + m.chassis_height_m);
  layout.chassis_com_z_m = layout.com_z_m;
  const double ratio = spec.systematic.wheel_radius_ratio;
  const double mean_radius = 0.5 * (m.left_wheel.radius_m + m.right_wheel.radius_m);
  layout.radius[0] = 2.0 * mean_radius / (1.0 + ratio);
  layout.radius[1] = 2.0 * mean_radius * ratio / (1.0 + ratio);
  const double mid_y = 0.5 * (m.left_wheel.position_m.y() + m.right_wheel.position_m.y());
  const double half_base = 0.5 * m.wheelbase_m() * spec.systematic.wheelbase_factor;
  layout.wheel_y[0] = mid_y + half_base;
  layout.wheel_y[1] = mid_y - half_base;
  layout.masses = ReferencePartMasses(m);
  if (spec.wheel_model == WheelModel::kRaycast) {
    // One body carries the reference's parts as if welded together: its centre
    // of mass is theirs (kept on the base's z axis, as the chassis').
    const PartMasses& masses = layout.masses;
    double moment = masses.chassis_kg * layout.chassis_com_z_m;
    for (int side = 0; side < 2; ++side) moment += masses.wheel_kg[side] * layout.radius[side];
    for (const CasterSpec& c : m.casters) moment += masses.caster_kg * c.radius_m;
    layout.com_z_m = moment / m.total_mass_kg();
  }
  return layout;
}

}  // namespace

struct RobotBody::Impl {
  struct Part {
    btRigidBody* rigid = nullptr;
    btTransform base_from_part;  // where the part sits in the robot's base frame
  };

  RobotBodyContext world;
  RobotSpec spec;
  int group = -1;
  int element = -1;         // chassis (and attachments' object)
  std::vector<Part> parts;  // chassis first, then left, right wheel, casters
  btHingeConstraint* hinge[2] = {nullptr, nullptr};
  double com_z_m = 0.0;  // chassis centre of mass above the base origin
  double target_radps[2] = {0, 0};
  double command_radps[2] = {0, 0};
  double wheel_rad[2] = {0, 0};  // unwrapped, positive forward
  double last_hinge_rad[2] = {0, 0};
  // WheelModel::kRaycast: the contact solver (left, right wheel, then
  // casters) and its per-wheel commands; parts then holds the chassis alone.
  std::unique_ptr<RaycastDrive> drive;
  std::vector<double> drive_command_radps;
  double push_height_m = 0.0;  // where pushes act, above the chassis body's centre of mass

  bool raycast() const { return drive != nullptr; }
  btRigidBody* chassis() const { return parts[0].rigid; }
  btRigidBody* wheel(int side) const { return parts[1 + side].rigid; }

  // The chassis: the footprint prism and the attachments in one compound whose
  // origin is the centre of mass. Child 0 is the prism (the chassis element);
  // child k >= 1 is attachment k - 1, its own element.
  std::unique_ptr<btCompoundShape> BuildChassisShape() {
    const RobotDescription& m = spec.model;
    auto compound = std::make_unique<btCompoundShape>();
    auto hull = std::make_unique<btConvexHullShape>();
    for (const Eigen::Vector2d& p : m.footprint_m) {
      hull->addPoint(btVector3(p.x(), p.y(), m.chassis_base_z_m - com_z_m), false);
      hull->addPoint(btVector3(p.x(), p.y(), m.chassis_base_z_m + m.chassis_height_m - com_z_m),
                     false);
    }
    if (spec.wheel_model == WheelModel::kRaycast) {
      hull->setMargin(0.0);  // the true outline, as walls (rays and contacts agree)
      // Bounds cached after the margin is gone: with the default 4 cm margin
      // in them, a chassis 4 cm above the floor overlaps it in the broadphase
      // and every step runs a convex test of chassis against floor for nothing.
      hull->recalcLocalAabb();
    } else {
      // The reference keeps the bounds with the margin: its robots' odometry
      // calibrations (robot.yaml) were made with the floor pairs this gives,
      // whose order in the solver changes the trajectories measurably.
      hull->recalcLocalAabb();
      hull->setMargin(0.0);
    }
    (*world.prisms)[hull.get()] = {m.footprint_m, m.chassis_base_z_m - com_z_m,
                                   m.chassis_base_z_m + m.chassis_height_m - com_z_m};
    btTransform identity;
    identity.setIdentity();
    compound->addChildShape(identity, hull.get());
    world.physics->KeepShape(std::move(hull));
    for (const RobotAttachment& a : spec.attachments) {
      auto cylinder =
          std::make_unique<btCylinderShapeZ>(btVector3(a.radius_m, a.radius_m, 0.5 * a.height_m));
      btTransform t;
      t.setIdentity();
      t.setOrigin(
          btVector3(a.position_m.x(), a.position_m.y(), a.base_z_m + 0.5 * a.height_m - com_z_m));
      compound->addChildShape(t, cylinder.get());
      world.physics->KeepShape(std::move(cylinder));
    }
    return compound;
  }

  // The inertia of the reference's bodies welded together, about their common
  // centre of mass: the chassis' as the reference computes it (its compound's)
  // plus each wheel and caster as a solid sphere, by the parallel-axis theorem.
  btVector3 WeldedInertia(btCompoundShape* compound, const PartLayout& layout) const {
    const RobotDescription& m = spec.model;
    const PartMasses& masses = layout.masses;
    const double com_z = com_z_m;
    btVector3 inertia(0, 0, 0);
    compound->calculateLocalInertia(masses.chassis_kg, inertia);
    const double dz = layout.chassis_com_z_m - com_z;
    inertia += masses.chassis_kg * btVector3(dz * dz, dz * dz, 0.0);
    const auto add_sphere = [&](double mass, const btVector3& centre, double r) {
      const btVector3 p = centre - btVector3(0, 0, com_z);
      const double own = 0.4 * mass * r * r;
      inertia += btVector3(mass * (p.y() * p.y() + p.z() * p.z()) + own,
                           mass * (p.x() * p.x() + p.z() * p.z()) + own,
                           mass * (p.x() * p.x() + p.y() * p.y()) + own);
    };
    const WheelSpec* wheels[2] = {&m.left_wheel, &m.right_wheel};
    for (int side = 0; side < 2; ++side) {
      add_sphere(masses.wheel_kg[side],
                 btVector3(wheels[side]->position_m.x(), layout.wheel_y[side], layout.radius[side]),
                 layout.radius[side]);
    }
    for (const CasterSpec& c : m.casters) {
      add_sphere(masses.caster_kg, btVector3(c.position_m.x(), c.position_m.y(), c.radius_m),
                 c.radius_m);
    }
    return inertia;
  }

  // The chassis of a WheelModel::kRaycast robot: `compound` (origin at the
  // common centre of mass of the reference's parts, `base_from_chassis`)
  // carrying the mass of the whole robot, so that a push or a collision tips
  // and slides the robot as it does the reference (whose lumped drive units
  // make it bottom-heavy), and the contact solver of its wheels and casters.
  void AddRaycastParts(std::unique_ptr<btCompoundShape> compound,
                       const btTransform& base_from_chassis, const PartLayout& layout,
                       const Material& material, int first_attachment) {
    const RobotDescription& m = spec.model;
    const btVector3 inertia = WeldedInertia(compound.get(), layout);
    // Pushes act where they act on the reference: at its chassis' centre of mass.
    push_height_m = layout.chassis_com_z_m - com_z_m;
    btRigidBody* body =
        world.physics->AddDynamic(std::move(compound), m.total_mass_kg(), base_from_chassis,
                                  material.friction, material.restitution, element, &inertia);
    body->setUserIndex2(spec.attachments.empty() ? -1 : first_attachment);
    parts.push_back({body, base_from_chassis});
    AddRaycastDrive(layout);
  }

  // Wheels as the reference builds them (systematic errors applied), then casters.
  void AddRaycastDrive(const PartLayout& layout) {
    const RobotDescription& m = spec.model;
    const WorldDescription& description = *world.description;
    const double com_z = com_z_m;
    const WheelSpec* wheels[2] = {&m.left_wheel, &m.right_wheel};
    const double tread =
        kWheelTreadFriction * description.MaterialNamed(description.floor.material).friction;
    std::vector<RaycastWheelSpec> specs;
    for (int side = 0; side < 2; ++side) {
      specs.push_back(
          {{wheels[side]->position_m.x(), layout.wheel_y[side], layout.radius[side] - com_z},
           layout.radius[side],
           true,
           tread,
           m.max_wheel_torque_nm});
    }
    for (const CasterSpec& c : m.casters) {
      specs.push_back({{c.position_m.x(), c.position_m.y(), c.radius_m - com_z}, c.radius_m});
    }
    RaycastDriveOptions options;
    options.iterations = world.options->solver_iterations;
    options.gravity_mps2 = world.options->gravity_mps2;
    options.floor_min_m = description.floor.min_m;
    options.floor_max_m = description.floor.max_m;
    drive_command_radps.assign(specs.size(), 0.0);
    drive = std::make_unique<RaycastDrive>(std::move(specs), options);
  }

  // The articulated reference: chassis, drive wheels on hinge motors, casters
  // (nearly frictionless spheres) on ball joints.
  void AddArticulatedParts(std::unique_ptr<btCompoundShape> compound,
                           const btTransform& base_from_chassis, const PartLayout& layout,
                           const Material& material, int first_attachment) {
    const RobotDescription& m = spec.model;
    PhysicsWorld& physics = *world.physics;
    btRigidBody* body =
        physics.AddDynamic(std::move(compound), layout.masses.chassis_kg, base_from_chassis,
                           material.friction, material.restitution, element);
    body->setUserIndex2(spec.attachments.empty() ? -1 : first_attachment);
    parts.push_back({body, base_from_chassis});
    const WheelSpec* wheel_specs[2] = {&m.left_wheel, &m.right_wheel};
    for (int side = 0; side < 2; ++side) {
      const WheelSpec& w = *wheel_specs[side];
      btTransform base_from_wheel;
      base_from_wheel.setIdentity();
      base_from_wheel.setOrigin(
          btVector3(w.position_m.x(), layout.wheel_y[side], layout.radius[side]));
      const int wheel_element = world.elements->Add(
          spec.id + (side == 0 ? "/left_wheel" : "/right_wheel"), m.material, true, group);
      btRigidBody* wheel_body = physics.AddDynamic(
          std::make_unique<btSphereShape>(layout.radius[side]), layout.masses.wheel_kg[side],
          base_from_wheel, kWheelTreadFriction, 0.0, wheel_element);
      parts.push_back({wheel_body, base_from_wheel});
      const btVector3 pivot_in_chassis = base_from_chassis.inverse() * base_from_wheel.getOrigin();
      auto joint = std::make_unique<btHingeConstraint>(*body, *wheel_body, pivot_in_chassis,
                                                       btVector3(0, 0, 0), btVector3(0, 1, 0),
                                                       btVector3(0, 1, 0));
      hinge[side] = joint.get();
      physics.AddConstraint(std::move(joint), true);
    }
    for (const CasterSpec& c : m.casters) {
      btTransform base_from_caster;
      base_from_caster.setIdentity();
      base_from_caster.setOrigin(btVector3(c.position_m.x(), c.position_m.y(), c.radius_m));
      const int caster_element =
          world.elements->Add(spec.id + "/" + c.link, m.material, true, group);
      btRigidBody* caster =
          physics.AddDynamic(std::make_unique<btSphereShape>(c.radius_m), layout.masses.caster_kg,
                             base_from_caster, 0.0, 0.0, caster_element);
      parts.push_back({caster, base_from_caster});
      auto joint = std::make_unique<btPoint2PointConstraint>(
          *body, *caster, base_from_chassis.inverse() * base_from_caster.getOrigin(),
          btVector3(0, 0, 0));
      physics.AddConstraint(std::move(joint), true);
    }
  }

  // Places every part at `pose`, at rest.
  void Place(const core::Pose2& pose) {
    const btTransform world_from_base = PlanarTransform(pose, 0.0);
    for (Part& part : parts) {
      const btTransform t = world_from_base * part.base_from_part;
      part.rigid->setWorldTransform(t);
      part.rigid->setInterpolationWorldTransform(t);
      part.rigid->getMotionState()->setWorldTransform(t);
      part.rigid->setLinearVelocity(btVector3(0, 0, 0));
      part.rigid->setAngularVelocity(btVector3(0, 0, 0));
      part.rigid->clearForces();
    }
    if (raycast()) {
      // Its contact solver reads the world inertia tensor before Bullet
      // refreshes it; the reference's bodies are left as they always were.
      chassis()->updateInertiaTensor();
      drive->Reset();
    }
  }

  btTransform WorldFromBase() const {
    btTransform com_from_base;
    com_from_base.setIdentity();
    com_from_base.setOrigin(btVector3(0, 0, -com_z_m));
    return chassis()->getWorldTransform() * com_from_base;
  }

  // Solves a WheelModel::kRaycast robot's wheel contacts for the coming step
  // and leaves their impulses in the chassis' velocities.
  void SolveRaycastContacts(double dt) {
    btRigidBody* body = chassis();
    const btMatrix3x3& basis = body->getWorldTransform().getBasis();
    const btMatrix3x3& inv_inertia = body->getInvInertiaTensorWorld();
    RaycastChassis c;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        c.world_from_body(i, j) = basis[i][j];
        c.inverse_inertia(i, j) = inv_inertia[i][j];
      }
    }
    const btVector3& com = body->getCenterOfMassPosition();
    const btVector3& v = body->getLinearVelocity();
    const btVector3& w = body->getAngularVelocity();
    c.com_m = {com.x(), com.y(), com.z()};
    c.inverse_mass = body->getInvMass();
    c.linear_mps = {v.x(), v.y(), v.z()};
    c.angular_radps = {w.x(), w.y(), w.z()};
    drive_command_radps[0] = command_radps[0];
    drive_command_radps[1] = command_radps[1];
    drive->Solve(dt, drive_command_radps, &c);
    body->setLinearVelocity(ToBt(c.linear_mps));
    body->setAngularVelocity(ToBt(c.angular_radps));
  }

  // Accumulates each wheel's rotation from its hinge angle (wrapped by Bullet).
  void UpdateWheelAngles() {
    for (int side = 0; side < 2; ++side) {
      const double h = hinge[side]->getHingeAngle();
      wheel_rad[side] += kHingeSign * WrapAngle(h - last_hinge_rad[side]);
      last_hinge_rad[side] = h;
    }
  }
};

RobotBody::RobotBody(const RobotSpec& robot_spec, int group, const RobotBodyContext& world)
    : impl_(std::make_unique<Impl>()) {
  ValidateRobotSpec(robot_spec, *world.elements);
  const RobotDescription& m = robot_spec.model;
  const Material& material = world.description->MaterialNamed(m.material);
  Impl& im = *impl_;
  im.world = world;
  im.spec = robot_spec;
  im.group = group;
  const PartLayout layout = LayOutParts(robot_spec);
  im.com_z_m = layout.com_z_m;
  std::unique_ptr<btCompoundShape> compound = im.BuildChassisShape();
  im.element = world.elements->Add(robot_spec.id, m.material, true, group);
  const int first_attachment = world.elements->size();
  for (const RobotAttachment& a : robot_spec.attachments) {
    world.elements->Add(robot_spec.id + "/" + a.name, a.material, true, group);
  }
  btTransform base_from_chassis;
  base_from_chassis.setIdentity();
  base_from_chassis.setOrigin(btVector3(0, 0, im.com_z_m));
  if (robot_spec.wheel_model == WheelModel::kRaycast) {
    im.AddRaycastParts(std::move(compound), base_from_chassis, layout, material, first_attachment);
    im.Place(robot_spec.pose);
    return;
  }
  im.AddArticulatedParts(std::move(compound), base_from_chassis, layout, material,
                         first_attachment);
  im.Place(robot_spec.pose);
  // The parts entered the broadphase at their base-frame transforms, around the
  // origin; move their bounding boxes to the robot's pose now. Left to the next
  // step, every robot added meanwhile would overlap every earlier one there:
  // N^2/2 pairs created and dropped again (for the hall benchmark's 1000 robots,
  // 12.5 million pairs, 400 MB and seconds of start-up).
  for (Impl::Part& part : im.parts) world.physics->dynamics().updateSingleAabb(part.rigid);
  for (int side = 0; side < 2; ++side) im.last_hinge_rad[side] = im.hinge[side]->getHingeAngle();
}

RobotBody::~RobotBody() = default;

const RobotSpec& RobotBody::spec() const { return impl_->spec; }
int RobotBody::group() const { return impl_->group; }
int RobotBody::element() const { return impl_->element; }

RobotState RobotBody::State() const {
  const Impl& r = *impl_;
  const btRigidBody* chassis = r.chassis();
  const btTransform world_from_base = r.WorldFromBase();
  RobotState s;
  s.pose = {world_from_base.getOrigin().x(), world_from_base.getOrigin().y(),
            YawOf(world_from_base)};
  const btVector3 up = world_from_base.getBasis().getColumn(2);
  s.tilt_rad = std::acos(std::clamp(static_cast<double>(up.z()), -1.0, 1.0));
  const btVector3 v = chassis->getVelocityInLocalPoint(world_from_base.getOrigin() -
                                                       chassis->getCenterOfMassPosition());
  s.velocity_mps = {v.x(), v.y()};
  s.yaw_rate_radps = chassis->getAngularVelocity().z();
  if (r.raycast()) {
    s.left_wheel_rad = r.drive->angle_rad(0);
    s.right_wheel_rad = r.drive->angle_rad(1);
    s.left_wheel_radps = r.drive->rate_radps(0);
    s.right_wheel_radps = r.drive->rate_radps(1);
    return s;
  }
  const btVector3 axis = chassis->getWorldTransform().getBasis().getColumn(1);
  const double rates[2] = {
      (r.wheel(0)->getAngularVelocity() - chassis->getAngularVelocity()).dot(axis),
      (r.wheel(1)->getAngularVelocity() - chassis->getAngularVelocity()).dot(axis)};
  s.left_wheel_rad = r.wheel_rad[0];
  s.right_wheel_rad = r.wheel_rad[1];
  s.left_wheel_radps = rates[0];
  s.right_wheel_radps = rates[1];
  return s;
}

void RobotBody::SetWheelSpeeds(double left_radps, double right_radps) {
  Impl& r = *impl_;
  const double limit = r.spec.model.max_wheel_speed_radps;
  r.target_radps[0] = std::clamp(left_radps, -limit, limit);
  r.target_radps[1] = std::clamp(right_radps, -limit, limit);
}

std::vector<Eigen::Vector2d> RobotBody::ContactPoints(
    const btCollisionDispatcher& dispatcher) const {
  return TouchPoints(dispatcher, impl_->chassis(), impl_->WorldFromBase().inverse());
}

void RobotBody::ApplyImpulse(const Eigen::Vector2d& impulse_ns) {
  const Impl& r = *impl_;
  const btVector3 impulse(impulse_ns.x(), impulse_ns.y(), 0.0);
  if (r.push_height_m == 0.0) {
    r.chassis()->applyCentralImpulse(impulse);
  } else {
    const btVector3 up = r.chassis()->getWorldTransform().getBasis().getColumn(2);
    r.chassis()->applyImpulse(impulse, r.push_height_m * up);
  }
}

void RobotBody::Teleport(const core::Pose2& pose) {
  Impl& r = *impl_;
  r.Place(pose);
  for (int side = 0; side < 2; ++side) {
    r.command_radps[side] = 0.0;
    r.target_radps[side] = 0.0;
    if (!r.raycast()) r.last_hinge_rad[side] = r.hinge[side]->getHingeAngle();
  }
}

void RobotBody::BeforeStep(double dt) {
  Impl& r = *impl_;
  const RobotDescription& m = r.spec.model;
  for (int side = 0; side < 2; ++side) {
    // Acceleration ramp towards the commanded speed; the motor delivers at
    // most the torque limit over the step.
    const double step = m.max_wheel_accel_radps2 * dt;
    r.command_radps[side] += std::clamp(r.target_radps[side] - r.command_radps[side], -step, step);
    if (!r.raycast()) {
      r.hinge[side]->enableAngularMotor(true, kHingeSign * r.command_radps[side],
                                        m.max_wheel_torque_nm * dt);
    }
  }
  if (r.raycast()) r.SolveRaycastContacts(dt);
}

void RobotBody::AfterStep(double dt) {
  if (impl_->raycast()) {
    impl_->drive->Integrate(dt);
  } else {
    impl_->UpdateWheelAngles();
  }
}

void RobotBody::AppendSection(double z, double max_cylinder_tilt_rad, const PrismRegistry& prisms,
                              core::PlanarSection* out, std::vector<UncutElement>* uncut) const {
  const Impl& robot = *impl_;
  // The chassis compound (origin at the centre of mass): child 0 the
  // footprint prism, child k >= 1 attachment k - 1.
  const btRigidBody* chassis = robot.chassis();
  const btTransform& t = chassis->getWorldTransform();
  const auto* compound = static_cast<const btCompoundShape*>(chassis->getCollisionShape());
  const RayPrism& prism = prisms.at(compound->getChildShape(0));
  CutPrism(t * compound->getChildTransform(0), prism.polygon, prism.z0, prism.z1, z, robot.element,
           out, uncut);
  for (std::size_t k = 0; k < robot.spec.attachments.size(); ++k) {
    const RobotAttachment& a = robot.spec.attachments[k];
    const int child = static_cast<int>(k) + 1;
    CutCylinder(t * compound->getChildTransform(child), a.radius_m, 0.5 * a.height_m, z,
                max_cylinder_tilt_rad, chassis->getUserIndex2() + static_cast<int>(k), out, uncut);
  }
  for (std::size_t p = 1; p < robot.parts.size(); ++p) {
    const btRigidBody* rb = robot.parts[p].rigid;
    const auto* sphere = static_cast<const btSphereShape*>(rb->getCollisionShape());
    CutSphere(rb->getWorldTransform().getOrigin(), sphere->getRadius(), z, rb->getUserIndex(), out);
  }
}

}  // namespace pavilion::sim
