#include "sim/world/world.h"

#include <btBulletDynamicsCommon.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "sim/raycast/baked_ray_world.h"
#include "sim/raycast/physics_ray.h"
#include "sim/robot/robot_body.h"
#include "sim/world/bullet_conversions.h"
#include "sim/world/contact_tracker.h"
#include "sim/world/crowd_coupling.h"
#include "sim/world/element_table.h"
#include "sim/world/physics_world.h"
#include "sim/world/prism_registry.h"
#include "sim/world/shape_sections.h"
#include "sim/world/static_geometry.h"
#include "sim/world/static_section.h"

namespace pavilion::sim {

void WorldOptions::Validate() const {
  if (!(physics_rate_hz >= 10.0 && physics_rate_hz <= 10000.0)) {
    throw std::invalid_argument("physics_rate_hz must be in [10, 10000]");
  }
  if (solver_iterations < 1 || solver_iterations > 100) {
    throw std::invalid_argument("solver_iterations must be in [1, 100]");
  }
  if (!(gravity_mps2 >= 0.0 && gravity_mps2 <= 100.0)) {
    throw std::invalid_argument("gravity_mps2 must be in [0, 100]");
  }
}

const char* WheelModelName(WheelModel model) {
  switch (model) {
    case WheelModel::kArticulated:
      return "articulated";
    case WheelModel::kRaycast:
      return "raycast";
  }
  return "?";
}

double BodyShape::HalfHeight() const {
  switch (type) {
    case BodyShapeType::kBox:
      return 0.5 * box_size_m.z();
    case BodyShapeType::kCylinder:
      return 0.5 * height_m;
    case BodyShapeType::kSphere:
      return radius_m;
  }
  return 0.0;
}

struct World::Impl {
  struct Body {
    BodySpec spec;
    int element = -1;
    btRigidBody* rigid = nullptr;
    Eigen::Vector2d velocity_mps{0, 0};
    double yaw_rate_radps = 0.0;
    // Planar Coulomb friction of an undriven upright body on the floor:
    // linear and yaw decelerations (m/s², rad/s²); zero for other bodies.
    double slide_decel_mps2 = 0.0;
    double spin_decel_radps2 = 0.0;
    // A driven upright body's decelerations while it yields (SetYielding).
    double yield_slide_decel_mps2 = 0.0;
    double yield_spin_decel_radps2 = 0.0;
    bool yielding = false;
  };

  Impl(WorldDescription world_description, const WorldOptions& world_options)
      : description(std::move(world_description)),
        options(world_options),
        physics(options, &elements.all()) {}

  WorldDescription description;
  WorldOptions options;
  std::int64_t tick = 0;
  ElementTable elements{&description};
  PhysicsWorld physics;
  // Laser-visible static geometry of the fast ray path
  // (WorldOptions::baked_static_rays); null without it.
  std::unique_ptr<BakedRayWorld> baked_rays;

  PrismRegistry prisms;              // robot chassis hulls
  std::int64_t static_revision = 0;  // counts door moves
  mutable std::atomic<std::int64_t> rays_cast{0};
  mutable std::mutex ray_mutex;  // serializes CastRay's Bullet path (world.h)

  std::vector<Body> bodies;
  std::vector<RobotBody> robots;
  std::unique_ptr<CrowdCoupling> crowd;
  std::int64_t crowd_walls_revision = 0;        // static_revision the crowd's walls are from
  std::vector<crowd::CrowdRobot> crowd_robots;  // scratch
  crowd::CrowdStepResult crowd_result;          // scratch
  // Where people touched each robot in the last step (world frame): the
  // bumpers feel them as they feel Bullet contacts.
  std::vector<std::vector<Eigen::Vector2d>> person_touches_m;
  std::vector<btRigidBody*> doors;  // parallel to description.doors
  ContactTracker contacts;
  std::vector<ContactChange> pending_changes;

