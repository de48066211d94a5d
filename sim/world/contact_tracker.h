#pragma once

#include <Eigen/Core>
#include <map>
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

// Which pairs of elements are in contact, from the contact manifolds of a
// physics world after each step (element indices are the collision objects'
// user indices; the floor, element 0, is not tracked): an episode begins when
// a pair's manifold holds a point within kContactDistanceM, its touch is the
// first step with a point at or below zero distance or a normal impulse, and
// it ends when no point is within kContactDistanceM.
class ContactTracker {
 public:
  // Appends the changes since the last call to `changes`: ends sorted by
  // element pair, then begins and touches sorted by pair, a pair's begin
  // before its touch (a deterministic order).
  void Update(btCollisionDispatcher& dispatcher, std::vector<ContactChange>* changes);

 private:
  struct Episode {
    bool touched = false;
    double min_distance_m = 0.0;
  };
  std::map<std::pair<int, int>, Episode> episodes_;
};

// The points (x and y in the frame of `frame_from_world`) where `object`
// touches anything but the floor now: what tactile bumpers feel.
std::vector<Eigen::Vector2d> TouchPoints(const btCollisionDispatcher& dispatcher,
                                         const btCollisionObject* object,
                                         const btTransform& frame_from_world);

}  // namespace pavilion::sim
