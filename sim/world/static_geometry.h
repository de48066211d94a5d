#pragma once

#include <vector>

#include "sim/world/element_table.h"
#include "sim/world/physics_world.h"
#include "sim/world/world_description.h"

namespace pavilion::sim {

// Adds the floor and the static elements of `description` (walls, boxes,
// cylinders, meshes, doors) to `physics` as static rigid bodies, appending
// their elements to `elements` in that order (sim::World's element indices).
// Returns the door bodies, parallel to description.doors. Throws
// std::runtime_error for an unreadable mesh file, std::out_of_range for an
// unknown material.
std::vector<btRigidBody*> AddStaticGeometry(const WorldDescription& description,
                                            ElementTable* elements, PhysicsWorld* physics);

}  // namespace pavilion::sim