  RobotBodyContext robot_context() {
    return {&description, &options, &elements, &physics, &prisms};
  }

  // Friction of an undriven upright body on the floor, and a driven body's
  // planar velocity, for the coming step of `dt`.
  static void ApplyPlanarMotion(Body* body, double dt) {
    Body& b = *body;
    const double slide_decel_mps2 = b.yielding ? b.yield_slide_decel_mps2 : b.slide_decel_mps2;
    const double spin_decel_radps2 = b.yielding ? b.yield_spin_decel_radps2 : b.spin_decel_radps2;
    if (slide_decel_mps2 > 0.0 && b.rigid->getInvMass() > 0.0 &&
        b.rigid->getWorldTransform().getOrigin().z() <
            b.spec.shape.HalfHeight() + kContactDistanceM) {
      // Coulomb friction with the floor; it stops a body but never reverses it.
      btVector3 v = b.rigid->getLinearVelocity();
      const double speed = std::hypot(v.x(), v.y());
      const double dv = std::min(speed, slide_decel_mps2 * dt);
      if (speed > 0.0)
        b.rigid->setLinearVelocity(
            btVector3(v.x() * (1 - dv / speed), v.y() * (1 - dv / speed), v.z()));
      btVector3 w = b.rigid->getAngularVelocity();
      const double dw = std::min(std::abs(w.z()), spin_decel_radps2 * dt);
      b.rigid->setAngularVelocity(btVector3(w.x(), w.y(), w.z() - std::copysign(dw, w.z())));
    }
    if (!b.spec.driven || b.yielding) return;
    const btVector3 v = b.rigid->getLinearVelocity();
    // The driving term of the social force model, integrated over the step
    // (exactly, for a constant set velocity): the velocity relaxes towards the
    // set one, and contacts then take away what the body cannot push. Without
    // a relaxation time the set velocity is simply held.
    const double keep =
        b.spec.drive_relaxation_s > 0.0 ? std::exp(-dt / b.spec.drive_relaxation_s) : 0.0;
    b.rigid->setLinearVelocity(btVector3(b.velocity_mps.x() + keep * (v.x() - b.velocity_mps.x()),
                                         b.velocity_mps.y() + keep * (v.y() - b.velocity_mps.y()),
                                         v.z()));
    const btVector3 w = b.rigid->getAngularVelocity();
    b.rigid->setAngularVelocity(btVector3(w.x(), w.y(), b.yaw_rate_radps));
  }

  // Cuts every body at height z into `out`; elements the plane does not cut
  // into circles or convex polygons go to `uncut`, or, when it is null, are
  // added as their upright extrusion (the top-down view and spawn checks).
  void AppendBodySection(double z, double max_cylinder_tilt_rad, core::PlanarSection* out,
                         std::vector<UncutElement>* uncut) const {
    for (const Body& body : bodies) {
      const btTransform& t = body.rigid->getWorldTransform();
      const BodyShape& shape = body.spec.shape;
      switch (shape.type) {
        case BodyShapeType::kSphere:
          CutSphere(t.getOrigin(), shape.radius_m, z, body.element, out);
          break;
        case BodyShapeType::kCylinder:
          CutCylinder(t, shape.radius_m, 0.5 * shape.height_m, z, max_cylinder_tilt_rad,
                      body.element, out, uncut);
          break;
        case BodyShapeType::kBox: {
          const Eigen::Vector3d half = 0.5 * shape.box_size_m;
          const std::vector<Eigen::Vector2d> rectangle = {{-half.x(), -half.y()},
                                                          {half.x(), -half.y()},
                                                          {half.x(), half.y()},
                                                          {-half.x(), half.y()}};
          CutPrism(t, rectangle, -half.z(), half.z(), z, body.element, out, uncut);
          break;
        }
      }
    }
  }

