#include "sim/robot/robot_body.h"

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/types/pose2.h"
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
// On an uneven floor the fast model's wheels and casters are springs: a solid
// rubber tyre of a 0.1 m wheel deflects about 2 mm under a quarter of a
// 110 kg Robox at this stiffness, damped near critically for that load
// (chosen; a rigid four-point support would leave a drive wheel in the air
// over a 1-2 mm dip between its contacts). On the flat floor they stay rigid.
constexpr double kTyreStiffnessNpm = 1.5e5;
constexpr double kTyreDampingNspm = 2.0e3;

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

// Throws std::invalid_argument naming the robot for an inconsistent model.
void ValidateRobot(const RobotDescription& m, const SystematicErrors& systematic,
                   const RobotPlacement& placement, const ElementTable& elements) {
  const auto fail = [&](const std::string& what) {
    throw std::invalid_argument("robot '" + placement.id + "': " + what);
  };
  if (placement.id.empty()) throw std::invalid_argument("robot id must not be empty");
  if (elements.Contains(placement.id)) fail("id is already used by a world element or body");
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
  for (const MarkerSpec& a : m.markers) {
    if (!(a.radius_m > 0.0 && a.height_m > 0.0 && a.base_z_m >= 0.0)) {
      fail("attachment '" + a.id + "' needs radius > 0, height > 0 and base >= 0");
    }
  }
  try {
    systematic.Validate();
  } catch (const std::invalid_argument& e) {
    fail(std::string("systematic errors: ") + e.what());
  }
}

}  // namespace

struct RobotBody::Part {
  btRigidBody* rigid = nullptr;
  btTransform base_from_part;  // where the part sits in the robot's base frame
};

