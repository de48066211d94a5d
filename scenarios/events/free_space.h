#pragma once

// Free space for a robot placed by hand (a kidnap, a teleport): its footprint
// circle inside the floor and clear of every element of the world's planar
// sections at the chassis' heights, bodies included. 2D checks against
// sim::World::SectionAt; no physics query.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/geometry/planar_section.h"
#include "core/types/pose2.h"
#include "sim/world/world_description.h"

namespace pavilion::scenarios {

// DiscObstacle::what for a disc that leaves the floor.
inline constexpr const char* kFloorEdge = "the floor's edge";

// What a disc of the plane runs into.
struct DiscObstacle {
  bool free = true;
  std::string what;  // the element's id, or kFloorEdge
};

// A disc of `radius_m` at `center_m` against the sections: free when it lies
// inside the floor and no segment or circle of an element outside
// `ignore_group` comes closer than `radius_m`, nor does a closed outline of
// one (counter-clockwise, planar_section.h) contain its centre.
DiscObstacle CheckDisc(const std::vector<core::PlanarSection>& sections, const sim::Floor& floor,
                       const Eigen::Vector2d& center_m, double radius_m, int ignore_group = -1);

// The cells of a grid over the floor whose centre a disc of `radius_m` can
// reach from `from_m` through free space (CheckDisc, 4-connected): the
// building the robot is in, not the floor outside its walls.
class ReachableCells {
 public:
  ReachableCells(const std::vector<core::PlanarSection>& sections, const sim::Floor& floor,
                 double radius_m, double cell_m, const Eigen::Vector2d& from_m, int ignore_group);
  // Whether the cell of `p_m` was reached (false outside the floor).
  bool Contains(const Eigen::Vector2d& p_m) const;
  int reached() const { return reached_; }

 private:
  int CellOf(const Eigen::Vector2d& p_m) const;  // -1 outside

  Eigen::Vector2d origin_m_;
  double cell_m_;
  int columns_ = 0;
  int rows_ = 0;
  std::vector<char> reached_cells_;
  int reached_ = 0;
};

// Whether `p_m` is enclosed by the section's static geometry: of kEnclosedRays
// rays from it in evenly spread directions, at most kOpenRaysAllowed leave the
// floor without meeting a segment or circle (an entrance in view). The floor
// outside a building's walls is not (issue 18: kidnaps "into free space").
bool Enclosed(const core::PlanarSection& section, const sim::Floor& floor,
              const Eigen::Vector2d& p_m);

// Whether a robot at `pose`, driving on its wheels forwards or backwards
// (straight, or turning up to 15 deg off), meets the section's static
// geometry before it leaves the floor. A kidnapped robot's wheels keep
// turning at its last command: set down facing an entrance, it drove out of
// the hall and off the floor (expo_day seed 1, 35,419 s; issue 21).
bool WheelsRunInside(const core::PlanarSection& section, const sim::Floor& floor,
                     const core::Pose2& pose);

// The heights (m) at which a chassis spanning [bottom_m, top_m] is checked:
// near its underside, its middle and near its top.
std::vector<double> ChassisCheckHeights(double bottom_m, double top_m);

}  // namespace pavilion::scenarios
