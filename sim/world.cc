#include "sim/world.h"

#include <btBulletDynamicsCommon.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <utility>

#include "sim/triangle_mesh.h"
#include "sim/wall_geometry.h"

namespace pavilion::sim {
namespace {

// Contact points closer than this count as touching (m).
constexpr double kContactDistanceM = 0.005;
// Floor slab thickness below z = 0 (m); thick enough that nothing tunnels.
constexpr double kFloorThicknessM = 1.0;
// Collision margin for triangle meshes (m); small so that rays and contacts
// meet the surface the description gives.
constexpr double kMeshMarginM = 0.001;

btVector3 ToBt(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

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

void AddPolygonSegments(const Quad& q, int element, core::PlanarSection* out) {
  for (int k = 0; k < 4; ++k) out->segments.push_back({q[k], q[(k + 1) % 4], element});
}

bool SpansHeight(double base_z, double height, double z) {
  return z >= base_z && z < base_z + height;
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

  std::vector<core::SectionElement> elements;
  std::vector<Body> bodies;
  std::vector<btRigidBody*> doors;  // parallel to description.doors
  std::set<std::pair<int, int>> touching;

  ~Impl() {
    for (auto& rb : rigid_bodies) dynamics.removeRigidBody(rb.get());
  }

  int AddElement(const std::string& id, const std::string& material, bool dynamic) {
    const core::LaserResponse laser =
        material.empty() ? core::LaserResponse::kNormal : description.MaterialNamed(material).laser;
    elements.push_back({id, laser, dynamic});
    return static_cast<int>(elements.size()) - 1;
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
    auto shape = std::make_unique<btBoxShape>(ToBt(0.5 * box.size_m));
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
        hull->setMargin(kMeshMarginM);
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

  void AppendBodySection(double z, core::PlanarSection* out) const {
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      const Body& body = bodies[i];
      const btTransform& t = body.rigid->getWorldTransform();
      const double zc = t.getOrigin().z();
      const Eigen::Vector2d centre(t.getOrigin().x(), t.getOrigin().y());
      const BodyShape& shape = body.spec.shape;
      const double dz = z - zc;
      if (std::abs(dz) > shape.HalfHeight()) continue;
      // Bodies are taken as upright extrusions here; tilted bodies are the
      // planar caster's fallback case (speed issue).
      switch (shape.type) {
        case BodyShapeType::kCylinder:
          out->circles.push_back({centre, shape.radius_m, body.element});
          break;
        case BodyShapeType::kSphere:
          out->circles.push_back(
              {centre, std::sqrt(shape.radius_m * shape.radius_m - dz * dz), body.element});
          break;
        case BodyShapeType::kBox: {
          Box box;
          box.pose = {centre.x(), centre.y(), YawOf(t)};
          box.size_m = shape.box_size_m;
          AddPolygonSegments(BoxFootprint(box), body.element, out);
          break;
        }
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
  impl_->Build();
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
      shape = std::make_unique<btBoxShape>(ToBt(0.5 * spec.shape.box_size_m));
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
    im.doors[i]->setWorldTransform(Impl::BoxTransform(door.AsBox()));
    // Static bodies are not re-inserted by Bullet: refresh the broadphase bounds.
    im.dynamics.updateSingleAabb(im.doors[i]);
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
  im.dynamics.stepSimulation(dt, 0, dt);
  ++im.tick;
  im.UpdateContacts(&im.pending_changes);
}

TickSnapshot World::Snapshot() const {
  TickSnapshot snapshot;
  snapshot.tick = impl_->tick;
  snapshot.time_s = time_s();
  snapshot.bodies.reserve(impl_->bodies.size());
  for (int b = 0; b < body_count(); ++b) snapshot.bodies.push_back(body_state(b));
  return snapshot;
}

std::int64_t World::tick() const { return impl_->tick; }
double World::step_s() const { return 1.0 / impl_->options.physics_rate_hz; }
double World::time_s() const { return static_cast<double>(impl_->tick) * step_s(); }

core::PlanarSection World::SectionAt(double height_m) const {
  core::PlanarSection section;
  section.height_m = height_m;
  section.elements = impl_->elements;
  impl_->AppendStaticSection(height_m, &section);
  impl_->AppendBodySection(height_m, &section);
  return section;
}

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

 private:
  const std::vector<core::SectionElement>& elements_;
  int ignore_;
  bool hit_transparent_;
};

}  // namespace

RayHit World::CastRay(const Eigen::Vector3d& from_m, const Eigen::Vector3d& to_m, int ignore_group,
                      bool hit_transparent) const {
  const btVector3 from = ToBt(from_m), to = ToBt(to_m);
  FilteredClosestRay callback(from, to, impl_->elements, ignore_group, hit_transparent);
  impl_->dynamics.rayTest(from, to, callback);
  RayHit hit;
  if (!callback.hasHit()) return hit;
  hit.hit = true;
  hit.point_m = {callback.m_hitPointWorld.x(), callback.m_hitPointWorld.y(),
                 callback.m_hitPointWorld.z()};
  hit.distance_m = (hit.point_m - from_m).norm();
  Eigen::Vector3d n(callback.m_hitNormalWorld.x(), callback.m_hitNormalWorld.y(),
                    callback.m_hitNormalWorld.z());
  if (n.dot(to_m - from_m) > 0) n = -n;
  hit.normal = n.normalized();
  hit.element = callback.m_collisionObject->getUserIndex();
  return hit;
}

const std::vector<core::SectionElement>& World::elements() const { return impl_->elements; }

std::vector<ContactChange> World::TakeContactChanges() {
  std::vector<ContactChange> out;
  out.swap(impl_->pending_changes);
  return out;
}

const WorldDescription& World::description() const { return impl_->description; }

}  // namespace pavilion::sim
