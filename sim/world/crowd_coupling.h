#pragma once

#include <Eigen/Core>
#include <map>
#include <memory>
#include <set>
#include <utility>
#include <vector>

#include "core/geometry/planar_section.h"
#include "sim/crowd/crowd.h"
#include "sim/world/world.h"

namespace pavilion::sim {

// The world's side of a crowd (private to sim/world): the walls people avoid,
// what lasers see of people, and the contacts people make with robots.
// People are not Bullet bodies (a hundred free Bullet walkers run at 14x real
// time alone); the crowd model moves them and the world applies their bounded
// contact forces to the robots' bodies.
class CrowdCoupling {
 public:
  CrowdCoupling(std::unique_ptr<crowd::Crowd> crowd, std::vector<int> person_elements);

  // The obstacles people walk around: every static element (glass included:
  // people see it) cut near the floor, where low furniture and plinths stand,
  // and, for elements that do not reach down there, at body height.
  static void CollectWalls(const core::PlanarSection& low, const core::PlanarSection& body,
                           std::vector<crowd::WallSegment>* walls,
                           std::vector<crowd::WallCircle>* pillars);
  // Heights (m) of the two cuts above.
  static constexpr double kLowCutM = 0.2;
  static constexpr double kBodyCutM = 1.0;

  crowd::Crowd& crowd() { return *crowd_; }
  const crowd::Crowd& crowd() const { return *crowd_; }
  int person_element(int person) const { return person_elements_.at(person); }

  // People cut at height z: two leg circles below the hip, the torso (an
  // ellipse as an octagon, oriented by the heading) up to the head.
  void AppendSection(double z_m, core::PlanarSection* out) const;
  // The first person a ray from `from_m` to `to_m` meets (legs and torso as
  // upright prisms cut at the ray's mid height: lasers cast near-horizontal
  // rays), if closer than `best->distance_m` or when best has no hit.
  void CastRay(const Eigen::Vector3d& from_m, const Eigen::Vector3d& to_m, RayHit* best) const;

  // Reports contact begins (each with its touch: people touch by pressing)
  // and ends between people and robots, given the contacts of this step keyed
  // by their (a, b) element pair, a < b.
  void UpdateContacts(const std::map<std::pair<int, int>, ContactChange>& touching,
                      std::vector<ContactChange>* out);

 private:
  std::unique_ptr<crowd::Crowd> crowd_;
  std::vector<int> person_elements_;
  std::set<std::pair<int, int>> touching_;
};

}  // namespace pavilion::sim
