#include "nav/local/local_planner.h"

#include <stdexcept>
#include <string>
#include <utility>

#include "nav/local/nf1.h"

namespace pavilion::nav {
namespace {

// The goal counts as reached by the band when its end is this close (m).
constexpr double kBandAtGoalM = 0.05;

}  // namespace

void LocalPlannerOptions::Validate() const {
  grid.Validate();
  band.Validate();
  if (!(extend_within_m > 0.0 && extend_within_m <= 20.0)) {
    throw std::invalid_argument("LocalPlannerOptions.extend_within_m must be in (0, 20] m");
  }
  if (band.robot_radius_m != grid.robot_radius_m) {
    throw std::invalid_argument(
        "LocalPlannerOptions.band.robot_radius_m must equal grid.robot_radius_m");
  }
}

LocalPlanner::LocalPlanner(const LocalPlannerOptions& options,
                           std::unique_ptr<InitialPathPlanner> initial)
    : options_(options), initial_(std::move(initial)), grid_(options.grid), band_(options.band) {
  options_.Validate();
}

bool LocalPlanner::Plan(const Eigen::Vector2d& robot, const Eigen::Vector2d& goal,
                        std::span<const Eigen::Vector2d> obstacles_in_world, std::uint64_t seed) {
  goal_ = goal;
  grid_.Build(robot, obstacles_in_world);
  // The goal may be off the grid or behind an obstacle: plan to the reachable
  // free cell nearest to it (the band's end then moves on as the robot does).
  const std::optional<Eigen::Vector2d> local_goal = Nf1Planner::LocalGoal(grid_, robot, goal);
  std::optional<std::vector<Eigen::Vector2d>> path;
  if (local_goal) path = initial_->Plan(grid_, robot, *local_goal, seed);
  has_band_ = path.has_value() && path->size() >= 2;
  if (!has_band_) return false;
  band_reaches_goal_ = (path->back() - goal).norm() <= kBandAtGoalM;
  band_.Reset(std::move(*path));
  field_.Build(grid_);
  has_band_ = band_.Update(robot, field_);
  return has_band_;
}

LocalPlanner::Status LocalPlanner::Update(const Eigen::Vector2d& robot,
                                          std::span<const Eigen::Vector2d> obstacles_in_world) {
  if (!has_band_) return Status::kNoBand;
  grid_.Build(robot, obstacles_in_world);
  field_.Build(grid_);
  if (!band_.Update(robot, field_)) {
    has_band_ = false;
    return Status::kSnapped;
  }
  if (!band_reaches_goal_ && !band_.bubbles().empty() &&
      (band_.bubbles().back().center - robot).norm() <= options_.extend_within_m) {
    return Status::kExtend;
  }
  return Status::kOk;
}

}  // namespace pavilion::nav
