#include "sim/world/physics_world.h"

#include <btBulletDynamicsCommon.h>

#include <utility>

#include "sim/world/world.h"

namespace pavilion::sim {
namespace {

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

// Broadphase filter groups: Bullet's own (btBroadphaseProxy) for dynamic and
// static bodies, plus one for the floor. A body added with
// Touches::kFloorOnly masks all but the floor; the others keep the group and
// mask btDiscreteDynamicsWorld::addRigidBody(body) would give them.
constexpr int kFloorFilter = 1 << 6;  // after btBroadphaseProxy::CharacterFilter (32)
constexpr int kDynamicGroup = btBroadphaseProxy::DefaultFilter;
constexpr int kStaticGroup = btBroadphaseProxy::StaticFilter;
constexpr int kAllMask = btBroadphaseProxy::AllFilter;

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

}  // namespace

struct PhysicsWorld::Impl {
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
  std::vector<std::unique_ptr<btTypedConstraint>> constraints;
  SameRobotFilter robot_filter;

  ~Impl() {
    for (auto& c : constraints) dynamics.removeConstraint(c.get());
    for (auto& rb : rigid_bodies) dynamics.removeRigidBody(rb.get());
  }
};

PhysicsWorld::PhysicsWorld(const WorldOptions& options,
                           const std::vector<core::SectionElement>* elements)
    : impl_(std::make_unique<Impl>()) {
  impl_->robot_filter.elements = elements;
  impl_->dynamics.getPairCache()->setOverlapFilterCallback(&impl_->robot_filter);
  impl_->dynamics.setGravity(btVector3(0, 0, -options.gravity_mps2));
  impl_->dynamics.getSolverInfo().m_numIterations = options.solver_iterations;
  impl_->dynamics.getSolverInfo().m_solverMode |= kSolverFrictionModes;
}

PhysicsWorld::~PhysicsWorld() = default;

btDiscreteDynamicsWorld& PhysicsWorld::dynamics() { return impl_->dynamics; }
const btDiscreteDynamicsWorld& PhysicsWorld::dynamics() const { return impl_->dynamics; }
btCollisionDispatcher& PhysicsWorld::dispatcher() { return impl_->dispatcher; }
const btCollisionDispatcher& PhysicsWorld::dispatcher() const { return impl_->dispatcher; }
btDbvtBroadphase& PhysicsWorld::broadphase() { return impl_->broadphase; }
const btDbvtBroadphase& PhysicsWorld::broadphase() const { return impl_->broadphase; }

btRigidBody* PhysicsWorld::AddStatic(std::unique_ptr<btCollisionShape> shape,
                                     const btTransform& transform, const Material& material,
                                     int element, bool floor) {
  btRigidBody::btRigidBodyConstructionInfo info(0.0, nullptr, shape.get());
  info.m_startWorldTransform = transform;
  info.m_friction = material.friction;
  info.m_restitution = material.restitution;
  auto body = std::make_unique<btRigidBody>(info);
  body->setUserIndex(element);
  impl_->dynamics.addRigidBody(body.get(), kStaticGroup | (floor ? kFloorFilter : 0),
                               kAllMask ^ kStaticGroup);
  impl_->shapes.push_back(std::move(shape));
  impl_->rigid_bodies.push_back(std::move(body));
  return impl_->rigid_bodies.back().get();
}

btRigidBody* PhysicsWorld::AddDynamic(std::unique_ptr<btCollisionShape> shape, double mass_kg,
                                      const btTransform& transform, double friction,
                                      double restitution, int element,
                                      const btVector3* given_inertia, Touches touches) {
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
  return AddRigidBody(std::move(shape), std::move(motion), std::move(rigid), touches);
}

btRigidBody* PhysicsWorld::AddRigidBody(std::unique_ptr<btCollisionShape> shape,
                                        std::unique_ptr<btMotionState> motion,
                                        std::unique_ptr<btRigidBody> rigid, Touches touches) {
  if (rigid->isStaticOrKinematicObject()) {
    impl_->dynamics.addRigidBody(rigid.get(), kStaticGroup, kAllMask ^ kStaticGroup);
  } else {
    impl_->dynamics.addRigidBody(rigid.get(), kDynamicGroup,
                                 touches == Touches::kFloorOnly ? kFloorFilter : kAllMask);
  }
  impl_->shapes.push_back(std::move(shape));
  impl_->motion_states.push_back(std::move(motion));
  impl_->rigid_bodies.push_back(std::move(rigid));
  return impl_->rigid_bodies.back().get();
}

void PhysicsWorld::AddConstraint(std::unique_ptr<btTypedConstraint> constraint,
                                 bool disable_collisions_between_linked_bodies) {
  impl_->dynamics.addConstraint(constraint.get(), disable_collisions_between_linked_bodies);
  impl_->constraints.push_back(std::move(constraint));
}

void PhysicsWorld::KeepShape(std::unique_ptr<btCollisionShape> shape) {
  impl_->shapes.push_back(std::move(shape));
}

void PhysicsWorld::KeepMesh(std::unique_ptr<btTriangleMesh> mesh) {
  impl_->triangle_meshes.push_back(std::move(mesh));
}

}  // namespace pavilion::sim