RobotBody::PartMasses RobotBody::ReferencePartMasses(const RobotDescription& m) {
  PartMasses p;
  p.caster_kg = kCasterMassKg;
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

RobotBody::PartLayout RobotBody::LayOutParts() const {
  const RobotDescription& m = model_;
  PartLayout layout;
  layout.com_z_m =
      std::clamp(m.chassis_com_m.z(), m.chassis_base_z_m, m.chassis_base_z_m + m.chassis_height_m);
  layout.chassis_com_z_m = layout.com_z_m;
  const double ratio = systematic_.wheel_radius_ratio;
  const double mean_radius =
      0.5 * (m.left_wheel.radius_m + m.right_wheel.radius_m) * systematic_.mean_radius_factor;
  layout.radius[0] = 2.0 * mean_radius / (1.0 + ratio);
  layout.radius[1] = 2.0 * mean_radius * ratio / (1.0 + ratio);
  const double mid_y = 0.5 * (m.left_wheel.position_m.y() + m.right_wheel.position_m.y());
  const double half_base = 0.5 * m.wheelbase_m() * systematic_.wheelbase_factor;
  layout.wheel_y[0] = mid_y + half_base;
  layout.wheel_y[1] = mid_y - half_base;
  layout.masses = ReferencePartMasses(m);
  if (placement_.wheel_model == WheelModel::kRaycast) {
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

// A slab of the chassis as a Bullet hull in the chassis compound's frame
// (origin at the centre of mass, com_z_m above the floor), its cached bounds
// as the wheel model wants them.
std::unique_ptr<btConvexHullShape> RobotBody::PrismHull(const ChassisPrism& prism) const {
  auto hull = std::make_unique<btConvexHullShape>();
  for (const Eigen::Vector2d& p : prism.outline_m) {
    hull->addPoint(btVector3(p.x(), p.y(), prism.z0_m - com_z_m_), false);
    hull->addPoint(btVector3(p.x(), p.y(), prism.z1_m - com_z_m_), false);
  }
  if (placement_.wheel_model == WheelModel::kRaycast) {
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
  return hull;
}

// Adds the markers' cylinders to `compound` (kept alive in `shapes`); each
// cylinder's shape carries its marker's element as its user index (-1: none).
void RobotBody::AddMarkerCylinders(btCompoundShape* compound, int first_marker_element,
                                   std::vector<std::unique_ptr<btCollisionShape>>* shapes) const {
  for (std::size_t k = 0; k < model_.markers.size(); ++k) {
    const MarkerSpec& a = model_.markers[k];
    auto cylinder =
        std::make_unique<btCylinderShapeZ>(btVector3(a.radius_m, a.radius_m, 0.5 * a.height_m));
    cylinder->setUserIndex(first_marker_element < 0 ? -1
                                                    : first_marker_element + static_cast<int>(k));
    btTransform t;
    t.setIdentity();
    t.setOrigin(
        btVector3(a.position_m.x(), a.position_m.y(), a.base_z_m + 0.5 * a.height_m - com_z_m_));
    compound->addChildShape(t, cylinder.get());
    shapes->push_back(std::move(cylinder));
  }
}

// The chassis: its slabs (RobotDescription::ChassisPrisms, bottom to top) and
// the markers in one compound whose origin is the centre of mass. Children
// 0 .. chassis_prisms_ - 1 are the slabs (the chassis element, registered as
// prisms); the rest are the markers, each child's shape carrying its element.
std::unique_ptr<btCompoundShape> RobotBody::BuildChassisShape(int first_marker_element) {
  auto compound = std::make_unique<btCompoundShape>();
  btTransform identity;
  identity.setIdentity();
  for (const ChassisPrism& prism : model_.ChassisPrisms()) {
    std::unique_ptr<btConvexHullShape> hull = PrismHull(prism);
    (*world_.prisms)[hull.get()] = {prism.outline_m, prism.z0_m - com_z_m_, prism.z1_m - com_z_m_};
    compound->addChildShape(identity, hull.get());
    world_.physics->KeepShape(std::move(hull));
  }
  chassis_prisms_ = compound->getNumChildShapes();
  std::vector<std::unique_ptr<btCollisionShape>> markers;
  AddMarkerCylinders(compound.get(), first_marker_element, &markers);
  for (auto& shape : markers) world_.physics->KeepShape(std::move(shape));
  return compound;
}

// The chassis' inertia about its centre of mass as Bullet gives a compound (a
// solid box of its bounds), taken from its envelope: one prism of the
// footprint over the chassis' height range, and the markers. So it does not
// depend on the slabs the chassis is built of (a recess at scanner height
// leaves it as it was), nor do the dynamics and the calibrations made with them.
btVector3 RobotBody::ChassisInertia(double mass_kg) const {
  const RobotDescription& m = model_;
  btCompoundShape envelope;
  btTransform identity;
  identity.setIdentity();
  const std::unique_ptr<btConvexHullShape> hull =
      PrismHull({m.footprint_m, m.chassis_base_z_m, m.chassis_base_z_m + m.chassis_height_m});
  envelope.addChildShape(identity, hull.get());
  std::vector<std::unique_ptr<btCollisionShape>> markers;
  AddMarkerCylinders(&envelope, -1, &markers);
  btVector3 inertia(0, 0, 0);
  envelope.calculateLocalInertia(mass_kg, inertia);
  return inertia;
}

// The inertia of the reference's bodies welded together, about their common
// centre of mass: the chassis' as the reference computes it (ChassisInertia)
// plus each wheel and caster as a solid sphere, by the parallel-axis theorem.
btVector3 RobotBody::WeldedInertia(const PartLayout& layout) const {
  const RobotDescription& m = model_;
  const PartMasses& masses = layout.masses;
  const double com_z = com_z_m_;
  btVector3 inertia = ChassisInertia(masses.chassis_kg);
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
void RobotBody::AddRaycastParts(std::unique_ptr<btCompoundShape> compound,
                                const btTransform& base_from_chassis, const PartLayout& layout,
                                const Material& material) {
  const RobotDescription& m = model_;
  const btVector3 inertia = WeldedInertia(layout);
  // Pushes act where they act on the reference: at its chassis' centre of mass.
  push_height_m_ = layout.chassis_com_z_m - com_z_m_;
  btRigidBody* body =
      world_.physics->AddDynamic(std::move(compound), m.total_mass_kg(), base_from_chassis,
                                 material.friction, material.restitution, element_, &inertia);
  parts_.push_back({body, base_from_chassis});
  AddRaycastDrive(layout);
}

// Wheels as the reference builds them (systematic errors applied), then casters.
void RobotBody::AddRaycastDrive(const PartLayout& layout) {
  const RobotDescription& m = model_;
  const WorldDescription& description = *world_.description;
  const double com_z = com_z_m_;
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
    RaycastWheelSpec caster{{c.position_m.x(), c.position_m.y(), c.radius_m - com_z}, c.radius_m};
    caster.stiffness_npm = c.stiffness_npm;
    caster.damping_nspm = c.damping_nspm;
    specs.push_back(caster);
  }
  RaycastDriveOptions options;
  options.iterations = world_.options->solver_iterations;
  options.gravity_mps2 = world_.options->gravity_mps2;
  options.floor_min_m = description.floor.min_m;
  options.floor_max_m = description.floor.max_m;
  options.relief = &description.floor.relief;
  if (!description.floor.relief.flat()) {
    options.contact_stiffness_npm = kTyreStiffnessNpm;
    options.contact_damping_nspm = kTyreDampingNspm;
  }
  drive_command_radps_.assign(specs.size(), 0.0);
  drive_ = std::make_unique<RaycastDrive>(std::move(specs), options);
}

// The articulated reference: chassis, drive wheels on hinge motors, casters
// (nearly frictionless spheres) on ball joints. A wheel's sphere stands in for
// a tyre as wide as WheelSpec::width_m inside the chassis; it touches the floor
// alone (Pygmalion's would bulge 4 cm beyond its 45 cm chassis and catch door
// posts the real wheel cannot reach), as the ray-cast drive's wheels do.
void RobotBody::AddArticulatedParts(std::unique_ptr<btCompoundShape> compound,
                                    const btTransform& base_from_chassis, const PartLayout& layout,
                                    const Material& material) {
  const RobotDescription& m = model_;
  PhysicsWorld& physics = *world_.physics;
  const btVector3 inertia = ChassisInertia(layout.masses.chassis_kg);
  btRigidBody* body =
      physics.AddDynamic(std::move(compound), layout.masses.chassis_kg, base_from_chassis,
                         material.friction, material.restitution, element_, &inertia);
  parts_.push_back({body, base_from_chassis});
  const WheelSpec* wheel_specs[2] = {&m.left_wheel, &m.right_wheel};
  for (int side = 0; side < 2; ++side) {
    const WheelSpec& w = *wheel_specs[side];
    btTransform base_from_wheel;
    base_from_wheel.setIdentity();
    base_from_wheel.setOrigin(
        btVector3(w.position_m.x(), layout.wheel_y[side], layout.radius[side]));
    const int wheel_element = world_.elements->Add(
        placement_.id + (side == 0 ? "/left_wheel" : "/right_wheel"), m.material, true, group_);
    btRigidBody* wheel_body =
        physics.AddDynamic(std::make_unique<btSphereShape>(layout.radius[side]),
                           layout.masses.wheel_kg[side], base_from_wheel, kWheelTreadFriction, 0.0,
                           wheel_element, nullptr, PhysicsWorld::Touches::kFloorOnly);
    parts_.push_back({wheel_body, base_from_wheel});
    const btVector3 pivot_in_chassis = base_from_chassis.inverse() * base_from_wheel.getOrigin();
    auto joint = std::make_unique<btHingeConstraint>(*body, *wheel_body, pivot_in_chassis,
                                                     btVector3(0, 0, 0), btVector3(0, 1, 0),
                                                     btVector3(0, 1, 0));
    hinge_[side] = joint.get();
    physics.AddConstraint(std::move(joint), true);
  }
  for (const CasterSpec& c : m.casters) {
    btTransform base_from_caster;
    base_from_caster.setIdentity();
    base_from_caster.setOrigin(btVector3(c.position_m.x(), c.position_m.y(), c.radius_m));
    const int caster_element =
        world_.elements->Add(placement_.id + "/" + c.link, m.material, true, group_);
    btRigidBody* caster =
        physics.AddDynamic(std::make_unique<btSphereShape>(c.radius_m), layout.masses.caster_kg,
                           base_from_caster, 0.0, 0.0, caster_element);
    parts_.push_back({caster, base_from_caster});
    auto joint = std::make_unique<btPoint2PointConstraint>(
        *body, *caster, base_from_chassis.inverse() * base_from_caster.getOrigin(),
        btVector3(0, 0, 0));
    physics.AddConstraint(std::move(joint), true);
  }
}

// Places every part at `pose`, at rest: on a relief, its base on the plane
// tangent to the floor below the base's origin (the wheels then rest within
// the relief's curvature of the floor, hundredths of a millimetre).
void RobotBody::Place(const core::Pose2& pose) {
  btTransform world_from_base = PlanarTransform(pose, 0.0);
  if (const FloorRelief& relief = world_.description->floor.relief; !relief.flat()) {
    const Eigen::Vector2d at(pose.x_m, pose.y_m);
    const Eigen::Vector3d n = relief.NormalAt(at);
    const btQuaternion tilt = shortestArcQuat(btVector3(0, 0, 1), btVector3(n.x(), n.y(), n.z()));
    world_from_base.setRotation(tilt * world_from_base.getRotation());
    world_from_base.setOrigin(btVector3(pose.x_m, pose.y_m, relief.HeightAt(at)));
  }
  for (Part& part : parts_) {
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
    drive_->Reset();
  }
}

btTransform RobotBody::WorldFromBase() const {
  btTransform com_from_base;
  com_from_base.setIdentity();
  com_from_base.setOrigin(btVector3(0, 0, -com_z_m_));
  return chassis()->getWorldTransform() * com_from_base;
}

// Solves a WheelModel::kRaycast robot's wheel contacts for the coming step
// and leaves their impulses in the chassis' velocities.
void RobotBody::SolveRaycastContacts(double dt) {
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
  drive_command_radps_[0] = command_radps_[0];
  drive_command_radps_[1] = command_radps_[1];
  drive_->Solve(dt, drive_command_radps_, &c);
  body->setLinearVelocity(ToBt(c.linear_mps));
  body->setAngularVelocity(ToBt(c.angular_radps));
}

// Accumulates each wheel's rotation from its hinge angle (wrapped by Bullet).
void RobotBody::UpdateWheelAngles() {
  for (int side = 0; side < 2; ++side) {
    const double h = hinge_[side]->getHingeAngle();
    wheel_rad_[side] += kHingeSign * core::NormalizeAngle(h - last_hinge_rad_[side]);
    last_hinge_rad_[side] = h;
  }
}

RobotBody::RobotBody(const RobotDescription& model, const SystematicErrors& systematic,
                     const RobotPlacement& placement, int group, const RobotBodyContext& world)
    : world_(world), model_(model), systematic_(systematic), placement_(placement), group_(group) {
  ValidateRobot(model, systematic, placement, *world.elements);
  const RobotDescription& m = model_;
  const Material& material = world.description->MaterialNamed(m.material);
  const PartLayout layout = LayOutParts();
  com_z_m_ = layout.com_z_m;
  element_ = world.elements->Add(placement_.id, m.material, true, group);
  const int first_attachment = world.elements->size();
  for (const MarkerSpec& a : m.markers) {
    world.elements->Add(placement_.id + "/" + a.id, a.material, true, group);
  }
  std::unique_ptr<btCompoundShape> compound = BuildChassisShape(first_attachment);
  btTransform base_from_chassis;
  base_from_chassis.setIdentity();
  base_from_chassis.setOrigin(btVector3(0, 0, com_z_m_));
  if (placement_.wheel_model == WheelModel::kRaycast) {
    AddRaycastParts(std::move(compound), base_from_chassis, layout, material);
    Place(placement_.pose);
    return;
  }
  AddArticulatedParts(std::move(compound), base_from_chassis, layout, material);
  Place(placement_.pose);
  // The parts entered the broadphase at their base-frame transforms, around the
  // origin; move their bounding boxes to the robot's pose now. Left to the next
  // step, every robot added meanwhile would overlap every earlier one there:
  // N^2/2 pairs created and dropped again (for the hall benchmark's 1000 robots,
  // 12.5 million pairs, 400 MB and seconds of start-up).
  for (Part& part : parts_) world.physics->dynamics().updateSingleAabb(part.rigid);
  for (int side = 0; side < 2; ++side) last_hinge_rad_[side] = hinge_[side]->getHingeAngle();
}

RobotBody::~RobotBody() = default;
RobotBody::RobotBody(RobotBody&&) noexcept = default;
RobotBody& RobotBody::operator=(RobotBody&&) noexcept = default;

btRigidBody* RobotBody::chassis() const { return parts_[0].rigid; }
btRigidBody* RobotBody::wheel(int side) const { return parts_[1 + side].rigid; }

RobotState RobotBody::State() const {
  const btRigidBody* body = chassis();
  const btTransform world_from_base = WorldFromBase();
  RobotState s;
  s.pose = {world_from_base.getOrigin().x(), world_from_base.getOrigin().y(),
            YawOf(world_from_base)};
  const btVector3 up = world_from_base.getBasis().getColumn(2);
  s.tilt_rad = std::acos(std::clamp(static_cast<double>(up.z()), -1.0, 1.0));
  const btVector3 v =
      body->getVelocityInLocalPoint(world_from_base.getOrigin() - body->getCenterOfMassPosition());
  s.velocity_mps = {v.x(), v.y()};
  s.yaw_rate_radps = body->getAngularVelocity().z();
  if (raycast()) {
    s.left_wheel_rad = drive_->angle_rad(0);
    s.right_wheel_rad = drive_->angle_rad(1);
    s.left_wheel_radps = drive_->rate_radps(0);
    s.right_wheel_radps = drive_->rate_radps(1);
    return s;
  }
  const btVector3 axis = body->getWorldTransform().getBasis().getColumn(1);
  const double rates[2] = {(wheel(0)->getAngularVelocity() - body->getAngularVelocity()).dot(axis),
                           (wheel(1)->getAngularVelocity() - body->getAngularVelocity()).dot(axis)};
  s.left_wheel_rad = wheel_rad_[0];
  s.right_wheel_rad = wheel_rad_[1];
  s.left_wheel_radps = rates[0];
  s.right_wheel_radps = rates[1];
  return s;
}

void RobotBody::SetWheelSpeeds(double left_radps, double right_radps) {
  const double limit = model_.max_wheel_speed_radps;
  target_radps_[0] = std::clamp(left_radps, -limit, limit);
  target_radps_[1] = std::clamp(right_radps, -limit, limit);
}

std::vector<Eigen::Vector2d> RobotBody::ContactPoints(
    const btCollisionDispatcher& dispatcher) const {
  return TouchPoints(dispatcher, chassis(), WorldFromBase().inverse());
}

std::array<double, 2> RobotBody::DriveWheelLoads(const btCollisionDispatcher& dispatcher) const {
  std::array<double, 2> load{0.0, 0.0};
  if (last_step_s_ <= 0.0) return load;
  for (int side = 0; side < 2; ++side) {
    if (raycast()) {
      load[side] = drive_->normal_impulse_ns(side) / last_step_s_;
      continue;
    }
    const btRigidBody* w = wheel(side);
    for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
      const btPersistentManifold* manifold =
          const_cast<btCollisionDispatcher&>(dispatcher).getManifoldByIndexInternal(m);
      if (manifold->getBody0() != w && manifold->getBody1() != w) continue;
      const btCollisionObject* other =
          manifold->getBody0() == w ? manifold->getBody1() : manifold->getBody0();
      if (other->getUserIndex() != 0) continue;  // the floor is element 0
      for (int c = 0; c < manifold->getNumContacts(); ++c) {
        load[side] += manifold->getContactPoint(c).getAppliedImpulse() / last_step_s_;
      }
    }
  }
  return load;
}

void RobotBody::ApplyImpulse(const Eigen::Vector2d& impulse_ns) {
  const btVector3 impulse(impulse_ns.x(), impulse_ns.y(), 0.0);
  if (push_height_m_ == 0.0) {
    chassis()->applyCentralImpulse(impulse);
  } else {
    const btVector3 up = chassis()->getWorldTransform().getBasis().getColumn(2);
    chassis()->applyImpulse(impulse, push_height_m_ * up);
  }
}

void RobotBody::ApplyImpulseAt(const Eigen::Vector2d& impulse_ns, const Eigen::Vector2d& point_m) {
  btRigidBody* body = chassis();
  body->activate(true);
  const btVector3 com = body->getCenterOfMassPosition();
  const btVector3 up = body->getWorldTransform().getBasis().getColumn(2);
  const btVector3 arm =
      btVector3(point_m.x() - com.x(), point_m.y() - com.y(), 0.0) + push_height_m_ * up;
  body->applyImpulse(btVector3(impulse_ns.x(), impulse_ns.y(), 0.0), arm);
}

void RobotBody::SetMotorsEngaged(bool engaged) {
  if (engaged && !motors_engaged_) {
    // The motor controller picks the wheels up at the rate they roll and
    // ramps them to the command at the acceleration limit (no locked wheels).
    const RobotState state = State();
    command_radps_[0] = state.left_wheel_radps;
    command_radps_[1] = state.right_wheel_radps;
  }
  motors_engaged_ = engaged;
  if (raycast()) drive_->SetEngaged(engaged);
  chassis()->activate(true);
}

void RobotBody::Teleport(const core::Pose2& pose) {
  Place(pose);
  for (int side = 0; side < 2; ++side) {
    command_radps_[side] = 0.0;
    target_radps_[side] = 0.0;
    if (!raycast()) last_hinge_rad_[side] = hinge_[side]->getHingeAngle();
  }
}

void RobotBody::Halt() {
  for (Part& part : parts_) {
    part.rigid->setLinearVelocity(btVector3(0, 0, 0));
    part.rigid->setAngularVelocity(btVector3(0, 0, 0));
    part.rigid->clearForces();
  }
  if (raycast()) drive_->Reset();
  for (int side = 0; side < 2; ++side) {
    command_radps_[side] = 0.0;
    target_radps_[side] = 0.0;
  }
  chassis()->activate(true);
}

void RobotBody::BeforeStep(double dt) {
  last_step_s_ = dt;
  const RobotDescription& m = model_;
  for (int side = 0; side < 2; ++side) {
    // Acceleration ramp towards the commanded speed; the motor delivers at
    // most the torque limit over the step.
    const double step = m.max_wheel_accel_radps2 * dt;
    command_radps_[side] += std::clamp(target_radps_[side] - command_radps_[side], -step, step);
    if (!raycast()) {
      // Disengaged, the hinge turns freely: the wheel rolls with the floor.
      hinge_[side]->enableAngularMotor(motors_engaged_, kHingeSign * command_radps_[side],
                                       m.max_wheel_torque_nm * dt);
    }
  }
  if (raycast()) SolveRaycastContacts(dt);
}

void RobotBody::AfterStep(double dt) {
  if (raycast()) {
    drive_->Integrate(dt);
  } else {
    UpdateWheelAngles();
  }
}

void RobotBody::AppendSection(double z, double max_cylinder_tilt_rad, const PrismRegistry& prisms,
                              core::PlanarSection* out, std::vector<UncutElement>* uncut) const {
  // The chassis compound (origin at the centre of mass): its slabs, then the
  // markers (BuildChassisShape).
  const btRigidBody* body = chassis();
  const btTransform& t = body->getWorldTransform();
  const auto* compound = static_cast<const btCompoundShape*>(body->getCollisionShape());
  for (int c = 0; c < compound->getNumChildShapes(); ++c) {
    const btCollisionShape* child = compound->getChildShape(c);
    if (c < chassis_prisms_) {
      const RayPrism& prism = prisms.at(child);
      CutPrism(t * compound->getChildTransform(c), prism.polygon, prism.z0, prism.z1, z, element_,
               out, uncut);
      continue;
    }
    const MarkerSpec& a = model_.markers[c - chassis_prisms_];
    CutCylinder(t * compound->getChildTransform(c), a.radius_m, 0.5 * a.height_m, z,
                max_cylinder_tilt_rad, child->getUserIndex(), out, uncut);
  }
  for (std::size_t p = 1; p < parts_.size(); ++p) {
    const btRigidBody* rb = parts_[p].rigid;
    const auto* sphere = static_cast<const btSphereShape*>(rb->getCollisionShape());
    CutSphere(rb->getWorldTransform().getOrigin(), sphere->getRadius(), z, rb->getUserIndex(), out);
  }
}

}  // namespace pavilion::sim
