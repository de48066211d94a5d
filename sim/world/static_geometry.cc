#include "sim/world/static_geometry.h"

#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "sim/world/bullet_conversions.h"
#include "sim/world/triangle_mesh.h"
#include "sim/world/wall_geometry.h"

namespace pavilion::sim {
namespace {

// Floor slab thickness below z = 0 (m); thick enough that nothing tunnels.
constexpr double kFloorThicknessM = 1.0;
// Collision margin for triangle meshes (m); small so that rays and contacts
// meet the surface the description gives.
constexpr double kMeshMarginM = 0.001;

// The samples of a height field, kept alive before the shape that reads them
// is built (a base class is constructed before the members of the derived one).
struct HeightSamples {
  std::vector<float> heights;
};

// An uneven floor (FloorRelief) as a Bullet height field that owns its samples.
class ReliefShape : private HeightSamples, public btHeightfieldTerrainShape {
 public:
  ReliefShape(std::vector<float> heights, int columns, int rows, float min_m, float max_m)
      : HeightSamples{std::move(heights)},
        btHeightfieldTerrainShape(columns, rows, HeightSamples::heights.data(), min_m, max_m,
                                  /*upAxis=*/2, /*flipQuadEdges=*/false) {}
};

// Adds static bodies of one world description to a physics world.
class StaticBuilder {
 public:
  StaticBuilder(const WorldDescription& description, ElementTable* elements, PhysicsWorld* physics)
      : description_(description), elements_(*elements), physics_(*physics) {}

  void AddFloor() {
    const Floor& floor = description_.floor;
    const int element = elements_.Add("floor", floor.material, false);
    if (!floor.relief.flat()) return AddReliefFloor(element);
    const Eigen::Vector2d half = 0.5 * (floor.max_m - floor.min_m);
    const Eigen::Vector2d centre = 0.5 * (floor.max_m + floor.min_m);
    auto shape =
        std::make_unique<btBoxShape>(btVector3(half.x(), half.y(), 0.5 * kFloorThicknessM));
    btTransform t;
    t.setIdentity();
    t.setOrigin(btVector3(centre.x(), centre.y(), -0.5 * kFloorThicknessM));
    AddStatic(std::move(shape), t, floor.material, element, /*floor=*/true);
  }

  // The relief sampled every kReliefGridSpacingM (or closer, so that the
  // samples meet the floor's edges) as a height field.
  void AddReliefFloor(int element) {
    const Floor& floor = description_.floor;
    const Eigen::Vector2d extent = floor.max_m - floor.min_m;
    const int columns = static_cast<int>(std::ceil(extent.x() / kReliefGridSpacingM)) + 1;
    const int rows = static_cast<int>(std::ceil(extent.y() / kReliefGridSpacingM)) + 1;
    const double dx = extent.x() / (columns - 1);
    const double dy = extent.y() / (rows - 1);
    std::vector<float> heights(static_cast<std::size_t>(columns) * rows);
    for (int j = 0; j < rows; ++j) {
      for (int i = 0; i < columns; ++i) {
        const Eigen::Vector2d p(floor.min_m.x() + i * dx, floor.min_m.y() + j * dy);
        heights[static_cast<std::size_t>(j) * columns + i] =
            static_cast<float>(floor.relief.HeightAt(p));
      }
    }
    const auto [lo, hi] = std::minmax_element(heights.begin(), heights.end());
    const float min_m = *lo, max_m = *hi;
    auto shape = std::make_unique<ReliefShape>(std::move(heights), columns, rows, min_m, max_m);
    shape->setLocalScaling(btVector3(dx, dy, 1.0));
    shape->setMargin(0.0);  // contacts on the surface the ray-cast wheels see
    // Bullet centres a height field on its bounding box.
    const Eigen::Vector2d centre = 0.5 * (floor.max_m + floor.min_m);
    btTransform t;
    t.setIdentity();
    t.setOrigin(btVector3(centre.x(), centre.y(), 0.5 * (min_m + max_m)));
    AddStatic(std::move(shape), t, floor.material, element, /*floor=*/true);
  }

  void AddWall(const Wall& wall) {
    const int element = elements_.Add(wall.id, wall.material, false);
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
      physics_.KeepShape(std::move(hull));
    }
    AddStatic(std::move(compound), identity, wall.material, element);
  }

  btRigidBody* AddBox(const Box& box) {
    const int element = elements_.Add(box.id, box.material, false);
    auto shape = MakeBox(0.5 * box.size_m);
    return AddStatic(std::move(shape), BoxTransform(box), box.material, element);
  }

  void AddCylinder(const Cylinder& c) {
    const int element = elements_.Add(c.id, c.material, false);
    auto shape =
        std::make_unique<btCylinderShapeZ>(btVector3(c.radius_m, c.radius_m, 0.5 * c.height_m));
    btTransform t;
    t.setIdentity();
    t.setOrigin(btVector3(c.position_m.x(), c.position_m.y(), c.base_z_m + 0.5 * c.height_m));
    AddStatic(std::move(shape), t, c.material, element);
  }

  void AddMesh(const Mesh& m) {
    const int element = elements_.Add(m.id, m.material, false);
    const std::vector<Eigen::Vector3d> vertices = PlacedVertices(m);
    const auto source = LoadTriangleMesh(m.file);
    auto mesh = std::make_unique<btTriangleMesh>();
    for (const auto& tri : source->triangles) {
      mesh->addTriangle(ToBt(vertices[tri[0]]), ToBt(vertices[tri[1]]), ToBt(vertices[tri[2]]));
    }
    auto shape = std::make_unique<btBvhTriangleMeshShape>(mesh.get(), true);
    shape->setMargin(kMeshMarginM);
    physics_.KeepMesh(std::move(mesh));
    btTransform identity;
    identity.setIdentity();
    AddStatic(std::move(shape), identity, m.material, element);
  }

 private:
  btRigidBody* AddStatic(std::unique_ptr<btCollisionShape> shape, const btTransform& transform,
                         const std::string& material, int element, bool floor = false) {
    return physics_.AddStatic(std::move(shape), transform, description_.MaterialNamed(material),
                              element, floor);
  }

  const WorldDescription& description_;
  ElementTable& elements_;
  PhysicsWorld& physics_;
};

}  // namespace

std::vector<btRigidBody*> AddStaticGeometry(const WorldDescription& description,
                                            ElementTable* elements, PhysicsWorld* physics) {
  StaticBuilder builder(description, elements, physics);
  builder.AddFloor();
  for (const Wall& wall : description.walls) builder.AddWall(wall);
  for (const Box& box : description.boxes) builder.AddBox(box);
  for (const Cylinder& c : description.cylinders) builder.AddCylinder(c);
  for (const Mesh& m : description.meshes) builder.AddMesh(m);
  std::vector<btRigidBody*> doors;
  for (const Door& door : description.doors) doors.push_back(builder.AddBox(door.AsBox()));
  return doors;
}

}  // namespace pavilion::sim