  void AppendRobotSection(double z, double max_cylinder_tilt_rad, core::PlanarSection* out,
                          std::vector<UncutElement>* uncut) const {
    for (const RobotBody& robot : robots)
      robot.AppendSection(z, max_cylinder_tilt_rad, prisms, out, uncut);
  }
};

World::World(WorldDescription description, const WorldOptions& options) {
  options.Validate();
  impl_ = std::make_unique<Impl>(std::move(description), options);
  impl_->doors = AddStaticGeometry(impl_->description, &impl_->elements, &impl_->physics);
  if (options.baked_static_rays) {
    impl_->baked_rays = std::make_unique<BakedRayWorld>(impl_->description, impl_->elements);
  }
}

World::~World() = default;

int World::AddBody(const BodySpec& spec) {
  if (!(spec.mass_kg > 0.0))
    throw std::invalid_argument("body '" + spec.id + "': mass_kg must be > 0");
  if (!(spec.drive_relaxation_s >= 0.0 && std::isfinite(spec.drive_relaxation_s))) {
    throw std::invalid_argument("body '" + spec.id + "': drive_relaxation_s must be >= 0");
  }
  Impl& im = *impl_;
  const Material& material = im.description.MaterialNamed(spec.material);
  std::unique_ptr<btCollisionShape> shape;
  switch (spec.shape.type) {
    case BodyShapeType::kBox:
      shape = MakeBox(0.5 * spec.shape.box_size_m);
      break;
    case BodyShapeType::kCylinder:
      shape = std::make_unique<btCylinderShapeZ>(
          btVector3(spec.shape.radius_m, spec.shape.radius_m, 0.5 * spec.shape.height_m));
      break;
    case BodyShapeType::kSphere:
      shape = std::make_unique<btSphereShape>(spec.shape.radius_m);
      break;
  }
  btVector3 inertia(0, 0, 0);
  shape->calculateLocalInertia(spec.mass_kg, inertia);
  // Upright bodies get infinite inertia about x and y (Bullet inverts a zero
  // inertia to zero), so they never tip over.
  if (spec.upright) inertia = btVector3(0, 0, inertia.z());
  btTransform t;
  t.setIdentity();
  t.setOrigin(btVector3(spec.pose.x_m, spec.pose.y_m, spec.shape.HalfHeight()));
  t.setRotation(btQuaternion(btVector3(0, 0, 1), spec.pose.theta_rad));
  auto motion = std::make_unique<btDefaultMotionState>(t);
  btRigidBody::btRigidBodyConstructionInfo info(spec.mass_kg, motion.get(), shape.get(), inertia);
  // Bullet's contact friction misbehaves for bodies that cannot tip (a pushed
  // upright body creeps on, or even turns back: world_test). Upright bodies are
  // therefore frictionless in Bullet and slide with the planar Coulomb friction
  // of Step(); driven bodies walk, and their feet do not rub on the floor.
  info.m_friction = spec.upright || spec.driven ? 0.0 : material.friction;
  info.m_restitution = material.restitution;
  auto rigid = std::make_unique<btRigidBody>(info);
  if (spec.driven) rigid->setActivationState(DISABLE_DEACTIVATION);
  const int element = im.elements.Add(spec.id, spec.material, true);
  rigid->setUserIndex(element);
  Impl::Body record{spec, element, rigid.get(), {0, 0}, 0.0, 0.0, 0.0};
  if (spec.upright) {
    // Bullet combines friction coefficients by their product; so do we.
    const double mu =
        material.friction * im.description.MaterialNamed(im.description.floor.material).friction;
    record.slide_decel_mps2 = mu * im.options.gravity_mps2;
    // Uniform pressure over a disc of the footprint radius: torque (2/3) μ m g r.
    const double r = spec.shape.type == BodyShapeType::kBox
                         ? 0.5 * spec.shape.box_size_m.head<2>().norm()
                         : spec.shape.radius_m;
    record.spin_decel_radps2 = inertia.z() > 0 ? (2.0 / 3.0) * mu * spec.mass_kg *
                                                     im.options.gravity_mps2 * r / inertia.z()
                                               : 0.0;
  }
  if (spec.driven) {  // driven bodies slide so only while they yield
    record.yield_slide_decel_mps2 = std::exchange(record.slide_decel_mps2, 0.0);
    record.yield_spin_decel_radps2 = std::exchange(record.spin_decel_radps2, 0.0);
  }
  im.physics.AddRigidBody(std::move(shape), std::move(motion), std::move(rigid));
  im.bodies.push_back(record);
  return static_cast<int>(im.bodies.size()) - 1;
}

int World::AddRobot(const RobotDescription& model, const SystematicErrors& systematic,
                    const RobotPlacement& placement) {
  Impl& im = *impl_;
  const int group = static_cast<int>(im.robots.size());
  im.robots.emplace_back(model, systematic, placement, group, im.robot_context());
  return static_cast<int>(im.robots.size()) - 1;
}

int World::robot_count() const { return static_cast<int>(impl_->robots.size()); }
const RobotDescription& World::robot_model(int robot) const {
  return impl_->robots.at(robot).model();
}
const RobotPlacement& World::robot_placement(int robot) const {
  return impl_->robots.at(robot).placement();
}
int World::robot_group(int robot) const { return impl_->robots.at(robot).group(); }
int World::robot_element(int robot) const { return impl_->robots.at(robot).element(); }

RobotState World::robot_state(int robot) const { return impl_->robots.at(robot).State(); }

void World::SetWheelSpeeds(int robot, double left_radps, double right_radps) {
  impl_->robots.at(robot).SetWheelSpeeds(left_radps, right_radps);
}

std::vector<Eigen::Vector2d> World::RobotContactPoints(int robot) const {
  const RobotBody& body = impl_->robots.at(robot);
  std::vector<Eigen::Vector2d> points = body.ContactPoints(impl_->physics.dispatcher());
  if (static_cast<std::size_t>(robot) < impl_->person_touches_m.size()) {
    const core::Pose2 base_from_world = body.State().pose.Inverse();
    for (const Eigen::Vector2d& p : impl_->person_touches_m[robot]) {
      points.push_back(base_from_world * p);
    }
  }
  return points;
}

std::array<double, 2> World::DriveWheelLoads(int robot) const {
  return impl_->robots.at(robot).DriveWheelLoads(impl_->physics.dispatcher());
}

void World::SetMotorsEngaged(int robot, bool engaged) {
  impl_->robots.at(robot).SetMotorsEngaged(engaged);
}

bool World::motors_engaged(int robot) const { return impl_->robots.at(robot).motors_engaged(); }

void World::ApplyRobotImpulse(int robot, const Eigen::Vector2d& impulse_ns) {
  impl_->robots.at(robot).ApplyImpulse(impulse_ns);
}

void World::HaltRobot(int robot) { impl_->robots.at(robot).Halt(); }

void World::TeleportRobot(int robot, const core::Pose2& pose) {
  impl_->robots.at(robot).Teleport(pose);
}

int World::body_count() const { return static_cast<int>(impl_->bodies.size()); }
const BodySpec& World::body_spec(int body) const { return impl_->bodies.at(body).spec; }
int World::body_element(int body) const { return impl_->bodies.at(body).element; }

BodyState World::body_state(int body) const {
  const btRigidBody* rb = impl_->bodies.at(body).rigid;
  const btTransform& t = rb->getWorldTransform();
  BodyState s;
  s.pose = {t.getOrigin().x(), t.getOrigin().y(), YawOf(t)};
  s.z_m = t.getOrigin().z();
  const btVector3 up = t.getBasis().getColumn(2);
  s.tilt_rad = std::acos(std::clamp(static_cast<double>(up.z()), -1.0, 1.0));
  s.velocity_mps = {rb->getLinearVelocity().x(), rb->getLinearVelocity().y()};
  s.yaw_rate_radps = rb->getAngularVelocity().z();
  return s;
}

void World::SetPlanarVelocity(int body, const Eigen::Vector2d& velocity_mps,
                              double yaw_rate_radps) {
  Impl::Body& b = impl_->bodies.at(body);
  b.velocity_mps = velocity_mps;
  b.yaw_rate_radps = yaw_rate_radps;
}

void World::SetYielding(int body, bool yielding) {
  Impl::Body& b = impl_->bodies.at(body);
  b.yielding = yielding && b.spec.driven && b.spec.upright;
}

void World::ApplyImpulse(int body, const Eigen::Vector2d& impulse_ns) {
  btRigidBody* rb = impl_->bodies.at(body).rigid;
  rb->activate(true);
  rb->applyCentralImpulse(btVector3(impulse_ns.x(), impulse_ns.y(), 0.0));
}

void World::Teleport(int body, const core::Pose2& pose) {
  Impl::Body& b = impl_->bodies.at(body);
  btTransform t;
  t.setIdentity();
  t.setOrigin(btVector3(pose.x_m, pose.y_m, b.spec.shape.HalfHeight()));
  t.setRotation(btQuaternion(btVector3(0, 0, 1), pose.theta_rad));
  b.rigid->setWorldTransform(t);
  b.rigid->getMotionState()->setWorldTransform(t);
  b.rigid->setLinearVelocity(btVector3(0, 0, 0));
  b.rigid->setAngularVelocity(btVector3(0, 0, 0));
  b.rigid->activate(true);
}

void World::SetDoorOpen(const std::string& door_id, bool open) {
  Impl& im = *impl_;
  for (std::size_t i = 0; i < im.description.doors.size(); ++i) {
    Door& door = im.description.doors[i];
    if (door.id != door_id) continue;
    door.open = open;
    ++im.static_revision;
    im.doors[i]->setWorldTransform(BoxTransform(door.AsBox()));
    // Static bodies are not re-inserted by Bullet: refresh the broadphase bounds.
    im.physics.dynamics().updateSingleAabb(im.doors[i]);
    if (im.baked_rays) im.baked_rays->MoveDoor(static_cast<int>(i), door.AsBox());
    return;
  }
  throw std::out_of_range("no door '" + door_id + "'");
}

void World::Step() {
  Impl& im = *impl_;
  const double dt = step_s();
  for (Impl::Body& b : im.bodies) Impl::ApplyPlanarMotion(&b, dt);
  for (RobotBody& r : im.robots) r.BeforeStep(dt);
  if (im.crowd) StepCrowd(dt);
  im.physics.dynamics().stepSimulation(dt, 0, dt);
  for (RobotBody& r : im.robots) r.AfterStep(dt);
  ++im.tick;
  im.contacts.Update(im.physics.dispatcher(), &im.pending_changes);
}

void World::StepCrowd(double dt) {
  Impl& im = *impl_;
  if (im.crowd_walls_revision != im.static_revision) {  // a door moved
    std::vector<crowd::WallSegment> walls;
    std::vector<crowd::WallCircle> pillars;
    CrowdCoupling::CollectWalls(StaticSectionAt(CrowdCoupling::kLowCutM),
                                StaticSectionAt(CrowdCoupling::kBodyCutM), &walls, &pillars);
    im.crowd->crowd().SetObstacles(std::move(walls), std::move(pillars));
    im.crowd_walls_revision = im.static_revision;
  }
  im.crowd_robots.resize(im.robots.size());
  for (std::size_t r = 0; r < im.robots.size(); ++r) {
    const RobotState state = im.robots[r].State();
    crowd::CrowdRobot& robot = im.crowd_robots[r];
    robot.pose = state.pose;
    robot.velocity_mps = state.velocity_mps;
    robot.yaw_rate_radps = state.yaw_rate_radps;
    if (robot.footprint_in_robot_m.empty())
      robot.footprint_in_robot_m = im.robots[r].model().footprint_m;
  }
  im.crowd_result.contacts.clear();
  im.crowd_result.pushes.clear();
  im.crowd->crowd().Step(dt, im.crowd_robots, &im.crowd_result);
  // The people's forces on the robots over the step, as impulses at the
  // contact points: a person's body and deliberate push together bounded by
  // what one person can exert.
  const double limit_n = im.crowd->crowd().options().social.max_push_force_n;
  struct PersonForce {
    Eigen::Vector2d force_n{0, 0};
    Eigen::Vector2d point_m{0, 0};
    bool pinned = false;  // held by a wall or others: not bounded
  };
  std::map<std::pair<int, int>, PersonForce> by_person;
  for (const crowd::RobotContactForce& f : im.crowd_result.contacts) {
    PersonForce& p = by_person[{f.robot, f.agent}];
    p.force_n += f.force_n;
    p.point_m = f.point_m;
    p.pinned = p.pinned || f.pinned;
  }
  for (const crowd::RobotPush& push : im.crowd_result.pushes) {
    PersonForce& p = by_person[{push.robot, push.person}];
    p.force_n += push.force_n;
    p.point_m = push.point_m;
  }
  std::map<std::pair<int, int>, ContactChange> touching;
  im.person_touches_m.resize(im.robots.size());
  for (auto& touches : im.person_touches_m) touches.clear();
  for (auto& [key, entry] : by_person) {
    Eigen::Vector2d& force = entry.force_n;
    const Eigen::Vector2d& point = entry.point_m;
    if (!entry.pinned && force.norm() > limit_n) force *= limit_n / force.norm();
    const auto [robot, person] = key;
    im.robots[robot].ApplyImpulseAt(force * dt, point);
    im.person_touches_m[robot].push_back(point);
    const int a = im.robots[robot].element(), b = im.crowd->person_element(person);
    ContactChange& c = touching[{std::min(a, b), std::max(a, b)}];
    c.a = std::min(a, b);
    c.b = std::max(a, b);
    c.point_m = Eigen::Vector3d(point.x(), point.y(), 0.5);
    c.impulse_ns = std::max(c.impulse_ns, force.norm() * dt);
  }
  im.crowd->UpdateContacts(touching, &im.pending_changes);
}

void World::AddCrowd(const CrowdSpec& spec, std::uint64_t seed) {
  Impl& im = *impl_;
  if (im.crowd) throw std::invalid_argument("crowd: a world holds at most one crowd");
  im.description.MaterialNamed(spec.material);  // throws for an unknown material
  crowd::CrowdSite site;
  site.floor_min_m = im.description.floor.min_m;
  site.floor_max_m = im.description.floor.max_m;
  site.entrance = spec.entrance;
  site.exit = spec.exit;
  site.roam_area = spec.roam_area;
  site.attractions = spec.attractions;
  for (const RobotBody& robot : im.robots) {
    const core::Pose2 pose = robot.State().pose;
    std::vector<Eigen::Vector2d> hull;
    for (const Eigen::Vector2d& v : robot.model().footprint_m) hull.push_back(pose * v);
    site.keep_clear.push_back(std::move(hull));
  }
  CrowdCoupling::CollectWalls(StaticSectionAt(CrowdCoupling::kLowCutM),
                              StaticSectionAt(CrowdCoupling::kBodyCutM), &site.walls,
                              &site.pillars);
  auto model = std::make_unique<crowd::Crowd>(std::move(site), spec.options, seed);
  std::vector<int> elements;
  for (int i = 0; i < model->size(); ++i) {
    char number[16];
    std::snprintf(number, sizeof number, "%03d", i + 1);
    elements.push_back(im.elements.Add(spec.id_prefix + number, spec.material, true));
  }
  im.crowd = std::make_unique<CrowdCoupling>(std::move(model), std::move(elements));
  im.crowd_walls_revision = im.static_revision;
}

const crowd::Crowd* World::crowd() const { return impl_->crowd ? &impl_->crowd->crowd() : nullptr; }
crowd::Crowd* World::mutable_crowd() { return impl_->crowd ? &impl_->crowd->crowd() : nullptr; }
int World::person_element(int person) const { return impl_->crowd->person_element(person); }

TickSnapshot World::Snapshot() const {
  TickSnapshot snapshot;
  snapshot.tick = impl_->tick;
  snapshot.time_s = time_s();
  snapshot.bodies.reserve(impl_->bodies.size());
  for (int b = 0; b < body_count(); ++b) snapshot.bodies.push_back(body_state(b));
  snapshot.robots.reserve(impl_->robots.size());
  for (int r = 0; r < robot_count(); ++r) snapshot.robots.push_back(robot_state(r));
  if (impl_->crowd) snapshot.people = impl_->crowd->crowd().people();
  return snapshot;
}

std::int64_t World::tick() const { return impl_->tick; }
double World::step_s() const { return 1.0 / impl_->options.physics_rate_hz; }
double World::time_s() const { return static_cast<double>(impl_->tick) * step_s(); }

core::PlanarSection World::SectionAt(double height_m) const {
  core::PlanarSection section = StaticSectionAt(height_m);
  // Tilted bodies as well as the plane allows (see AppendBodySection).
  impl_->AppendBodySection(height_m, std::numbers::pi / 2, &section, nullptr);
  impl_->AppendRobotSection(height_m, std::numbers::pi / 2, &section, nullptr);
  if (impl_->crowd) impl_->crowd->AppendSection(height_m, &section);
  return section;
}

core::PlanarSection World::StaticSectionAt(double height_m) const {
  core::PlanarSection section;
  section.height_m = height_m;
  section.elements = impl_->elements.all();
  AppendStaticSection(impl_->description, height_m, &section);
  return section;
}

void World::AppendDynamicSection(double height_m, double max_cylinder_tilt_rad,
                                 core::PlanarSection* out, std::vector<UncutElement>* uncut) const {
  impl_->AppendBodySection(height_m, max_cylinder_tilt_rad, out, uncut);
  impl_->AppendRobotSection(height_m, max_cylinder_tilt_rad, out, uncut);
  if (impl_->crowd) impl_->crowd->AppendSection(height_m, out);
}

std::int64_t World::static_revision() const { return impl_->static_revision; }

RayHit World::CastRay(const Eigen::Vector3d& from_m, const Eigen::Vector3d& to_m, int ignore_group,
                      bool hit_transparent) const {
  const Impl& im = *impl_;
  im.rays_cast.fetch_add(1, std::memory_order_relaxed);
  RayHit hit;
  if (im.options.baked_static_rays && !hit_transparent) {
    // Reads only: rays in parallel (the scans that fall back from the planar
    // caster, on the scenario runner's worker pool).
    hit = im.baked_rays->Cast(from_m, to_m, ignore_group, im.elements.all(), im.prisms,
                              im.physics.broadphase());
  } else {
    // btCollisionWorld::rayTest walks the broadphase with the broadphase's one stack.
    const std::lock_guard<std::mutex> lock(im.ray_mutex);
    hit = CastPhysicsRay(im.physics.dynamics(), im.elements.all(), from_m, to_m, ignore_group,
                         hit_transparent);
  }
  if (im.crowd) im.crowd->CastRay(from_m, to_m, &hit);  // people are not Bullet bodies
  return hit;
}

const std::vector<core::SectionElement>& World::elements() const { return impl_->elements.all(); }

std::int64_t World::rays_cast() const { return impl_->rays_cast.load(); }

std::vector<ContactChange> World::TakeContactChanges() {
  std::vector<ContactChange> out;
  out.swap(impl_->pending_changes);
  return out;
}

const WorldDescription& World::description() const { return impl_->description; }

}  // namespace pavilion::sim
