#include "nav/local/ompl_path_planner.h"

#include <ompl/base/MotionValidator.h>
#include <ompl/base/PlannerTerminationCondition.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/StateSampler.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/datastructures/NearestNeighborsLinear.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <ompl/util/Console.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "core/random/random_stream.h"

namespace pavilion::nav {
namespace {

namespace ob = ompl::base;
namespace og = ompl::geometric;

constexpr int kDimensions = 2;
constexpr int kMaxIterations = 1000000;
constexpr double kMaxRangeM = 40.0;  // the largest LocalGrid side
// A goal state is reached when a tree state is within this distance (m): only
// the goal itself (RRT* adds it exactly through goal biasing).
constexpr double kGoalThresholdM = 1e-9;
// The last valid point of a blocked motion stops this far (in cells) before
// the first blocked cell, so that it lies in the free one.
constexpr double kBlockedBackoffCells = 1e-6;
// Stream ids of the two RNGs seeded from Plan()'s seed.
constexpr std::uint64_t kSamplerStream = 0x5a3b1e;
constexpr std::uint64_t kPlannerStream = 0x91a7c2;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

std::uint32_t DeriveSeed(std::uint64_t seed, std::uint64_t stream) {
  core::RandomStream derived(seed, stream);
  return static_cast<std::uint32_t>(derived.NextU64() >> 32);
}

Eigen::Vector2d PointOf(const ob::State* state) {
  const double* v = state->as<ob::RealVectorStateSpace::StateType>()->values;
  return {v[0], v[1]};
}

// Parameter t in [0, 1] at which segment a-b first touches a cell that is not
// free, +inf when none does. Amanatides & Woo traversal in cell units; at an
// exact corner crossing the two side cells are tested too.
double FirstBlockedParameter(const LocalGrid& grid, const Eigen::Vector2d& a,
                             const Eigen::Vector2d& b) {
  const Eigen::Vector2d q0 = (a - grid.origin()) / grid.cell_m();
  const Eigen::Vector2d d = (b - grid.origin()) / grid.cell_m() - q0;
  GridCell cell = grid.CellOf(a);
  const GridCell last = grid.CellOf(b);
  if (!grid.Free(cell)) return 0.0;
  int step[kDimensions];
  double t_max[kDimensions];
  double t_delta[kDimensions];
  for (int i = 0; i < kDimensions; ++i) {
    step[i] = d[i] > 0.0 ? 1 : (d[i] < 0.0 ? -1 : 0);
    if (step[i] == 0) {
      t_max[i] = t_delta[i] = kInfinity;
      continue;
    }
    const double boundary = step[i] > 0 ? cell[i] + 1.0 : cell[i];
    t_max[i] = (boundary - q0[i]) / d[i];
    t_delta[i] = step[i] / d[i];
  }
  while (cell != last) {
    const double t = std::min(t_max[0], t_max[1]);
    if (t > 1.0) break;
    if (t_max[0] == t_max[1]) {
      if (!grid.Free(cell + GridCell(step[0], 0)) || !grid.Free(cell + GridCell(0, step[1]))) {
        return t;
      }
      cell += GridCell(step[0], step[1]);
      t_max[0] += t_delta[0];
      t_max[1] += t_delta[1];
    } else {
      const int i = t_max[0] < t_max[1] ? 0 : 1;
      cell[i] += step[i];
      t_max[i] += t_delta[i];
    }
    if (!grid.Free(cell)) return t;
  }
  return grid.Free(last) ? kInfinity : 1.0;
}

// Uniform samples over the grid's bounds from an RNG seeded at construction.
class SeededSampler : public ob::StateSampler {
 public:
  SeededSampler(const ob::StateSpace* space, std::uint32_t seed)
      : ob::StateSampler(space), bounds_(space->as<ob::RealVectorStateSpace>()->getBounds()) {
    rng_.setLocalSeed(seed);
  }
  void sampleUniform(ob::State* state) override {
    double* v = state->as<ob::RealVectorStateSpace::StateType>()->values;
    for (int i = 0; i < kDimensions; ++i) v[i] = rng_.uniformReal(bounds_.low[i], bounds_.high[i]);
  }
  void sampleUniformNear(ob::State* state, const ob::State* near, double distance) override {
    double* v = state->as<ob::RealVectorStateSpace::StateType>()->values;
    const Eigen::Vector2d c = PointOf(near);
    for (int i = 0; i < kDimensions; ++i) {
      v[i] = std::clamp(rng_.uniformReal(c[i] - distance, c[i] + distance), bounds_.low[i],
                        bounds_.high[i]);
    }
  }
  void sampleGaussian(ob::State* state, const ob::State* mean, double std_dev) override {
    double* v = state->as<ob::RealVectorStateSpace::StateType>()->values;
    const Eigen::Vector2d c = PointOf(mean);
    for (int i = 0; i < kDimensions; ++i) {
      v[i] = std::clamp(rng_.gaussian(c[i], std_dev), bounds_.low[i], bounds_.high[i]);
    }
  }

