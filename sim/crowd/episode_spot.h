#pragma once

#include <Eigen/Core>
#include <optional>
#include <span>

#include "core/types/pose2.h"
#include "sim/crowd/crowd.h"
#include "sim/crowd/floor_field.h"
#include "sim/crowd/social_force.h"

namespace pavilion::sim::crowd {

// Where a visitor of a §6.5 episode may stand near a robot: on the floor the
// crowd walks (a free cell of the walkable grid, so at least the routes'
// clearance from walls and exhibits), in the part of it from which `connected`
// (the exit's field) can be reached, clear of every robot, and reached from
// where the visitor is by a straight walk that crosses no wall or exhibit
// (visitors walk to an episode's place in a straight line; the robots they
// walk around). Without this the places, drawn around the robot, lay in walls
// or behind them, and visitors pressed into the robot for a whole episode
// trying to reach them (docs/crowd.md, "Visits and behaviours").
struct StandingFloor {
  const WalkableGrid* grid = nullptr;
  const DistanceField* connected = nullptr;
  std::span<const RobotObstacle> robots;
};

// True when a person of radius_m may stand at p_m: a free, connected cell with
// every robot's hull at least radius_m plus a small gap away.
bool CanStand(const StandingFloor& floor, const Eigen::Vector2d& p_m, double radius_m);

// True when the straight walk from from_m to to_m crosses no cell an obstacle
// touches (the cell the walk starts in excepted: a person may stand close to a wall).
bool ClearWalk(const WalkableGrid& grid, const Eigen::Vector2d& from_m,
               const Eigen::Vector2d& to_m);

// A place distance_m from center_m in the direction angle_rad, or, when a
// person of radius_m cannot stand there or walk there straight from from_m,
// the first of the directions angle_rad + step_rad, angle_rad - step_rad,
// angle_rad + 2 step_rad, ... up to max_steps steps either side that it can.
// None when none can: the visitor then waits where it is.
std::optional<Eigen::Vector2d> SpotAround(const StandingFloor& floor,
                                          const Eigen::Vector2d& center_m, double distance_m,
                                          double angle_rad, double step_rad, int max_steps,
                                          const Eigen::Vector2d& from_m, double radius_m);

// Where a visitor of radius_m at person_m stands in an episode (thesis §6.5)
// near a robot at robot_pose whose footprint reaches reach_m from its origin:
// at a standing gap beyond that reach, so that the visitor's body stays
// 0.5-0.8 m from the robot's hull and never leans on it (the robot's
// repulsion holds it a little farther: docs/crowd.md). Curious: in front of
// the robot; crowding: at slot_rad from its front, in a U; following: behind
// it; blocking: at fixed_m (BlockingPlace), while a person can stand there. A
// place no one can stand on or walk to moves round the robot (SpotAround);
// with none, the visitor's own position (it waits). Not for pushers.
Eigen::Vector2d EpisodePlace(const StandingFloor& floor, Behaviour behaviour,
                             const core::Pose2& robot_pose, double reach_m, double slot_rad,
                             const Eigen::Vector2d& fixed_m, const Eigen::Vector2d& person_m,
                             double radius_m);

// A blocker's place: on the robot's path (`ahead`, unit) 1.5 m beyond its
// reach, or up to 30 deg beside it; the visitor's own position when none.
Eigen::Vector2d BlockingPlace(const StandingFloor& floor, const Eigen::Vector2d& robot_m,
                              double reach_m, const Eigen::Vector2d& ahead,
                              const Eigen::Vector2d& person_m, double radius_m);

}  // namespace pavilion::sim::crowd
