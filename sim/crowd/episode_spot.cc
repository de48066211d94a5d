#include "sim/crowd/episode_spot.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pavilion::sim::crowd {
namespace {

// A standing place keeps this much room beyond a person's body to every
// robot's hull, m (chosen: a spot a robot stands on is no spot).
constexpr double kRobotClearanceM = 0.1;
// A straight walk is sampled at this fraction of a grid cell.
constexpr double kWalkSampleCells = 0.25;
constexpr double kPi = std::numbers::pi;
// Gaps beyond the robot's reach (its footprint's circumradius) and the
// person's radius at which a curious visitor stands, crowders form their U
// and a follower walks; how far ahead a blocker steps into the path, m
// (chosen: docs/crowd.md).
constexpr double kCuriousGapM = 0.5;
constexpr double kCrowdGapM = 0.5;
constexpr double kFollowGapM = 0.8;
constexpr double kBlockAheadM = 1.5;
// A place that is no floor to stand on (a wall, an exhibit, behind one) moves
// round the robot by this step, at most this many steps either side (chosen:
// a curious visitor stays within 90 deg of the robot's front, a crowder near
// its slot, a follower behind, a blocker within 30 deg of the path).
constexpr double kSpotStepRad = 15.0 * kPi / 180.0;
constexpr int kCuriousSteps = 6;
constexpr int kCrowdSteps = 3;
constexpr int kFollowSteps = 4;
constexpr int kBlockSteps = 2;

}  // namespace

bool CanStand(const StandingFloor& floor, const Eigen::Vector2d& p_m, double radius_m) {
  if (!floor.grid->IsFree(p_m)) return false;
  if (floor.connected && !floor.connected->Reachable(p_m)) return false;
  for (const RobotObstacle& r : floor.robots) {
    if (r.hull_m.size() < 3) continue;
    Eigen::Vector2d n, c;
    if (SignedDistanceToConvex(r.hull_m, p_m, &n, &c) < radius_m + kRobotClearanceM) return false;
  }
  return true;
}

bool ClearWalk(const WalkableGrid& grid, const Eigen::Vector2d& from_m,
               const Eigen::Vector2d& to_m) {
  const std::optional<FloorCell> start = grid.CellAt(from_m);
  const double length = (to_m - from_m).norm();
  const int samples =
      std::max(1, static_cast<int>(std::ceil(length / (kWalkSampleCells * grid.cell_m()))));
  for (int k = 1; k <= samples; ++k) {
    const Eigen::Vector2d p = from_m + (to_m - from_m) * (static_cast<double>(k) / samples);
    const std::optional<FloorCell> cell = grid.CellAt(p);
    if (!cell) return false;
    if (start && *cell == *start) continue;
    if (grid.kind(*cell) == CellKind::kObstacle) return false;
  }
  return true;
}

std::optional<Eigen::Vector2d> SpotAround(const StandingFloor& floor,
                                          const Eigen::Vector2d& center_m, double distance_m,
                                          double angle_rad, double step_rad, int max_steps,
                                          const Eigen::Vector2d& from_m, double radius_m) {
  for (int k = 0; k <= 2 * max_steps; ++k) {
    // 0, +1, -1, +2, -2, ... steps.
    const int steps = (k + 1) / 2 * (k % 2 == 1 ? 1 : -1);
    const double a = angle_rad + steps * step_rad;
    const Eigen::Vector2d p = center_m + distance_m * Eigen::Vector2d(std::cos(a), std::sin(a));
    if (CanStand(floor, p, radius_m) && ClearWalk(*floor.grid, from_m, p)) return p;
  }
  return std::nullopt;
}

Eigen::Vector2d EpisodePlace(const StandingFloor& floor, Behaviour behaviour,
                             const core::Pose2& robot_pose, double reach_m, double slot_rad,
                             const Eigen::Vector2d& fixed_m, const Eigen::Vector2d& person_m,
                             double radius_m) {
  const Eigen::Vector2d c = robot_pose.translation();
  const double th = robot_pose.theta_rad;
  std::optional<Eigen::Vector2d> spot;
  switch (behaviour) {
    case Behaviour::kCurious:
      spot = SpotAround(floor, c, reach_m + radius_m + kCuriousGapM, th, kSpotStepRad,
                        kCuriousSteps, person_m, radius_m);
      break;
    case Behaviour::kCrowding:
      spot = SpotAround(floor, c, reach_m + radius_m + kCrowdGapM, th + slot_rad, kSpotStepRad,
                        kCrowdSteps, person_m, radius_m);
      break;
    case Behaviour::kFollowing:
      spot = SpotAround(floor, c, reach_m + radius_m + kFollowGapM, th + kPi, kSpotStepRad,
                        kFollowSteps, person_m, radius_m);
      break;
    case Behaviour::kBlocking:
      if (CanStand(floor, fixed_m, radius_m)) spot = fixed_m;
      break;
    case Behaviour::kPushing:
    case Behaviour::kOrdinary:
      break;
  }
  return spot.value_or(person_m);
}

Eigen::Vector2d BlockingPlace(const StandingFloor& floor, const Eigen::Vector2d& robot_m,
                              double reach_m, const Eigen::Vector2d& ahead,
                              const Eigen::Vector2d& person_m, double radius_m) {
  return SpotAround(floor, robot_m, reach_m + kBlockAheadM, std::atan2(ahead.y(), ahead.x()),
                    kSpotStepRad, kBlockSteps, person_m, radius_m)
      .value_or(person_m);
}

}  // namespace pavilion::sim::crowd
