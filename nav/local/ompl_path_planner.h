#pragma once

// OMPL initial paths for the elastic band (thesis §6.3.4 initialises with NF1;
// these are the selectable alternatives): RRT-Connect, and RRT* as the
// asymptotically optimizing planner. RRT* is chosen because it runs in the
// calling thread with exactly two random sources (its goal-bias RNG and the
// state sampler), both of which can be seeded here, and it keeps improving the
// path with more iterations; PRM* grows its roadmap in a second thread and
// BIT*/informed variants draw from further samplers.
//
// The planning space is the 2-D position over the grid's bounds (no heading:
// the robot is a circle here). A state is valid when LocalGrid::Free holds for
// its cell; a motion is valid when every cell the segment touches is free.
//
// Determinism: OMPL 1.5 seeds each ompl::RNG from one process-wide generator
// in creation order, so results would depend on what else (which thread)
// created RNGs before. Every RNG the planners draw from is reseeded from
// Plan()'s `seed`: the state sampler (a sampler allocator whose sampler calls
// setLocalSeed) and the planner's own rng_ (RRT*'s goal bias; RRT-Connect's
// is seeded though its 1.5 solve() does not draw from it). Nearest neighbours
// use OMPL's linear structure (GNAT's k-centers draw from an RNG). Planning
// stops after an iteration count, never a wall-clock time, and the path is
// shortcut by a deterministic greedy line-of-sight pass (OMPL's PathSimplifier
// draws random states). The same (grid, start, goal, seed) gives the same path
// bytes in any thread and any creation order.

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "nav/local/initial_path_planner.h"
#include "nav/local/local_grid.h"

namespace pavilion::nav {

enum class OmplPlannerType {
  kRrtConnect,  // bidirectional RRT (Kuffner & LaValle 2000): first solution
  kRrtStar,     // RRT* (Karaman & Frazzoli 2011): improves until max_iterations
};

struct OmplPlannerOptions {
  OmplPlannerType type = OmplPlannerType::kRrtConnect;
  // Planner loop iterations (termination-condition evaluations), [1, 1e6].
  // RRT-Connect stops at its first solution; RRT* uses them all.
  int max_iterations = 2000;
  // Longest tree extension per iteration, m, (0, 40].
  double range_m = 1.0;
  // RRT*: probability of sampling the goal, [0, 1). Not used by RRT-Connect.
  double goal_bias = 0.05;
  // Shorten the raw tree path by greedy line-of-sight shortcuts.
  bool shortcut = true;

  void Validate() const;  // throws std::invalid_argument naming the field
};

class OmplPathPlanner : public InitialPathPlanner {
 public:
  explicit OmplPathPlanner(const OmplPlannerOptions& options = {});

  // A path from `start` to `goal` (both exact, world frame) whose segments
  // touch free cells only, or none when start or goal is not free or the
  // planner finds no exact solution within max_iterations.
  std::optional<std::vector<Eigen::Vector2d>> Plan(const LocalGrid& grid,
                                                   const Eigen::Vector2d& start,
                                                   const Eigen::Vector2d& goal,
                                                   std::uint64_t seed) override;
  // "ompl_rrt_connect" or "ompl_rrt_star".
  std::string name() const override;
  const OmplPlannerOptions& options() const { return options_; }

 private:
  OmplPlannerOptions options_;
};

// True when every grid cell the closed segment a-b touches is free
// (LocalGrid::Free); a segment through a cell corner must clear all cells
// sharing that corner. Exact cell traversal (Amanatides & Woo 1987).
bool SegmentFreeOnGrid(const LocalGrid& grid, const Eigen::Vector2d& a, const Eigen::Vector2d& b);

// Greedy shortcut: from each kept point, jump to the farthest later point in
// free line of sight (SegmentFreeOnGrid). Keeps the ends; deterministic.
std::vector<Eigen::Vector2d> ShortcutPath(const LocalGrid& grid,
                                          const std::vector<Eigen::Vector2d>& path);

}  // namespace pavilion::nav
