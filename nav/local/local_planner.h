#pragma once

// The path-planning sublayer (thesis §6.3.4): on a local grid from the current
// obstacle points, an initial path (NF1 by default, or an OMPL planner) that an
// elastic band then keeps smooth and clear, updated at several Hz; when the
// band snaps the caller plans again. The robot is a circle here; the dynamic
// window below accounts for its true shape.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "nav/local/distance_field.h"
#include "nav/local/elastic_band.h"
#include "nav/local/initial_path_planner.h"
#include "nav/local/local_grid.h"

namespace pavilion::nav {

struct LocalPlannerOptions {
  LocalGridOptions grid;
  ElasticBandOptions band;
  // When the band ends short of the goal (the goal is off the grid or not
  // free), plan again once the robot is this close to the band's end, m, (0, 20].
  double extend_within_m = 1.5;

  void Validate() const;  // throws std::invalid_argument naming the field
};

class LocalPlanner {
 public:
  LocalPlanner(const LocalPlannerOptions& options, std::unique_ptr<InitialPathPlanner> initial);

  // A new band from `robot` towards `goal` (world frame) on a grid built from
  // `obstacles_in_world`; false when the initial planner finds no path (the
  // band is then dropped).
  bool Plan(const Eigen::Vector2d& robot, const Eigen::Vector2d& goal,
            std::span<const Eigen::Vector2d> obstacles_in_world, std::uint64_t seed);

  enum class Status { kOk, kSnapped, kExtend, kNoBand };
  // One band update from fresh obstacle points: kSnapped (plan again: a
  // replan), kExtend (the band's end is near and short of the goal: plan on).
  Status Update(const Eigen::Vector2d& robot, std::span<const Eigen::Vector2d> obstacles_in_world);

  bool has_band() const { return has_band_; }
  const ElasticBand& band() const { return band_; }
  const Eigen::Vector2d& goal() const { return goal_; }
  // The point `distance_m` along the band from the robot (the band's end
  // beyond it); requires has_band().
  Eigen::Vector2d TargetAhead(double distance_m) const { return band_.TargetAhead(distance_m); }
  const LocalGrid& grid() const { return grid_; }
  const InitialPathPlanner& initial_planner() const { return *initial_; }

 private:
  LocalPlannerOptions options_;
  std::unique_ptr<InitialPathPlanner> initial_;
  LocalGrid grid_;
  DistanceField field_;
  ElasticBand band_;
  Eigen::Vector2d goal_ = Eigen::Vector2d::Zero();
  bool has_band_ = false;
  bool band_reaches_goal_ = false;
};

}  // namespace pavilion::nav
