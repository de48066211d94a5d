#pragma once

#include <memory>
#include <vector>

#include "core/geometry/planar_section.h"
#include "sim/world/world_description.h"

// Bullet types are only declared here (the layer lint keeps Bullet includes out
// of every sim/ header); the units that use them include Bullet themselves.
class btCollisionDispatcher;
class btCollisionShape;
class btDbvtBroadphase;
class btDiscreteDynamicsWorld;
class btMotionState;
class btRigidBody;
class btTransform;
class btTriangleMesh;
class btTypedConstraint;
class btVector3;

namespace pavilion::sim {

struct WorldOptions;

// The Bullet dynamics world of a sim::World and the owner of everything added
// to it (shapes, meshes, motion states, rigid bodies, constraints), released
// in reverse on destruction. Pairs of parts of the same robot (one element
// group) never collide. Internal to the world's implementation.
class PhysicsWorld {
 public:
  // `elements` (the world's element table, by element index) outlives this;
  // rigid bodies carry their element index as user index.
  PhysicsWorld(const WorldOptions& options, const std::vector<core::SectionElement>* elements);
  ~PhysicsWorld();
  PhysicsWorld(const PhysicsWorld&) = delete;
  PhysicsWorld& operator=(const PhysicsWorld&) = delete;

  btDiscreteDynamicsWorld& dynamics();
  const btDiscreteDynamicsWorld& dynamics() const;
  btCollisionDispatcher& dispatcher();
  const btCollisionDispatcher& dispatcher() const;
  btDbvtBroadphase& broadphase();
  const btDbvtBroadphase& broadphase() const;

  // What a body may touch. A robot's drive wheel is a sphere standing in for
  // a thin tyre inside the chassis: only its rolling contact with the floor is
  // real, and its bulk (up to a radius beside the axle) must touch nothing else.
  enum class Touches { kAll, kFloorOnly };

  // A static rigid body of `material` at `transform`; `floor` marks the ground
  // the drive wheels roll on.
  btRigidBody* AddStatic(std::unique_ptr<btCollisionShape> shape, const btTransform& transform,
                         const Material& material, int element, bool floor = false);
  // A dynamic rigid body, never deactivated. Its inertia is the shape's unless
  // given (principal moments about the body axes).
  btRigidBody* AddDynamic(std::unique_ptr<btCollisionShape> shape, double mass_kg,
                          const btTransform& transform, double friction, double restitution,
                          int element, const btVector3* given_inertia = nullptr,
                          Touches touches = Touches::kAll);
  // Adds a rigid body built by the caller and keeps its parts.
  btRigidBody* AddRigidBody(std::unique_ptr<btCollisionShape> shape,
                            std::unique_ptr<btMotionState> motion,
                            std::unique_ptr<btRigidBody> rigid, Touches touches = Touches::kAll);
  void AddConstraint(std::unique_ptr<btTypedConstraint> constraint,
                     bool disable_collisions_between_linked_bodies);
  // Keeps a shape that lives as long as the world (a child of a compound).
  void KeepShape(std::unique_ptr<btCollisionShape> shape);
  // Keeps a triangle mesh that a mesh shape points to.
  void KeepMesh(std::unique_ptr<btTriangleMesh> mesh);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pavilion::sim
