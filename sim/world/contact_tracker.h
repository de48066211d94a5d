#pragma once

#include <Eigen/Core>
#include <set>
#include <utility>
#include <vector>

#include "sim/world/world.h"

// Bullet types are only declared here (the layer lint keeps Bullet includes out
// of every sim/ header).
class btCollisionDispatcher;
class btCollisionObject;
class btTransform;

namespace pavilion::sim {

// Contact points closer than this count as touching (m).
inline constexpr double kContactDistanceM = 0.005;

// Which pairs of elements touch, from the contact manifolds of a physics world
// after each step (element indices are the collision objects' user indices;
// the floor, element 0, is not tracked).
class ContactTracker {
 public:
  // Appends the changes since the last call to `changes`: ends, then begins,
  // each sorted by element pair (a deterministic order).
  void Update(btCollisionDispatcher& dispatcher, std::vector<ContactChange>* changes);

 private:
  std::set<std::pair<int, int>> touching_;
};

// The points (x and y in the frame of `frame_from_world`) where `object`
// touches anything but the floor now: what tactile bumpers feel.
std::vector<Eigen::Vector2d> TouchPoints(const btCollisionDispatcher& dispatcher,
                                         const btCollisionObject* object,
                                         const btTransform& frame_from_world);

}  // namespace pavilion::sim
