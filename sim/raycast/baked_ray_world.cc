#include "sim/raycast/baked_ray_world.h"

#include <BulletCollision/NarrowPhaseCollision/btRaycastCallback.h>
#include <btBulletDynamicsCommon.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <optional>
#include <utility>

#include "sim/raycast/ray_shapes.h"
#include "sim/world/bullet_conversions.h"
#include "sim/world/triangle_mesh.h"
#include "sim/world/wall_geometry.h"

namespace pavilion::sim {
namespace {

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
             const std::vector<core::SectionElement>& elements, const PrismRegistry& prisms,
             int ignore)
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
      // A child whose shape carries an element as its user index is that
      // element (a robot's marker); the others are the object's.
      for (int k = 0; k < compound->getNumChildShapes(); ++k) {
        const btCollisionShape* child = compound->getChildShape(k);
        const int child_element = child->getUserIndex() >= 0 ? child->getUserIndex() : element;
        Test(object, child, t * compound->getChildTransform(k), child_element);
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
  const PrismRegistry& prisms_;
  int ignore_;
  double fraction_ = 1.0;
  btVector3 normal_{0, 0, 0};
  int element_ = -1;
};

// A hit at `p` of the ray from `from_m` to `to_m`, its normal facing the ray.
RayHit MakeHit(const Eigen::Vector3d& from_m, const Eigen::Vector3d& to_m, const btVector3& p,
               const btVector3& normal, int element) {
  RayHit hit;
  hit.hit = true;
  hit.point_m = {p.x(), p.y(), p.z()};
  hit.distance_m = (hit.point_m - from_m).norm();
  Eigen::Vector3d n(normal.x(), normal.y(), normal.z());
  if (n.dot(to_m - from_m) > 0) n = -n;
  hit.normal = n.normalized();
  hit.element = element;
  return hit;
}

// btDbvtBroadphase::rayTest walks the broadphase's two trees with one stack
// of the broadphase's own (m_rayTestStacks[0]: Bullet built without
// BT_THREADSAFE), so two rays cast at once would share it. This is the same
// walk — the same trees in the same order with the same ray data, hence the
// same candidates in the same order — with a stack per thread, so that the
// robots' scans may fall back to this path from several threads at once.
void BroadphaseRayTest(const btDbvtBroadphase& broadphase, const btVector3& from,
                       const btVector3& to, btBroadphaseRayCallback& callback) {
  struct Tester : btDbvt::ICollide {
    explicit Tester(btBroadphaseRayCallback& c) : callback(c) {}
    void Process(const btDbvtNode* leaf) override {
      callback.process(static_cast<btBroadphaseProxy*>(leaf->data));
    }
    btBroadphaseRayCallback& callback;
  };
  thread_local btAlignedObjectArray<const btDbvtNode*> stack;
  Tester tester(callback);
  const btVector3 no_aabb(0, 0, 0);  // rayTest's defaults: a ray, not a box cast
  for (const btDbvt& set : broadphase.m_sets) {
    set.rayTestInternal(set.m_root, from, to, callback.m_rayDirectionInverse, callback.m_signs,
                        callback.m_lambda_max, no_aabb, no_aabb, stack, tester);
  }
}

}  // namespace

struct BakedRayWorld::Impl {
  std::unique_ptr<btTriangleMesh> ray_mesh;
  std::unique_ptr<btBvhTriangleMeshShape> ray_mesh_shape;
  std::vector<int> ray_triangle_element;  // element of each baked triangle
  // 1 for faces of closed prisms (outward normals: a ray from inside meets
  // only back faces and passes, as for convex shapes); 0 for mesh triangles.
  std::vector<char> ray_triangle_closed;
  std::vector<std::unique_ptr<btCollisionShape>> shapes;  // of the ray objects
  std::vector<std::unique_ptr<btCollisionObject>> ray_objects;
  std::vector<btCollisionObject*> ray_doors;  // parallel to description.doors; null if unseen

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

  void BakeMesh(const Mesh& m, int element) {
    const auto source = LoadTriangleMesh(m.file);
    const std::vector<Eigen::Vector3d> v = PlacedVertices(m);
    for (const auto& tri : source->triangles) {
      ray_mesh->addTriangle(ToBt(v[tri[0]]), ToBt(v[tri[1]]), ToBt(v[tri[2]]));
      ray_triangle_element.push_back(element);
      ray_triangle_closed.push_back(0);
    }
  }