 private:
  ob::RealVectorBounds bounds_;
};

// Motions valid when every cell the segment touches is free.
class GridMotionValidator : public ob::MotionValidator {
 public:
  GridMotionValidator(ob::SpaceInformation* si, const LocalGrid& grid)
      : ob::MotionValidator(si), grid_(grid) {}
  bool checkMotion(const ob::State* s1, const ob::State* s2) const override {
    const bool ok = SegmentFreeOnGrid(grid_, PointOf(s1), PointOf(s2));
    ok ? ++valid_ : ++invalid_;
    return ok;
  }
  bool checkMotion(const ob::State* s1, const ob::State* s2,
                   std::pair<ob::State*, double>& last_valid) const override {
    const Eigen::Vector2d a = PointOf(s1);
    const Eigen::Vector2d b = PointOf(s2);
    const double t = FirstBlockedParameter(grid_, a, b);
    if (t == kInfinity) {
      ++valid_;
      return true;
    }
    const double length_cells = std::max((b - a).norm() / grid_.cell_m(), 1.0);
    last_valid.second = std::max(0.0, t - kBlockedBackoffCells / length_cells);
    if (last_valid.first != nullptr) {
      si_->getStateSpace()->interpolate(s1, s2, last_valid.second, last_valid.first);
    }
    ++invalid_;
    return false;
  }

