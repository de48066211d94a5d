#include "sim/world/world.h"

#include <BulletCollision/NarrowPhaseCollision/btRaycastCallback.h>
#include <btBulletDynamicsCommon.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <numbers>
#include <set>
#include <stdexcept>
#include <utility>

#include "sim/raycast/ray_shapes.h"
#include "sim/robot/raycast_drive.h"
#include "sim/world/triangle_mesh.h"
#include "sim/world/wall_geometry.h"

namespace pavilion::sim {
namespace {

// Contact points closer than this count as touching (m).
constexpr double kContactDistanceM = 0.005;
// Floor slab thickness below z = 0 (m); thick enough that nothing tunnels.
constexpr double kFloorThicknessM = 1.0;
// Collision margin for triangle meshes (m); small so that rays and contacts
// meet the surface the description gives.
constexpr double kMeshMarginM = 0.001;
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
// Bullet's default solver mode gives each contact point a single friction row,
// along the slip velocity at the start of the step: the perpendicular tangent
// is frictionless within the step. A sphere wheel touches the floor at one
// point, so whatever the other constraints push sideways during the iterations
// slips unopposed: at rest Pygmalion crept 0.24 mm/s sideways and turned
// 0.16 mrad/s with its encoders still, and in curves (traction plus lateral
// force) odometry's heading error per 0.5 s had 1.40 mrad σ instead of 1.22 on
// straights (office tour). Two orthogonal friction rows per contact (a friction
// pyramid) hold both tangents: creep < 0.003 mm/s, σ 0.09 / 0.04 mrad.
constexpr int kSolverFrictionModes = SOLVER_USE_2_FRICTION_DIRECTIONS;
// A shape whose z axis has a vertical component below this lies too flat for
// its side edges to meet a horizontal plane at a usable angle (cos 89.4°).
constexpr double kMinAxisZ = 0.01;

btVector3 ToBt(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

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

double YawOf(const btTransform& t) {
  btScalar yaw, pitch, roll;
  t.getBasis().getEulerZYX(yaw, pitch, roll);
  return static_cast<double>(yaw);
}

// Cuts a triangle by the plane z = h and appends the section segment, oriented
// with the solid on its left (the triangle's outward normal to its right).
void CutTriangle(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                 double h, int element, core::PlanarSection* out) {
  const Eigen::Vector3d p[3] = {p0, p1, p2};
  Eigen::Vector2d hits[3];
  int count = 0;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d& a = p[k];
    const Eigen::Vector3d& b = p[(k + 1) % 3];
    const bool a_above = a.z() >= h;
    const bool b_above = b.z() >= h;
    if (a_above == b_above) continue;
    const double t = (h - a.z()) / (b.z() - a.z());
    hits[count++] = (a + t * (b - a)).head<2>();
  }
  if (count != 2 || (hits[0] - hits[1]).squaredNorm() < 1e-18) return;
  const Eigen::Vector3d normal = (p1 - p0).cross(p2 - p0);
  const Eigen::Vector2d dir(-normal.y(), normal.x());  // normal rotated by +90°
  core::SectionSegment s;
  s.element = element;
  if ((hits[1] - hits[0]).dot(dir) >= 0) {
    s.a_m = hits[0];
    s.b_m = hits[1];
  } else {
    s.a_m = hits[1];
    s.b_m = hits[0];
  }
  out->segments.push_back(s);
}

btTransform PlanarTransform(const core::Pose2& pose, double z) {
  btTransform t;
  t.setIdentity();
  t.setOrigin(btVector3(pose.x_m, pose.y_m, z));
  t.setRotation(btQuaternion(btVector3(0, 0, 1), pose.theta_rad));
  return t;
}

double WrapAngle(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }

// A box whose collision margin fits inside it: Bullet keeps the margin inside
// a box's extents, and a margin larger than the thinnest half extent (a 4 cm
// door under the default 4 cm) distorts the shape by centimetres.
std::unique_ptr<btBoxShape> MakeBox(const Eigen::Vector3d& half_m) {
  auto box = std::make_unique<btBoxShape>(ToBt(half_m));
  const double margin = std::min(box->getMargin(), 0.25 * half_m.minCoeff());
  box->setMargin(margin);  // keeps the outer extents at half_m
  return box;
}

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

// A vertical prism among the dynamic shapes (a robot's chassis hull) in its
// shape's frame, for exact laser rays.
struct RayPrism {
  std::vector<Eigen::Vector2d> polygon;
  double z0 = 0.0;
  double z1 = 0.0;
};

void AddPolygonSegments(const Quad& q, int element, core::PlanarSection* out) {
  for (int k = 0; k < 4; ++k) out->segments.push_back({q[k], q[(k + 1) % 4], element});
}

bool SpansHeight(double base_z, double height, double z) {
  return z >= base_z && z < base_z + height;
}

// Cuts of dynamic shapes by the plane z = h (AppendDynamicSection). Shapes
// are placed by Bullet transforms; `h` is in the world frame.

void CutSphere(const btVector3& centre, double radius, double h, int element,
               core::PlanarSection* out) {
  const double dz = h - centre.z();
  if (std::abs(dz) < radius) {
    out->circles.push_back(
        {{centre.x(), centre.y()}, std::sqrt(radius * radius - dz * dz), element});
  }
}

// A bound of an element that could not be cut, for the planar caster's fallback
// test: the horizontal distance of its points from the centre is at most the radius.
void AddUncut(const btVector3& centre, double radius, int element,
              std::vector<UncutElement>* uncut) {
  uncut->push_back({element, {centre.x(), centre.y()}, radius});
}

// A vertical prism over a convex counter-clockwise polygon (shape frame), z
// in [z0, z1), placed by `t`. While the plane crosses only its side faces the
// cut is exact at any tilt: the points where the plane meets the side edges,
// still counter-clockwise (the map from the polygon to its cut is affine with a
// positive determinant while the axis points up). A plane through a cap gives
// another polygon: listed in `uncut`, or with a null `uncut` added as the
// upright extrusion at the prism's planar pose.
void CutPrism(const btTransform& t, const std::vector<Eigen::Vector2d>& polygon, double z0,
              double z1, double h, int element, core::PlanarSection* out,
              std::vector<UncutElement>* uncut) {
  const btVector3 axis = t.getBasis().getColumn(2);
  std::vector<Eigen::Vector2d> cut;
  cut.reserve(polygon.size());
  std::size_t below = 0, above = 0;
  double reach = 0.0;  // horizontal bound of the prism around its origin
  for (const Eigen::Vector2d& p : polygon) {
    const btVector3 foot = t * btVector3(p.x(), p.y(), 0.0);
    // Shape-frame height at which this side edge meets the plane.
    const double s = axis.z() > kMinAxisZ ? (h - foot.z()) / axis.z() : 0.0;
    if (s < z0) ++below;
    if (s >= z1) ++above;
    cut.emplace_back(foot.x() + s * axis.x(), foot.y() + s * axis.y());
    for (const double zz : {z0, z1}) {
      const btVector3 v = t * btVector3(p.x(), p.y(), zz) - t.getOrigin();
      reach = std::max(reach, std::hypot(v.x(), v.y()));
    }
  }
  const std::size_t n = polygon.size();
  if (axis.z() > kMinAxisZ && (below == n || above == n)) return;  // not cut
  if (axis.z() > kMinAxisZ && below == 0 && above == 0) {
    for (std::size_t i = 0; i < n; ++i)
      out->segments.push_back({cut[i], cut[(i + 1) % n], element});
    return;
  }
  if (uncut != nullptr) {
    // Lying down or cut through a cap: only if the plane reaches the prism at all.
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Eigen::Vector2d& p : polygon) {
      for (const double zz : {z0, z1}) {
        const double vz = (t * btVector3(p.x(), p.y(), zz)).z();
        lo = std::min(lo, vz);
        hi = std::max(hi, vz);
      }
    }
    if (h >= lo && h <= hi) AddUncut(t.getOrigin(), reach, element, uncut);
    return;
  }
  // Upright extrusion at the planar pose (as the section did before tilts were cut).
  const btVector3 o = t.getOrigin();
  const double dz = h - o.z();
  if (dz < z0 || dz >= z1) return;
  const core::Pose2 pose{o.x(), o.y(), YawOf(t)};
  for (std::size_t i = 0; i < n; ++i) {
    out->segments.push_back({pose * polygon[i], pose * polygon[(i + 1) % n], element});
  }
}

// A cylinder about its shape z axis, centred at its origin. Upright, its cut is
// a circle; tilted by θ it is an ellipse with semi-axes r and r/cos θ about the
// point where the axis meets the plane, taken as the circle of radius r there
// while θ <= max_tilt_rad (error r(1/cos θ − 1): 7.6 µm for r = 5 cm at 1°).
// Beyond that, or with the plane through a cap, it goes to `uncut` (or, with a
// null `uncut`, is added as that circle anyway).
void CutCylinder(const btTransform& t, double radius, double half_height, double h,
                 double max_tilt_rad, int element, core::PlanarSection* out,
                 std::vector<UncutElement>* uncut) {
  const btVector3 axis = t.getBasis().getColumn(2);
  const btVector3& c = t.getOrigin();
  const double bound = std::hypot(radius, half_height);
  if (std::abs(h - c.z()) >= bound) return;  // out of reach of the plane
  if (axis.z() > kMinAxisZ) {
    const double s = (h - c.z()) / axis.z();  // axial coordinate of the axis' crossing
    const double spread = radius * std::sqrt(std::max(0.0, 1.0 - axis.z() * axis.z())) / axis.z();
    if (s + spread < -half_height || s - spread >= half_height) return;  // not cut
    const bool sides_only = s - spread >= -half_height && s + spread < half_height;
    if ((sides_only && axis.z() >= std::cos(max_tilt_rad)) || uncut == nullptr) {
      out->circles.push_back({{c.x() + s * axis.x(), c.y() + s * axis.y()}, radius, element});
      return;
    }
  } else if (uncut == nullptr) {
    return;  // lying flat: no meaningful circle for the picture
  }
  AddUncut(c, bound, element, uncut);
}

}  // namespace

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
  };

  WorldDescription description;
  WorldOptions options;
  std::int64_t tick = 0;

  btDefaultCollisionConfiguration collision_config;
  btCollisionDispatcher dispatcher{&collision_config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld dynamics{&dispatcher, &broadphase, &solver, &collision_config};

  // Ownership of everything Bullet points to; released in reverse in ~Impl.
  std::vector<std::unique_ptr<btTriangleMesh>> triangle_meshes;
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btMotionState>> motion_states;
  std::vector<std::unique_ptr<btRigidBody>> rigid_bodies;

  struct RobotPart {
    btRigidBody* rigid = nullptr;
    btTransform base_from_part;  // where the part sits in the robot's base frame
  };
  struct Robot {
    RobotSpec spec;
    int group = -1;
    int element = -1;              // chassis (and attachments' object)
    std::vector<RobotPart> parts;  // chassis first, then left, right wheel, casters
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
  };

  // Robots' own parts never collide with each other.
  struct SameRobotFilter : btOverlapFilterCallback {
    const std::vector<core::SectionElement>* elements = nullptr;
    bool needBroadphaseCollision(btBroadphaseProxy* p0, btBroadphaseProxy* p1) const override {
      if ((p0->m_collisionFilterGroup & p1->m_collisionFilterMask) == 0 ||
          (p1->m_collisionFilterGroup & p0->m_collisionFilterMask) == 0) {
        return false;
      }
      const int a = static_cast<const btCollisionObject*>(p0->m_clientObject)->getUserIndex();
      const int b = static_cast<const btCollisionObject*>(p1->m_clientObject)->getUserIndex();
      if (a < 0 || b < 0) return true;
      const int ga = (*elements)[a].group;
      return ga < 0 || ga != (*elements)[b].group;
    }
  };

  // Laser-visible static geometry for the fast ray path (WorldOptions::baked_static_rays):
  // walls, boxes and meshes as one triangle BVH, cylinders and doors as primitive
  // objects (outside any Bullet world) met by exact intersections.
  std::unique_ptr<btTriangleMesh> ray_mesh;
  std::unique_ptr<btBvhTriangleMeshShape> ray_mesh_shape;
  std::vector<int> ray_triangle_element;  // element of each baked triangle
  // 1 for faces of closed prisms (outward normals: a ray from inside meets
  // only back faces and passes, as for convex shapes); 0 for mesh triangles.
  std::vector<char> ray_triangle_closed;
  std::vector<std::unique_ptr<btCollisionObject>> ray_objects;
  std::vector<btCollisionObject*> ray_doors;  // parallel to description.doors; null if unseen

  std::map<const btCollisionShape*, RayPrism> prisms;
  std::int64_t static_revision = 0;    // counts door moves
  mutable std::int64_t rays_cast = 0;  // guarded by ray_mutex
  mutable std::mutex ray_mutex;        // serializes CastRay (world.h)

  std::vector<core::SectionElement> elements;
  std::vector<Body> bodies;
  std::vector<Robot> robots;
  std::vector<std::unique_ptr<btTypedConstraint>> constraints;
  SameRobotFilter robot_filter;
  std::vector<btRigidBody*> doors;  // parallel to description.doors
  std::set<std::pair<int, int>> touching;

  Impl() {
    robot_filter.elements = &elements;
    dynamics.getPairCache()->setOverlapFilterCallback(&robot_filter);
  }

  ~Impl() {
    for (auto& c : constraints) dynamics.removeConstraint(c.get());
    for (auto& rb : rigid_bodies) dynamics.removeRigidBody(rb.get());
  }

  int AddElement(const std::string& id, const std::string& material, bool dynamic, int group = -1) {
    const core::LaserResponse laser =
        material.empty() ? core::LaserResponse::kNormal : description.MaterialNamed(material).laser;
    elements.push_back({id, laser, dynamic, group});
    return static_cast<int>(elements.size()) - 1;
  }

  bool IdTaken(const std::string& id) const {
    return std::any_of(elements.begin(), elements.end(),
                       [&](const core::SectionElement& e) { return e.id == id; });
  }

  // A dynamic rigid body owned by the world, never deactivated. Its inertia is
  // the shape's unless given (principal moments about the body axes).
  btRigidBody* AddDynamic(std::unique_ptr<btCollisionShape> shape, double mass_kg,
                          const btTransform& transform, double friction, double restitution,
                          int element, const btVector3* given_inertia = nullptr) {
    btVector3 inertia(0, 0, 0);
    shape->calculateLocalInertia(mass_kg, inertia);
    if (given_inertia != nullptr) inertia = *given_inertia;
    auto motion = std::make_unique<btDefaultMotionState>(transform);
    btRigidBody::btRigidBodyConstructionInfo info(mass_kg, motion.get(), shape.get(), inertia);
    info.m_friction = friction;
    info.m_restitution = restitution;
    auto rigid = std::make_unique<btRigidBody>(info);
    rigid->setActivationState(DISABLE_DEACTIVATION);
    rigid->setUserIndex(element);
    dynamics.addRigidBody(rigid.get());
    shapes.push_back(std::move(shape));
    motion_states.push_back(std::move(motion));
    rigid_bodies.push_back(std::move(rigid));
    return rigid_bodies.back().get();
  }

  // The chassis of a WheelModel::kRaycast robot: `compound` (origin at the
  // common centre of mass of the reference's parts, `base_from_chassis`)
  // carrying the mass of the whole robot, and the contact solver of its wheels
  // and casters.
  void AddRaycastRobot(std::unique_ptr<btCompoundShape> compound,
                       const btTransform& base_from_chassis, const PartMasses& masses,
                       double chassis_com_z_m, const double radius[2], const double wheel_y[2],
                       const Material& material, int first_attachment, Robot* robot) {
    const RobotDescription& m = robot->spec.model;
    const double com_z = robot->com_z_m;
    // The reference's bodies welded together, so that a push or a collision
    // tips and slides the robot as it does the reference (whose lumped drive
    // units make it bottom-heavy): the inertia about the common centre of mass
    // is the chassis' as the reference computes it (its compound's) plus each
    // wheel and caster as a solid sphere, by the parallel-axis theorem.
    btVector3 inertia(0, 0, 0);
    compound->calculateLocalInertia(masses.chassis_kg, inertia);
    const double dz = chassis_com_z_m - com_z;
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
                 btVector3(wheels[side]->position_m.x(), wheel_y[side], radius[side]),
                 radius[side]);
    }
    for (const CasterSpec& c : m.casters) {
      add_sphere(masses.caster_kg, btVector3(c.position_m.x(), c.position_m.y(), c.radius_m),
                 c.radius_m);
    }
    // Pushes act where they act on the reference: at its chassis' centre of mass.
    robot->push_height_m = chassis_com_z_m - com_z;
    btRigidBody* chassis =
        AddDynamic(std::move(compound), m.total_mass_kg(), base_from_chassis, material.friction,
                   material.restitution, robot->element, &inertia);
    chassis->setUserIndex2(robot->spec.attachments.empty() ? -1 : first_attachment);
    robot->parts.push_back({chassis, base_from_chassis});

    // Wheels as the reference builds them (systematic errors applied), then casters.
    const double tread =
        kWheelTreadFriction * description.MaterialNamed(description.floor.material).friction;
    std::vector<RaycastWheelSpec> specs;
    for (int side = 0; side < 2; ++side) {
      specs.push_back({{wheels[side]->position_m.x(), wheel_y[side], radius[side] - com_z},
                       radius[side],
                       true,
                       tread,
                       m.max_wheel_torque_nm});
    }
    for (const CasterSpec& c : m.casters) {
      specs.push_back({{c.position_m.x(), c.position_m.y(), c.radius_m - com_z}, c.radius_m});
    }
    RaycastDriveOptions options;
    options.iterations = this->options.solver_iterations;
    options.gravity_mps2 = this->options.gravity_mps2;
    options.floor_min_m = description.floor.min_m;
    options.floor_max_m = description.floor.max_m;
    robot->drive_command_radps.assign(specs.size(), 0.0);
    robot->drive = std::make_unique<RaycastDrive>(std::move(specs), options);
  }

  // Places every part of a robot at `pose`, at rest.
  static void PlaceRobot(Robot* robot, const core::Pose2& pose) {
    const btTransform world_from_base = PlanarTransform(pose, 0.0);
    for (RobotPart& part : robot->parts) {
      const btTransform t = world_from_base * part.base_from_part;
      part.rigid->setWorldTransform(t);
      part.rigid->setInterpolationWorldTransform(t);
      part.rigid->getMotionState()->setWorldTransform(t);
      part.rigid->setLinearVelocity(btVector3(0, 0, 0));
      part.rigid->setAngularVelocity(btVector3(0, 0, 0));
      part.rigid->clearForces();
    }
    if (robot->raycast()) {
      // Its contact solver reads the world inertia tensor before Bullet
      // refreshes it; the reference's bodies are left as they always were.
      robot->chassis()->updateInertiaTensor();
      robot->drive->Reset();
    }
  }

  btTransform WorldFromBase(const Robot& robot) const {
    btTransform com_from_base;
    com_from_base.setIdentity();
    com_from_base.setOrigin(btVector3(0, 0, -robot.com_z_m));
    return robot.chassis()->getWorldTransform() * com_from_base;
  }

  // Solves a WheelModel::kRaycast robot's wheel contacts for the coming step
  // and leaves their impulses in the chassis' velocities.
  static void SolveRaycastContacts(Robot* robot, double dt) {
    btRigidBody* chassis = robot->chassis();
    const btMatrix3x3& basis = chassis->getWorldTransform().getBasis();
    const btMatrix3x3& inv_inertia = chassis->getInvInertiaTensorWorld();
    RaycastChassis c;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        c.world_from_body(i, j) = basis[i][j];
        c.inverse_inertia(i, j) = inv_inertia[i][j];
      }
    }
    const btVector3& com = chassis->getCenterOfMassPosition();
    const btVector3& v = chassis->getLinearVelocity();
    const btVector3& w = chassis->getAngularVelocity();
    c.com_m = {com.x(), com.y(), com.z()};
    c.inverse_mass = chassis->getInvMass();
    c.linear_mps = {v.x(), v.y(), v.z()};
    c.angular_radps = {w.x(), w.y(), w.z()};
    robot->drive_command_radps[0] = robot->command_radps[0];
    robot->drive_command_radps[1] = robot->command_radps[1];
    robot->drive->Solve(dt, robot->drive_command_radps, &c);
    chassis->setLinearVelocity(ToBt(c.linear_mps));
    chassis->setAngularVelocity(ToBt(c.angular_radps));
  }

  // Accumulates each wheel's rotation from its hinge angle (wrapped by Bullet).
  void UpdateWheelAngles(Robot* robot) {
    for (int side = 0; side < 2; ++side) {
      const double h = robot->hinge[side]->getHingeAngle();
      robot->wheel_rad[side] += kHingeSign * WrapAngle(h - robot->last_hinge_rad[side]);
      robot->last_hinge_rad[side] = h;
    }
  }

  btRigidBody* AddStatic(std::unique_ptr<btCollisionShape> shape, const btTransform& transform,
                         const std::string& material, int element) {
    const Material& m = description.MaterialNamed(material);
    btRigidBody::btRigidBodyConstructionInfo info(0.0, nullptr, shape.get());
    info.m_startWorldTransform = transform;
    info.m_friction = m.friction;
    info.m_restitution = m.restitution;
    auto body = std::make_unique<btRigidBody>(info);
    body->setUserIndex(element);
    dynamics.addRigidBody(body.get());
    shapes.push_back(std::move(shape));
    rigid_bodies.push_back(std::move(body));
    return rigid_bodies.back().get();
  }

  void AddStaticMesh(std::unique_ptr<btTriangleMesh> mesh, const std::string& material,
                     int element) {
    auto shape = std::make_unique<btBvhTriangleMeshShape>(mesh.get(), true);
    shape->setMargin(kMeshMarginM);
    triangle_meshes.push_back(std::move(mesh));
    btTransform identity;
    identity.setIdentity();
    AddStatic(std::move(shape), identity, material, element);
  }

  static btTransform BoxTransform(const Box& box) {
    btTransform t;
    t.setIdentity();
    t.setOrigin(btVector3(box.pose.x_m, box.pose.y_m, box.base_z_m + 0.5 * box.size_m.z()));
    t.setRotation(btQuaternion(btVector3(0, 0, 1), box.pose.theta_rad));
    return t;
  }

  btRigidBody* AddBox(const Box& box) {
    const int element = AddElement(box.id, box.material, false);
    auto shape = MakeBox(0.5 * box.size_m);
    return AddStatic(std::move(shape), BoxTransform(box), box.material, element);
  }

  void Build() {
    const Floor& floor = description.floor;
    {
      const int element = AddElement("floor", floor.material, false);
      const Eigen::Vector2d half = 0.5 * (floor.max_m - floor.min_m);
      const Eigen::Vector2d centre = 0.5 * (floor.max_m + floor.min_m);
      auto shape =
          std::make_unique<btBoxShape>(btVector3(half.x(), half.y(), 0.5 * kFloorThicknessM));
      btTransform t;
      t.setIdentity();
      t.setOrigin(btVector3(centre.x(), centre.y(), -0.5 * kFloorThicknessM));
      AddStatic(std::move(shape), t, floor.material, element);
    }
    for (const Wall& wall : description.walls) {
      const int element = AddElement(wall.id, wall.material, false);
      // One convex prism per mitred quad in a compound: convex-convex contacts
      // are several times cheaper than contacts with a triangle mesh.
      auto compound = std::make_unique<btCompoundShape>();
      btTransform identity;
      identity.setIdentity();
      for (const Quad& q : WallFootprint(wall)) {
        auto hull = std::make_unique<btConvexHullShape>();
        for (const auto& corner : q) {
          hull->addPoint(btVector3(corner.x(), corner.y(), wall.base_z_m), false);
          hull->addPoint(btVector3(corner.x(), corner.y(), wall.base_z_m + wall.height_m), false);
        }
        hull->recalcLocalAabb();
        // No margin: Bullet would inflate the hull by it, and rays would meet
        // the wall a margin early (1 mm/cos(incidence) short ranges).
        hull->setMargin(0.0);
        compound->addChildShape(identity, hull.get());
        shapes.push_back(std::move(hull));
      }
      AddStatic(std::move(compound), identity, wall.material, element);
    }
    for (const Box& box : description.boxes) AddBox(box);
    for (const Cylinder& c : description.cylinders) {
      const int element = AddElement(c.id, c.material, false);
      auto shape =
          std::make_unique<btCylinderShapeZ>(btVector3(c.radius_m, c.radius_m, 0.5 * c.height_m));
      btTransform t;
      t.setIdentity();
      t.setOrigin(btVector3(c.position_m.x(), c.position_m.y(), c.base_z_m + 0.5 * c.height_m));
      AddStatic(std::move(shape), t, c.material, element);
    }
    for (const Mesh& m : description.meshes) {
      const int element = AddElement(m.id, m.material, false);
      const std::vector<Eigen::Vector3d> vertices = PlacedVertices(m);
      const auto source = LoadTriangleMesh(m.file);
      auto mesh = std::make_unique<btTriangleMesh>();
      for (const auto& tri : source->triangles) {
        mesh->addTriangle(ToBt(vertices[tri[0]]), ToBt(vertices[tri[1]]), ToBt(vertices[tri[2]]));
      }
      AddStaticMesh(std::move(mesh), m.material, element);
    }
    for (const Door& door : description.doors) doors.push_back(AddBox(door.AsBox()));
  }

  bool LaserVisible(int element) const {
    return elements[element].laser != core::LaserResponse::kTransparent;
  }

  void AddRayObject(std::unique_ptr<btCollisionShape> shape, const btTransform& t, int element) {
    auto object = std::make_unique<btCollisionObject>();
    object->setCollisionShape(shape.get());
    object->setWorldTransform(t);
    object->setUserIndex(element);
    shapes.push_back(std::move(shape));
    ray_objects.push_back(std::move(object));
  }

  // A vertical prism over a convex outline as triangles of the ray mesh.
  void BakePrism(const Quad& q, double z0, double z1, int element) {
    const auto v = [](const Eigen::Vector2d& p, double z) { return btVector3(p.x(), p.y(), z); };
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d& a = q[k];
      const Eigen::Vector2d& b = q[(k + 1) % 4];
      ray_mesh->addTriangle(v(a, z0), v(b, z0), v(b, z1));
      ray_mesh->addTriangle(v(a, z0), v(b, z1), v(a, z1));
      ray_triangle_element.insert(ray_triangle_element.end(), 2, element);
    }
    // Caps wound so that every face's normal points out of the solid (the
    // outline is counter-clockwise seen from above).
    ray_mesh->addTriangle(v(q[0], z1), v(q[1], z1), v(q[2], z1));
    ray_mesh->addTriangle(v(q[0], z1), v(q[2], z1), v(q[3], z1));
    ray_mesh->addTriangle(v(q[0], z0), v(q[2], z0), v(q[1], z0));
    ray_mesh->addTriangle(v(q[0], z0), v(q[3], z0), v(q[2], z0));
    ray_triangle_element.insert(ray_triangle_element.end(), 4, element);
    ray_triangle_closed.resize(ray_triangle_element.size(), 1);
  }

  // Builds the ray world from the static elements (after Build()).
  void BuildRayWorld() {
    ray_mesh = std::make_unique<btTriangleMesh>();
    int element = 1;  // the floor (0) is never in a horizontal beam's way
    for (const Wall& wall : description.walls) {
      if (LaserVisible(element)) {
        for (const Quad& q : WallFootprint(wall)) {
          BakePrism(q, wall.base_z_m, wall.base_z_m + wall.height_m, element);
        }
      }
      ++element;
    }
    for (const Box& box : description.boxes) {
      if (LaserVisible(element)) {
        BakePrism(BoxFootprint(box), box.base_z_m, box.base_z_m + box.size_m.z(), element);
      }
      ++element;
    }
    for (const Cylinder& c : description.cylinders) {
      if (LaserVisible(element)) {
        btTransform t;
        t.setIdentity();
        t.setOrigin(btVector3(c.position_m.x(), c.position_m.y(), c.base_z_m + 0.5 * c.height_m));
        AddRayObject(
            std::make_unique<btCylinderShapeZ>(btVector3(c.radius_m, c.radius_m, 0.5 * c.height_m)),
            t, element);
      }
      ++element;
    }
    for (const Mesh& m : description.meshes) {
      if (LaserVisible(element)) {
        const auto source = LoadTriangleMesh(m.file);
        const std::vector<Eigen::Vector3d> v = PlacedVertices(m);
        for (const auto& tri : source->triangles) {
          ray_mesh->addTriangle(ToBt(v[tri[0]]), ToBt(v[tri[1]]), ToBt(v[tri[2]]));
          ray_triangle_element.push_back(element);
          ray_triangle_closed.push_back(0);
        }
      }
      ++element;
    }
    for (const Door& door : description.doors) {
      if (LaserVisible(element)) {
        const Box box = door.AsBox();
        AddRayObject(MakeBox(0.5 * box.size_m), BoxTransform(box), element);
        ray_doors.push_back(ray_objects.back().get());
      } else {
        ray_doors.push_back(nullptr);
      }
      ++element;
    }
    if (!ray_triangle_element.empty()) {
      ray_mesh_shape = std::make_unique<btBvhTriangleMeshShape>(ray_mesh.get(), true);
    }
  }

  // A mesh's vertices scaled, yawed and placed in the world frame.
  static std::vector<Eigen::Vector3d> PlacedVertices(const Mesh& m) {
    const auto source = LoadTriangleMesh(m.file);
    const double c = std::cos(m.yaw_rad);
    const double s = std::sin(m.yaw_rad);
    std::vector<Eigen::Vector3d> out;
    out.reserve(source->vertices.size());
    for (const Eigen::Vector3d& v : source->vertices) {
      const Eigen::Vector3d p = v.cwiseProduct(m.scale);
      out.emplace_back(m.position_m.x() + c * p.x() - s * p.y(),
                       m.position_m.y() + s * p.x() + c * p.y(), m.position_m.z() + p.z());
    }
    return out;
  }

  void AppendStaticSection(double z, core::PlanarSection* out) const {
    int element = 1;  // 0 is the floor
    for (const Wall& wall : description.walls) {
      if (SpansHeight(wall.base_z_m, wall.height_m, z)) {
        for (const auto& seg : WallOutline(wall))
          out->segments.push_back({seg[0], seg[1], element});
      }
      ++element;
    }
    for (const Box& box : description.boxes) {
      if (SpansHeight(box.base_z_m, box.size_m.z(), z)) {
        AddPolygonSegments(BoxFootprint(box), element, out);
      }
      ++element;
    }
    for (const Cylinder& c : description.cylinders) {
      if (SpansHeight(c.base_z_m, c.height_m, z))
        out->circles.push_back({c.position_m, c.radius_m, element});
      ++element;
    }
    for (const Mesh& m : description.meshes) {
      const auto source = LoadTriangleMesh(m.file);
      const std::vector<Eigen::Vector3d> v = PlacedVertices(m);
      for (const auto& tri : source->triangles) {
        CutTriangle(v[tri[0]], v[tri[1]], v[tri[2]], z, element, out);
      }
      ++element;
    }
    for (const Door& door : description.doors) {
      const Box box = door.AsBox();
      if (SpansHeight(box.base_z_m, box.size_m.z(), z)) {
        AddPolygonSegments(BoxFootprint(box), element, out);
      }
      ++element;
    }
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
    for (const Robot& robot : robots) {
      // The chassis compound (origin at the centre of mass): child 0 the
      // footprint prism, child k >= 1 attachment k - 1.
      const btRigidBody* chassis = robot.chassis();
      const btTransform& t = chassis->getWorldTransform();
      const auto* compound = static_cast<const btCompoundShape*>(chassis->getCollisionShape());
      const RayPrism& prism = prisms.at(compound->getChildShape(0));
      CutPrism(t * compound->getChildTransform(0), prism.polygon, prism.z0, prism.z1, z,
               robot.element, out, uncut);
      for (std::size_t k = 0; k < robot.spec.attachments.size(); ++k) {
        const RobotAttachment& a = robot.spec.attachments[k];
        const int child = static_cast<int>(k) + 1;
        CutCylinder(t * compound->getChildTransform(child), a.radius_m, 0.5 * a.height_m, z,
                    max_cylinder_tilt_rad, chassis->getUserIndex2() + static_cast<int>(k), out,
                    uncut);
      }
      for (std::size_t p = 1; p < robot.parts.size(); ++p) {
        const btRigidBody* rb = robot.parts[p].rigid;
        const auto* sphere = static_cast<const btSphereShape*>(rb->getCollisionShape());
        CutSphere(rb->getWorldTransform().getOrigin(), sphere->getRadius(), z, rb->getUserIndex(),
                  out);
      }
    }
  }

  void UpdateContacts(std::vector<ContactChange>* changes) {
    std::set<std::pair<int, int>> now;
    std::vector<ContactChange> begins;
    const int manifolds = dispatcher.getNumManifolds();
    for (int m = 0; m < manifolds; ++m) {
      const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
      int a = manifold->getBody0()->getUserIndex();
      int b = manifold->getBody1()->getUserIndex();
      if (a == 0 || b == 0) continue;  // the floor
      double impulse = 0.0;
      bool touching_now = false;
      btVector3 point(0, 0, 0);
      for (int p = 0; p < manifold->getNumContacts(); ++p) {
        const btManifoldPoint& cp = manifold->getContactPoint(p);
        if (cp.getDistance() < kContactDistanceM) {
          touching_now = true;
          if (cp.getAppliedImpulse() >= impulse) {
            impulse = cp.getAppliedImpulse();
            point = cp.getPositionWorldOnA();
          }
        }
      }
      if (!touching_now) continue;
      if (a > b) std::swap(a, b);
      if (!now.insert({a, b}).second) continue;
      if (!touching.contains({a, b})) {
        begins.push_back({true, a, b, {point.x(), point.y(), point.z()}, impulse});
      }
    }
    // Deterministic order: ends then begins, each sorted by element pair.
    for (const auto& pair : touching) {
      if (!now.contains(pair)) changes->push_back({false, pair.first, pair.second, {0, 0, 0}, 0.0});
    }
    std::sort(begins.begin(), begins.end(), [](const ContactChange& x, const ContactChange& y) {
      return std::pair(x.a, x.b) < std::pair(y.a, y.b);
    });
    changes->insert(changes->end(), begins.begin(), begins.end());
    touching = std::move(now);
  }

  std::vector<ContactChange> pending_changes;
};