  void AddCylinder(const Cylinder& c, int element) {
    btTransform t;
    t.setIdentity();
    t.setOrigin(btVector3(c.position_m.x(), c.position_m.y(), c.base_z_m + 0.5 * c.height_m));
    AddRayObject(
        std::make_unique<btCylinderShapeZ>(btVector3(c.radius_m, c.radius_m, 0.5 * c.height_m)), t,
        element);
  }
};

BakedRayWorld::BakedRayWorld(const WorldDescription& description, const ElementTable& elements)
    : impl_(std::make_unique<Impl>()) {
  Impl& im = *impl_;
  im.ray_mesh = std::make_unique<btTriangleMesh>();
  int element = 1;  // the floor (0) is never in a horizontal beam's way
  for (const Wall& wall : description.walls) {
    if (elements.LaserVisible(element)) {
      for (const Quad& q : WallFootprint(wall)) {
        im.BakePrism(q, wall.base_z_m, wall.base_z_m + wall.height_m, element);
      }
    }
    ++element;
  }
  for (const Box& box : description.boxes) {
    if (elements.LaserVisible(element)) {
      im.BakePrism(BoxFootprint(box), box.base_z_m, box.base_z_m + box.size_m.z(), element);
    }
    ++element;
  }
  for (const Cylinder& c : description.cylinders) {
    if (elements.LaserVisible(element)) im.AddCylinder(c, element);
    ++element;
  }
  for (const Mesh& m : description.meshes) {
    if (elements.LaserVisible(element)) im.BakeMesh(m, element);
    ++element;
  }
  for (const Door& door : description.doors) {
    if (elements.LaserVisible(element)) {
      const Box box = door.AsBox();
      im.AddRayObject(MakeBox(0.5 * box.size_m), BoxTransform(box), element);
      im.ray_doors.push_back(im.ray_objects.back().get());
    } else {
      im.ray_doors.push_back(nullptr);
    }
    ++element;
  }
  if (!im.ray_triangle_element.empty()) {
    im.ray_mesh_shape = std::make_unique<btBvhTriangleMeshShape>(im.ray_mesh.get(), true);
  }
}

BakedRayWorld::~BakedRayWorld() = default;

void BakedRayWorld::MoveDoor(int door, const Box& box) {
  if (door < static_cast<int>(impl_->ray_doors.size()) && impl_->ray_doors[door] != nullptr) {
    impl_->ray_doors[door]->setWorldTransform(BoxTransform(box));
  }
}

RayHit BakedRayWorld::Cast(const Eigen::Vector3d& from_m, const Eigen::Vector3d& to_m,
                           int ignore_group, const std::vector<core::SectionElement>& elements,
                           const PrismRegistry& prisms, const btDbvtBroadphase& broadphase) const {
  const Impl& im = *impl_;
  const btVector3 from = ToBt(from_m), to = ToBt(to_m);
  MeshRay mesh(from, to, im.ray_triangle_closed);
  if (im.ray_mesh_shape) im.ray_mesh_shape->performRaycast(&mesh, from, to);
  const btVector3 mesh_end = mesh.hit() ? from.lerp(to, mesh.m_hitFraction) : to;
  DynamicRay statics(from, mesh_end, elements, prisms, -1);
  for (const auto& object : im.ray_objects) statics.TestObject(object.get());
  const btVector3 end = statics.hit() ? from.lerp(mesh_end, statics.fraction()) : mesh_end;
  DynamicRay dynamic(from, end, elements, prisms, ignore_group);
  if (end != from) {
    BroadphaseRayTest(broadphase, from, end, dynamic);
  }
  if (dynamic.hit()) {
    return MakeHit(from_m, to_m, from.lerp(end, dynamic.fraction()), dynamic.normal(),
                   dynamic.element());
  }
  if (statics.hit()) return MakeHit(from_m, to_m, end, statics.normal(), statics.element());
  if (mesh.hit()) {
    return MakeHit(from_m, to_m, mesh_end, mesh.normal(), im.ray_triangle_element[mesh.triangle()]);
  }
  return RayHit{};
}

}  // namespace pavilion::sim