 private:
  const LocalGrid& grid_;
};

// The two planners with their own RNG (protected in OMPL) seeded.
class SeededRrtConnect : public og::RRTConnect {
 public:
  SeededRrtConnect(const ob::SpaceInformationPtr& si, std::uint32_t seed) : og::RRTConnect(si) {
    rng_.setLocalSeed(seed);
  }
};

class SeededRrtStar : public og::RRTstar {
 public:
  SeededRrtStar(const ob::SpaceInformationPtr& si, std::uint32_t seed) : og::RRTstar(si) {
    rng_.setLocalSeed(seed);
  }
};

ob::PlannerPtr MakePlanner(const OmplPlannerOptions& options, const ob::SpaceInformationPtr& si,
                           const ob::ProblemDefinitionPtr& problem, std::uint32_t seed) {
  if (options.type == OmplPlannerType::kRrtConnect) {
    auto planner = std::make_shared<SeededRrtConnect>(si, seed);
    planner->setRange(options.range_m);
    planner->setProblemDefinition(problem);
    planner->setNearestNeighbors<ompl::NearestNeighborsLinear>();  // also runs setup()
    return planner;
  }
  auto planner = std::make_shared<SeededRrtStar>(si, seed);
  planner->setRange(options.range_m);
  planner->setGoalBias(options.goal_bias);
  planner->setProblemDefinition(problem);
  planner->setNearestNeighbors<ompl::NearestNeighborsLinear>();
  return planner;
}

ob::SpaceInformationPtr MakeSpace(const LocalGrid& grid, std::uint32_t sampler_seed) {
  auto space = std::make_shared<ob::RealVectorStateSpace>(kDimensions);
  ob::RealVectorBounds bounds(kDimensions);
  const double side_m = grid.cells_per_side() * grid.cell_m();
  for (int i = 0; i < kDimensions; ++i) {
    bounds.setLow(i, grid.origin()[i]);
    bounds.setHigh(i, grid.origin()[i] + side_m);
  }
  space->setBounds(bounds);
  space->setStateSamplerAllocator([sampler_seed](const ob::StateSpace* s) -> ob::StateSamplerPtr {
    return std::make_shared<SeededSampler>(s, sampler_seed);
  });
  auto si = std::make_shared<ob::SpaceInformation>(space);
  si->setStateValidityChecker(
      [&grid](const ob::State* state) { return grid.FreeAt(PointOf(state)); });
  si->setMotionValidator(std::make_shared<GridMotionValidator>(si.get(), grid));
  si->setup();
  return si;
}

void SilenceOmpl() {
  static std::once_flag once;
  std::call_once(once, [] { ompl::msg::setLogLevel(ompl::msg::LOG_NONE); });
}

}  // namespace

void OmplPlannerOptions::Validate() const {
  auto fail = [](const std::string& message) { throw std::invalid_argument(message); };
  if (type != OmplPlannerType::kRrtConnect && type != OmplPlannerType::kRrtStar) {
    fail("type must be rrt_connect or rrt_star");
  }
  if (!(max_iterations >= 1 && max_iterations <= kMaxIterations)) {
    fail("max_iterations must be in [1, 1000000]");
  }
  if (!(range_m > 0.0 && range_m <= kMaxRangeM)) fail("range_m must be in (0, 40] m");
  if (!(goal_bias >= 0.0 && goal_bias < 1.0)) fail("goal_bias must be in [0, 1)");
}

OmplPathPlanner::OmplPathPlanner(const OmplPlannerOptions& options) : options_(options) {
  options_.Validate();
  SilenceOmpl();
}

std::string OmplPathPlanner::name() const {
  return options_.type == OmplPlannerType::kRrtConnect ? "ompl_rrt_connect" : "ompl_rrt_star";
}

std::optional<std::vector<Eigen::Vector2d>> OmplPathPlanner::Plan(const LocalGrid& grid,
                                                                  const Eigen::Vector2d& start,
                                                                  const Eigen::Vector2d& goal,
                                                                  std::uint64_t seed) {
  if (!grid.FreeAt(start) || !grid.FreeAt(goal)) return std::nullopt;
  if (SegmentFreeOnGrid(grid, start, goal)) return std::vector<Eigen::Vector2d>{start, goal};
  const ob::SpaceInformationPtr si = MakeSpace(grid, DeriveSeed(seed, kSamplerStream));
  auto problem = std::make_shared<ob::ProblemDefinition>(si);
  ob::ScopedState<> start_state(si->getStateSpace());
  ob::ScopedState<> goal_state(si->getStateSpace());
  for (int i = 0; i < kDimensions; ++i) {
    start_state[i] = start[i];
    goal_state[i] = goal[i];
  }
  problem->setStartAndGoalStates(start_state, goal_state, kGoalThresholdM);
  const ob::PlannerPtr planner =
      MakePlanner(options_, si, problem, DeriveSeed(seed, kPlannerStream));
  int calls = 0;
  const int max_calls = options_.max_iterations;
  const ob::PlannerTerminationCondition stop([&calls, max_calls] { return ++calls > max_calls; });
  if (planner->solve(stop) != ob::PlannerStatus::EXACT_SOLUTION || !problem->hasExactSolution()) {
    return std::nullopt;
  }
  const auto* solution = problem->getSolutionPath()->as<og::PathGeometric>();
  std::vector<Eigen::Vector2d> path;
  for (std::size_t k = 0; k < solution->getStateCount(); ++k) {
    path.push_back(PointOf(solution->getState(k)));
  }
  if (path.size() < 2) return std::nullopt;
  path.front() = start;
  path.back() = goal;
  if (options_.shortcut) path = ShortcutPath(grid, path);
  return path;
}

bool SegmentFreeOnGrid(const LocalGrid& grid, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return FirstBlockedParameter(grid, a, b) == kInfinity;
}

std::vector<Eigen::Vector2d> ShortcutPath(const LocalGrid& grid,
                                          const std::vector<Eigen::Vector2d>& path) {
  if (path.size() <= 2) return path;
  std::vector<Eigen::Vector2d> shortcut{path.front()};
  std::size_t from = 0;
  while (from + 1 < path.size()) {
    std::size_t to = path.size() - 1;
    while (to > from + 1 && !SegmentFreeOnGrid(grid, path[from], path[to])) --to;
    shortcut.push_back(path[to]);
    from = to;
  }
  return shortcut;
}

}  // namespace pavilion::nav