World::World(WorldDescription description, const WorldOptions& options)
    : impl_(std::make_unique<Impl>()) {
  options.Validate();
  impl_->description = std::move(description);
  impl_->options = options;
  impl_->dynamics.setGravity(btVector3(0, 0, -options.gravity_mps2));
  impl_->dynamics.getSolverInfo().m_numIterations = options.solver_iterations;
  impl_->dynamics.getSolverInfo().m_solverMode |= kSolverFrictionModes;
  impl_->Build();
  if (options.baked_static_rays) impl_->BuildRayWorld();
}

World::~World() = default;

int World::AddBody(const BodySpec& spec) {
  if (!(spec.mass_kg > 0.0))
    throw std::invalid_argument("body '" + spec.id + "': mass_kg must be > 0");
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
  const int element = im.AddElement(spec.id, spec.material, true);
  rigid->setUserIndex(element);
  im.dynamics.addRigidBody(rigid.get());
  Impl::Body record{spec, element, rigid.get(), {0, 0}, 0.0, 0.0, 0.0};
  if (spec.upright && !spec.driven) {
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
  im.bodies.push_back(record);
  im.shapes.push_back(std::move(shape));
  im.motion_states.push_back(std::move(motion));
  im.rigid_bodies.push_back(std::move(rigid));
  return static_cast<int>(im.bodies.size()) - 1;
}

int World::AddRobot(const RobotSpec& spec) {
  Impl& im = *impl_;
  const RobotDescription& m = spec.model;
  const auto fail = [&](const std::string& what) {
    throw std::invalid_argument("robot '" + spec.id + "': " + what);
  };
  if (spec.id.empty()) throw std::invalid_argument("robot id must not be empty");
  if (im.IdTaken(spec.id)) fail("id is already used by a world element or body");
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
  const Material& material = im.description.MaterialNamed(m.material);

  Impl::Robot robot;
  robot.spec = spec;
  robot.group = static_cast<int>(im.robots.size());
  // The chassis' centre of mass from the model, kept on the base's z axis (the
  // drive is symmetric) and inside the chassis' height.
  robot.com_z_m =
      std::clamp(m.chassis_com_m.z(), m.chassis_base_z_m, m.chassis_base_z_m + m.chassis_height_m);
  const double chassis_com_z_m = robot.com_z_m;
  // Drive wheels: the physical robot's radii and wheelbase carry the
  // systematic errors (mean radius and the wheel positions' midpoint kept).
  const double ratio = spec.systematic.wheel_radius_ratio;
  const double mean_radius = 0.5 * (m.left_wheel.radius_m + m.right_wheel.radius_m);
  const double radius[2] = {2.0 * mean_radius / (1.0 + ratio),
                            2.0 * mean_radius * ratio / (1.0 + ratio)};
  const double mid_y = 0.5 * (m.left_wheel.position_m.y() + m.right_wheel.position_m.y());
  const double half_base = 0.5 * m.wheelbase_m() * spec.systematic.wheelbase_factor;
  const WheelSpec* wheel_specs[2] = {&m.left_wheel, &m.right_wheel};
  const double wheel_y[2] = {mid_y + half_base, mid_y - half_base};
  const bool raycast = spec.wheel_model == WheelModel::kRaycast;
  const PartMasses masses = ReferencePartMasses(m);
  if (raycast) {
    // One body carries the reference's parts as if welded together: its centre
    // of mass is theirs (kept on the base's z axis, as the chassis').
    double moment = masses.chassis_kg * chassis_com_z_m;
    for (int side = 0; side < 2; ++side) moment += masses.wheel_kg[side] * radius[side];
    for (const CasterSpec& c : m.casters) moment += masses.caster_kg * c.radius_m;
    robot.com_z_m = moment / m.total_mass_kg();
  }

  // Chassis: the footprint prism and the attachments in one compound whose
  // origin is the centre of mass. Child 0 is the prism (the chassis element);
  // child k >= 1 is attachment k - 1, its own element (see ElementOf).
  auto compound = std::make_unique<btCompoundShape>();
  {
    auto hull = std::make_unique<btConvexHullShape>();
    for (const Eigen::Vector2d& p : m.footprint_m) {
      hull->addPoint(btVector3(p.x(), p.y(), m.chassis_base_z_m - robot.com_z_m), false);
      hull->addPoint(
          btVector3(p.x(), p.y(), m.chassis_base_z_m + m.chassis_height_m - robot.com_z_m), false);
    }
    if (raycast) {
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
    im.prisms[hull.get()] = {m.footprint_m, m.chassis_base_z_m - robot.com_z_m,
                             m.chassis_base_z_m + m.chassis_height_m - robot.com_z_m};
    btTransform identity;
    identity.setIdentity();
    compound->addChildShape(identity, hull.get());
    im.shapes.push_back(std::move(hull));
  }
  for (const RobotAttachment& a : spec.attachments) {
    auto cylinder =
        std::make_unique<btCylinderShapeZ>(btVector3(a.radius_m, a.radius_m, 0.5 * a.height_m));
    btTransform t;
    t.setIdentity();
    t.setOrigin(btVector3(a.position_m.x(), a.position_m.y(),
                          a.base_z_m + 0.5 * a.height_m - robot.com_z_m));
    compound->addChildShape(t, cylinder.get());
    im.shapes.push_back(std::move(cylinder));
  }
  robot.element = im.AddElement(spec.id, m.material, true, robot.group);
  const int first_attachment = static_cast<int>(im.elements.size());
  for (const RobotAttachment& a : spec.attachments) {
    im.AddElement(spec.id + "/" + a.name, a.material, true, robot.group);
  }
  btTransform base_from_chassis;
  base_from_chassis.setIdentity();
  base_from_chassis.setOrigin(btVector3(0, 0, robot.com_z_m));
  if (raycast) {
    im.AddRaycastRobot(std::move(compound), base_from_chassis, masses, chassis_com_z_m, radius,
                       wheel_y, material, first_attachment, &robot);
    Impl::PlaceRobot(&robot, spec.pose);
    im.robots.push_back(std::move(robot));
    return static_cast<int>(im.robots.size()) - 1;
  }
  const double* wheel_mass_kg = masses.wheel_kg;
  btRigidBody* chassis = im.AddDynamic(std::move(compound), masses.chassis_kg, base_from_chassis,
                                       material.friction, material.restitution, robot.element);
  chassis->setUserIndex2(spec.attachments.empty() ? -1 : first_attachment);
  robot.parts.push_back({chassis, base_from_chassis});

  for (int side = 0; side < 2; ++side) {
    const WheelSpec& w = *wheel_specs[side];
    const double y = wheel_y[side];
    btTransform base_from_wheel;
    base_from_wheel.setIdentity();
    base_from_wheel.setOrigin(btVector3(w.position_m.x(), y, radius[side]));
    const int element = im.AddElement(spec.id + (side == 0 ? "/left_wheel" : "/right_wheel"),
                                      m.material, true, robot.group);
    btRigidBody* wheel =
        im.AddDynamic(std::make_unique<btSphereShape>(radius[side]), wheel_mass_kg[side],
                      base_from_wheel, kWheelTreadFriction, 0.0, element);
    robot.parts.push_back({wheel, base_from_wheel});
    const btVector3 pivot_in_chassis = base_from_chassis.inverse() * base_from_wheel.getOrigin();
    auto hinge =
        std::make_unique<btHingeConstraint>(*chassis, *wheel, pivot_in_chassis, btVector3(0, 0, 0),
                                            btVector3(0, 1, 0), btVector3(0, 1, 0));
    robot.hinge[side] = hinge.get();
    im.dynamics.addConstraint(hinge.get(), true);
    im.constraints.push_back(std::move(hinge));
  }
  // Casters: nearly frictionless spheres on ball joints.
  for (const CasterSpec& c : m.casters) {
    btTransform base_from_caster;
    base_from_caster.setIdentity();
    base_from_caster.setOrigin(btVector3(c.position_m.x(), c.position_m.y(), c.radius_m));
    const int element = im.AddElement(spec.id + "/" + c.link, m.material, true, robot.group);
    btRigidBody* caster = im.AddDynamic(std::make_unique<btSphereShape>(c.radius_m),
                                        masses.caster_kg, base_from_caster, 0.0, 0.0, element);
    robot.parts.push_back({caster, base_from_caster});
    auto joint = std::make_unique<btPoint2PointConstraint>(
        *chassis, *caster, base_from_chassis.inverse() * base_from_caster.getOrigin(),
        btVector3(0, 0, 0));
    im.dynamics.addConstraint(joint.get(), true);
    im.constraints.push_back(std::move(joint));
  }
  Impl::PlaceRobot(&robot, spec.pose);
  // The parts entered the broadphase at their base-frame transforms, around the
  // origin; move their bounding boxes to the robot's pose now. Left to the next
  // step, every robot added meanwhile would overlap every earlier one there:
  // N^2/2 pairs created and dropped again (for the hall benchmark's 1000 robots,
  // 12.5 million pairs, 400 MB and seconds of start-up).
  for (Impl::RobotPart& part : robot.parts) im.dynamics.updateSingleAabb(part.rigid);
  for (int side = 0; side < 2; ++side)
    robot.last_hinge_rad[side] = robot.hinge[side]->getHingeAngle();
  im.robots.push_back(std::move(robot));
  return static_cast<int>(im.robots.size()) - 1;
}

int World::robot_count() const { return static_cast<int>(impl_->robots.size()); }
const RobotSpec& World::robot_spec(int robot) const { return impl_->robots.at(robot).spec; }
int World::robot_group(int robot) const { return impl_->robots.at(robot).group; }
int World::robot_element(int robot) const { return impl_->robots.at(robot).element; }

RobotState World::robot_state(int robot) const {
  const Impl::Robot& r = impl_->robots.at(robot);
  const btRigidBody* chassis = r.chassis();
  const btTransform world_from_base = impl_->WorldFromBase(r);
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

void World::SetWheelSpeeds(int robot, double left_radps, double right_radps) {
  Impl::Robot& r = impl_->robots.at(robot);
  const double limit = r.spec.model.max_wheel_speed_radps;
  r.target_radps[0] = std::clamp(left_radps, -limit, limit);
  r.target_radps[1] = std::clamp(right_radps, -limit, limit);
}

std::vector<Eigen::Vector2d> World::RobotContactPoints(int robot) const {
  const Impl& im = *impl_;
  const Impl::Robot& r = im.robots.at(robot);
  const btTransform base_from_world = im.WorldFromBase(r).inverse();
  std::vector<Eigen::Vector2d> points;
  const int manifolds = im.dispatcher.getNumManifolds();
  for (int k = 0; k < manifolds; ++k) {
    const btPersistentManifold* manifold =
        const_cast<btCollisionDispatcher&>(im.dispatcher).getManifoldByIndexInternal(k);
    const bool chassis_is_a = manifold->getBody0() == r.chassis();
    if (!chassis_is_a && manifold->getBody1() != r.chassis()) continue;
    const btCollisionObject* other = chassis_is_a ? manifold->getBody1() : manifold->getBody0();
    if (other->getUserIndex() == 0) continue;  // the floor
    for (int p = 0; p < manifold->getNumContacts(); ++p) {
      const btManifoldPoint& cp = manifold->getContactPoint(p);
      if (cp.getDistance() >= kContactDistanceM) continue;
      const btVector3 q =
          base_from_world * (chassis_is_a ? cp.getPositionWorldOnA() : cp.getPositionWorldOnB());
      points.emplace_back(q.x(), q.y());
    }
  }
  return points;
}

void World::ApplyRobotImpulse(int robot, const Eigen::Vector2d& impulse_ns) {
  const Impl::Robot& r = impl_->robots.at(robot);
  const btVector3 impulse(impulse_ns.x(), impulse_ns.y(), 0.0);
  if (r.push_height_m == 0.0) {
    r.chassis()->applyCentralImpulse(impulse);
  } else {
    const btVector3 up = r.chassis()->getWorldTransform().getBasis().getColumn(2);
    r.chassis()->applyImpulse(impulse, r.push_height_m * up);
  }
}

void World::TeleportRobot(int robot, const core::Pose2& pose) {
  Impl::Robot& r = impl_->robots.at(robot);
  Impl::PlaceRobot(&r, pose);
  for (int side = 0; side < 2; ++side) {
    r.command_radps[side] = 0.0;
    r.target_radps[side] = 0.0;
    if (!r.raycast()) r.last_hinge_rad[side] = r.hinge[side]->getHingeAngle();
  }
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
    im.doors[i]->setWorldTransform(Impl::BoxTransform(door.AsBox()));
    // Static bodies are not re-inserted by Bullet: refresh the broadphase bounds.
    im.dynamics.updateSingleAabb(im.doors[i]);
    if (i < im.ray_doors.size() && im.ray_doors[i] != nullptr) {
      im.ray_doors[i]->setWorldTransform(Impl::BoxTransform(door.AsBox()));
    }
    return;
  }
  throw std::out_of_range("no door '" + door_id + "'");
}

void World::Step() {
  Impl& im = *impl_;
  const double dt = step_s();
  for (Impl::Body& b : im.bodies) {
    if (b.slide_decel_mps2 > 0.0 && b.rigid->getInvMass() > 0.0 &&
        b.rigid->getWorldTransform().getOrigin().z() <
            b.spec.shape.HalfHeight() + kContactDistanceM) {
      // Coulomb friction with the floor; it stops a body but never reverses it.
      btVector3 v = b.rigid->getLinearVelocity();
      const double speed = std::hypot(v.x(), v.y());
      const double dv = std::min(speed, b.slide_decel_mps2 * dt);
      if (speed > 0.0)
        b.rigid->setLinearVelocity(
            btVector3(v.x() * (1 - dv / speed), v.y() * (1 - dv / speed), v.z()));
      btVector3 w = b.rigid->getAngularVelocity();
      const double dw = std::min(std::abs(w.z()), b.spin_decel_radps2 * dt);
      b.rigid->setAngularVelocity(btVector3(w.x(), w.y(), w.z() - std::copysign(dw, w.z())));
    }
    if (!b.spec.driven) continue;
    const btVector3 v = b.rigid->getLinearVelocity();
    b.rigid->setLinearVelocity(btVector3(b.velocity_mps.x(), b.velocity_mps.y(), v.z()));
    const btVector3 w = b.rigid->getAngularVelocity();
    b.rigid->setAngularVelocity(btVector3(w.x(), w.y(), b.yaw_rate_radps));
  }
  for (Impl::Robot& r : im.robots) {
    const RobotDescription& m = r.spec.model;
    for (int side = 0; side < 2; ++side) {
      // Acceleration ramp towards the commanded speed; the motor delivers at
      // most the torque limit over the step.
      const double step = m.max_wheel_accel_radps2 * dt;
      r.command_radps[side] +=
          std::clamp(r.target_radps[side] - r.command_radps[side], -step, step);
      if (!r.raycast()) {
        r.hinge[side]->enableAngularMotor(true, kHingeSign * r.command_radps[side],
                                          m.max_wheel_torque_nm * dt);
      }
    }
    if (r.raycast()) im.SolveRaycastContacts(&r, dt);
  }
  im.dynamics.stepSimulation(dt, 0, dt);
  for (Impl::Robot& r : im.robots) {
    if (r.raycast()) {
      r.drive->Integrate(dt);
    } else {
      im.UpdateWheelAngles(&r);
    }
  }
  ++im.tick;
  im.UpdateContacts(&im.pending_changes);
}

TickSnapshot World::Snapshot() const {
  TickSnapshot snapshot;
  snapshot.tick = impl_->tick;
  snapshot.time_s = time_s();
  snapshot.bodies.reserve(impl_->bodies.size());
  for (int b = 0; b < body_count(); ++b) snapshot.bodies.push_back(body_state(b));
  snapshot.robots.reserve(impl_->robots.size());
  for (int r = 0; r < robot_count(); ++r) snapshot.robots.push_back(robot_state(r));
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
  return section;
}

core::PlanarSection World::StaticSectionAt(double height_m) const {
  core::PlanarSection section;
  section.height_m = height_m;
  section.elements = impl_->elements;
  impl_->AppendStaticSection(height_m, &section);
  return section;
}

void World::AppendDynamicSection(double height_m, double max_cylinder_tilt_rad,
                                 core::PlanarSection* out, std::vector<UncutElement>* uncut) const {
  impl_->AppendBodySection(height_m, max_cylinder_tilt_rad, out, uncut);
  impl_->AppendRobotSection(height_m, max_cylinder_tilt_rad, out, uncut);
}

std::int64_t World::static_revision() const { return impl_->static_revision; }

namespace {

// Closest hit that skips one element and, optionally, transparent elements.
class FilteredClosestRay : public btCollisionWorld::ClosestRayResultCallback {
 public:
  FilteredClosestRay(const btVector3& from, const btVector3& to,
                     const std::vector<core::SectionElement>& elements, int ignore,
                     bool hit_transparent)
      : ClosestRayResultCallback(from, to),
        elements_(elements),
        ignore_(ignore),
        hit_transparent_(hit_transparent) {}

  bool needsCollision(btBroadphaseProxy* proxy) const override {
    const auto* object = static_cast<const btCollisionObject*>(proxy->m_clientObject);
    const int element = object->getUserIndex();
    if (element >= 0) {
      const core::SectionElement& e = elements_[element];
      if (ignore_ >= 0 && e.group == ignore_) return false;
      if (!hit_transparent_ && e.laser == core::LaserResponse::kTransparent) return false;
    }
    return ClosestRayResultCallback::needsCollision(proxy);
  }

  // Called for each hit closer than the closest so far; the last call wins.
  btScalar addSingleResult(btCollisionWorld::LocalRayResult& result,
                           bool normal_in_world_space) override {
    element_ = result.m_collisionObject->getUserIndex();
    // A robot chassis compound: child k >= 1 is an attachment with its own element.
    const int first_attachment = result.m_collisionObject->getUserIndex2();
    if (first_attachment >= 0 && result.m_localShapeInfo != nullptr &&
        result.m_localShapeInfo->m_triangleIndex >= 1) {
      element_ = first_attachment + result.m_localShapeInfo->m_triangleIndex - 1;
    }
    return ClosestRayResultCallback::addSingleResult(result, normal_in_world_space);
  }

  int element() const { return element_; }

 private:
  const std::vector<core::SectionElement>& elements_;
  int ignore_;
  bool hit_transparent_;
  int element_ = -1;
};

// The closest triangle of the baked static mesh.
class MeshRay : public btTriangleRaycastCallback {
 public:
  MeshRay(const btVector3& from, const btVector3& to, const std::vector<char>& closed)
      : btTriangleRaycastCallback(from, to, kF_KeepUnflippedNormal), closed_(closed) {}
  btScalar reportHit(const btVector3& normal, btScalar fraction, int /*part*/,
                     int triangle) override {
    const bool back_face = normal.dot(m_to - m_from) > 0;
    if (back_face && closed_[triangle]) return m_hitFraction;  // leaving a solid
    if (fraction < m_hitFraction) {
      normal_ = normal;
      triangle_ = triangle;
    }
    return std::min(fraction, m_hitFraction);
  }
  bool hit() const { return triangle_ >= 0; }
  int triangle() const { return triangle_; }
  const btVector3& normal() const { return normal_; }

 private:
  const std::vector<char>& closed_;
  btVector3 normal_{0, 0, 0};
  int triangle_ = -1;
};

// The dynamic part of the laser's fast path: candidates from the physics
// world's broadphase, exact analytic intersections with their shapes
// (sim/raycast/ray_shapes.h), Bullet's generic ray test for any other shape.
class DynamicRay : public btBroadphaseRayCallback {
 public:
  DynamicRay(const btVector3& from, const btVector3& to,
             const std::vector<core::SectionElement>& elements,
             const std::map<const btCollisionShape*, RayPrism>& prisms, int ignore)
      : from_(from), to_(to), elements_(elements), prisms_(prisms), ignore_(ignore) {
    // Broadphase ray data (as btCollisionWorld::rayTest sets it up).
    btVector3 dir = to - from;
    const btScalar length = dir.length();
    if (length > 0) dir /= length;
    for (int i = 0; i < 3; ++i) {
      m_rayDirectionInverse[i] = dir[i] == 0.0 ? BT_LARGE_FLOAT : 1.0 / dir[i];
      m_signs[i] = m_rayDirectionInverse[i] < 0.0;
    }
    m_lambda_max = length;
  }

  bool process(const btBroadphaseProxy* proxy) override {
    const auto* object = static_cast<const btCollisionObject*>(proxy->m_clientObject);
    const int element = object->getUserIndex();
    if (element < 0) return true;
    const core::SectionElement& e = elements_[element];
    if (!e.dynamic || (ignore_ >= 0 && e.group == ignore_) ||
        e.laser == core::LaserResponse::kTransparent) {
      return true;
    }
    Test(object, object->getCollisionShape(), object->getWorldTransform(), element);
    return true;
  }

  // Tests one object of the static primitives, whatever its flags.
  void TestObject(const btCollisionObject* object) {
    Test(object, object->getCollisionShape(), object->getWorldTransform(), object->getUserIndex());
  }

  bool hit() const { return element_ >= 0; }
  double fraction() const { return fraction_; }
  const btVector3& normal() const { return normal_; }
  int element() const { return element_; }

 private:
  void Test(const btCollisionObject* object, const btCollisionShape* shape, const btTransform& t,
            int element) {
    if (shape->getShapeType() == COMPOUND_SHAPE_PROXYTYPE) {
      const auto* compound = static_cast<const btCompoundShape*>(shape);
      const int first_attachment = object->getUserIndex2();
      for (int k = 0; k < compound->getNumChildShapes(); ++k) {
        const int child_element =
            first_attachment >= 0 && k >= 1 ? first_attachment + k - 1 : element;
        Test(object, compound->getChildShape(k), t * compound->getChildTransform(k), child_element);
      }
      return;
    }
    // The ray in the shape's frame; t along from → to.
    const btVector3 o = t.invXform(from_);
    const btVector3 d = t.getBasis().transpose() * (to_ - from_);
    const Eigen::Vector3d eo(o.x(), o.y(), o.z()), ed(d.x(), d.y(), d.z());
    std::optional<RayShapeHit> h;
    switch (shape->getShapeType()) {
      case SPHERE_SHAPE_PROXYTYPE:
        h = RaySphere(eo, ed, static_cast<const btSphereShape*>(shape)->getRadius(), fraction_);
        break;
      case BOX_SHAPE_PROXYTYPE: {
        const btVector3 half = static_cast<const btBoxShape*>(shape)->getHalfExtentsWithMargin();
        h = RayBox(eo, ed, {half.x(), half.y(), half.z()}, fraction_);
        break;
      }
      case CYLINDER_SHAPE_PROXYTYPE: {
        const auto* cylinder = static_cast<const btCylinderShape*>(shape);
        if (cylinder->getUpAxis() == 2) {
          const btVector3 half = cylinder->getHalfExtentsWithMargin();
          h = RayCylinderZ(eo, ed, half.x(), half.z(), fraction_);
        } else {
          Generic(object, shape, t, element);
          return;
        }
        break;
      }
      default:
        if (auto it = prisms_.find(shape); it != prisms_.end()) {
          h = RayPrismZ(eo, ed, it->second.polygon, it->second.z0, it->second.z1, fraction_);
        } else {
          Generic(object, shape, t, element);
          return;
        }
    }
    if (h && h->t < fraction_) {
      fraction_ = h->t;
      normal_ = t.getBasis() * btVector3(h->normal.x(), h->normal.y(), h->normal.z());
      element_ = element;
    }
  }

  void Generic(const btCollisionObject* object, const btCollisionShape* shape, const btTransform& t,
               int element) {
    btTransform from, to;
    from.setIdentity();
    from.setOrigin(from_);
    to.setIdentity();
    to.setOrigin(to_);
    btCollisionWorld::ClosestRayResultCallback result(from_, to_);
    result.m_closestHitFraction = fraction_;
    btCollisionWorld::rayTestSingle(from, to, const_cast<btCollisionObject*>(object), shape, t,
                                    result);
    if (result.hasHit() && result.m_closestHitFraction < fraction_) {
      fraction_ = result.m_closestHitFraction;
      normal_ = result.m_hitNormalWorld;
      element_ = element;
    }
  }

  btVector3 from_, to_;
  const std::vector<core::SectionElement>& elements_;
  const std::map<const btCollisionShape*, RayPrism>& prisms_;
  int ignore_;
  double fraction_ = 1.0;
  btVector3 normal_{0, 0, 0};
  int element_ = -1;
};

}  // namespace

RayHit World::CastRay(const Eigen::Vector3d& from_m, const Eigen::Vector3d& to_m, int ignore_group,
                      bool hit_transparent) const {
  const Impl& im = *impl_;
  const std::lock_guard<std::mutex> lock(im.ray_mutex);
  ++im.rays_cast;
  const btVector3 from = ToBt(from_m), to = ToBt(to_m);
  const auto make_hit = [&](const btVector3& p, const btVector3& normal, int element) {
    RayHit hit;
    hit.hit = true;
    hit.point_m = {p.x(), p.y(), p.z()};
    hit.distance_m = (hit.point_m - from_m).norm();
    Eigen::Vector3d n(normal.x(), normal.y(), normal.z());
    if (n.dot(to_m - from_m) > 0) n = -n;
    hit.normal = n.normalized();
    hit.element = element;
    return hit;
  };
  if (im.options.baked_static_rays && !hit_transparent) {
    // Fast path: the static triangle tree, the few static primitives, then the
    // dynamic bodies — each only up to the closest hit so far, and with exact
    // shape intersections.
    MeshRay mesh(from, to, im.ray_triangle_closed);
    if (im.ray_mesh_shape) im.ray_mesh_shape->performRaycast(&mesh, from, to);
    const btVector3 mesh_end = mesh.hit() ? from.lerp(to, mesh.m_hitFraction) : to;
    DynamicRay statics(from, mesh_end, im.elements, im.prisms, -1);
    for (const auto& object : im.ray_objects) statics.TestObject(object.get());
    const btVector3 end = statics.hit() ? from.lerp(mesh_end, statics.fraction()) : mesh_end;
    DynamicRay dynamic(from, end, im.elements, im.prisms, ignore_group);
    if (end != from) {
      const_cast<btDbvtBroadphase&>(im.broadphase).rayTest(from, end, dynamic);
    }
    if (dynamic.hit()) {
      return make_hit(from.lerp(end, dynamic.fraction()), dynamic.normal(), dynamic.element());
    }
    if (statics.hit()) return make_hit(end, statics.normal(), statics.element());
    if (mesh.hit()) {
      return make_hit(mesh_end, mesh.normal(), im.ray_triangle_element[mesh.triangle()]);
    }
    return RayHit{};
  }
  FilteredClosestRay all(from, to, im.elements, ignore_group, hit_transparent);
  im.dynamics.rayTest(from, to, all);
  RayHit hit;
  if (!all.hasHit()) return hit;
  const FilteredClosestRay& result = all;
  hit.hit = true;
  hit.point_m = {result.m_hitPointWorld.x(), result.m_hitPointWorld.y(),
                 result.m_hitPointWorld.z()};
  hit.distance_m = (hit.point_m - from_m).norm();
  Eigen::Vector3d n(result.m_hitNormalWorld.x(), result.m_hitNormalWorld.y(),
                    result.m_hitNormalWorld.z());
  if (n.dot(to_m - from_m) > 0) n = -n;
  hit.normal = n.normalized();
  hit.element = result.element();
  return hit;
}

const std::vector<core::SectionElement>& World::elements() const { return impl_->elements; }

std::int64_t World::rays_cast() const {
  const std::lock_guard<std::mutex> lock(impl_->ray_mutex);
  return impl_->rays_cast;
}

std::vector<ContactChange> World::TakeContactChanges() {
  std::vector<ContactChange> out;
  out.swap(impl_->pending_changes);
  return out;
}

const WorldDescription& World::description() const { return impl_->description; }

}  // namespace pavilion::sim
