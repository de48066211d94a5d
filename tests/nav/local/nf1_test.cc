#include "nav/local/nf1.h"

#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <limits>
#include <numbers>
#include <vector>

#include "core/random/random_stream.h"
#include "nav/local/local_grid.h"

namespace {

using pavilion::core::RandomStream;
using pavilion::nav::GridCell;
using pavilion::nav::LocalGrid;
using pavilion::nav::LocalGridOptions;
using pavilion::nav::Nf1Planner;

constexpr int kScenes = 60;
constexpr double kPointSpacing_m = 0.02;  // scan-like density along walls and people

// A random scene on the default grid centred at the origin: a few walls, a few
// people (discs) and scattered points, all seeded.
std::vector<Eigen::Vector2d> RandomScene(std::uint64_t seed) {
  RandomStream rng(seed, RandomStream::StreamId("nf1_test"));
  std::vector<Eigen::Vector2d> points;
  const int walls = static_cast<int>(rng.UniformInt(0, 3));
  for (int w = 0; w < walls; ++w) {
    const Eigen::Vector2d a(rng.Uniform(-4, 4), rng.Uniform(-4, 4));
    const double heading = rng.Uniform(0, std::numbers::pi);
    const double length = rng.Uniform(1.0, 4.0);
    const Eigen::Vector2d dir(std::cos(heading), std::sin(heading));
    for (double s = 0; s <= length; s += kPointSpacing_m) points.push_back(a + s * dir);
  }
  const int people = static_cast<int>(rng.UniformInt(2, 8));
  for (int k = 0; k < people; ++k) {
    const Eigen::Vector2d c(rng.Uniform(-4, 4), rng.Uniform(-4, 4));
    const double r = rng.Uniform(0.15, 0.3);
    for (double t = 0; t < 2 * std::numbers::pi; t += kPointSpacing_m / r) {
      points.push_back(c + r * Eigen::Vector2d(std::cos(t), std::sin(t)));
    }
  }
  const int scatter = static_cast<int>(rng.UniformInt(0, 30));
  for (int k = 0; k < scatter; ++k) points.emplace_back(rng.Uniform(-4, 4), rng.Uniform(-4, 4));
  return points;
}

// Naive breadth-first reference: std::deque, bounds and Free() checked per step.
std::vector<int> ReferenceValues(const LocalGrid& grid, const GridCell& goal) {
  const int n = grid.cells_per_side();
  std::vector<int> dist(static_cast<std::size_t>(n) * n, -1);
  if (!grid.Free(goal)) return dist;
  std::deque<GridCell> queue{goal};
  dist[grid.Index(goal)] = 0;
  const GridCell steps[4] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  while (!queue.empty()) {
    const GridCell c = queue.front();
    queue.pop_front();
    for (const GridCell& s : steps) {
      const GridCell q = c + s;
      if (!grid.Inside(q) || !grid.Free(q) || dist[grid.Index(q)] >= 0) continue;
      dist[grid.Index(q)] = dist[grid.Index(c)] + 1;
      queue.push_back(q);
    }
  }
  return dist;
}

// A uniformly drawn cell among those with dist >= 0, if any.
std::optional<GridCell> DrawReached(const LocalGrid& grid, const std::vector<int>& dist,
                                    RandomStream* rng) {
  std::vector<int> reached;
  for (int i = 0; i < static_cast<int>(dist.size()); ++i) {
    if (dist[i] >= 0) reached.push_back(i);
  }
  if (reached.empty()) return std::nullopt;
  return grid.CellAt(reached[rng->UniformInt(0, static_cast<std::int64_t>(reached.size()) - 1)]);
}

std::optional<GridCell> DrawFree(const LocalGrid& grid, RandomStream* rng) {
  for (int attempt = 0; attempt < 1000; ++attempt) {
    const GridCell c(static_cast<int>(rng->UniformInt(0, grid.cells_per_side() - 1)),
                     static_cast<int>(rng->UniformInt(0, grid.cells_per_side() - 1)));
    if (grid.Free(c)) return c;
  }
  return std::nullopt;
}

// The nearest (Euclidean, cell centre) reached cell to `goal`, by brute force.
double NearestReachedDistance(const LocalGrid& grid, const std::vector<int>& dist,
                              const Eigen::Vector2d& goal) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < static_cast<int>(dist.size()); ++i) {
    if (dist[i] >= 0) best = std::min(best, (grid.CenterOf(grid.CellAt(i)) - goal).norm());
  }
  return best;
}

double CellPathLength(const LocalGrid& grid, const std::vector<GridCell>& cells) {
  double length = 0;
  for (std::size_t k = 1; k < cells.size(); ++k) {
    length += grid.cell_m() * (cells[k] - cells[k - 1]).cast<double>().norm();
  }
  return length;
}

// NF1 values equal the naive breadth-first reference on every cell of 60
// seeded random scenes, unreachable cells included.
TEST(Nf1PlannerTest, ValuesMatchNaiveBreadthFirstReference) {
  LocalGrid grid(LocalGridOptions{});
  Nf1Planner planner;
  int compared_unreachable = 0;
  for (int scene = 0; scene < kScenes; ++scene) {
    grid.Build(Eigen::Vector2d::Zero(), RandomScene(scene));
    RandomStream rng(scene, 1);
    const std::optional<GridCell> goal = DrawFree(grid, &rng);
    ASSERT_TRUE(goal);
    planner.Compute(grid, *goal);
    const std::vector<int> reference = ReferenceValues(grid, *goal);
    for (int i = 0; i < static_cast<int>(reference.size()); ++i) {
      const GridCell c = grid.CellAt(i);
      if (reference[i] < 0) {
        ASSERT_EQ(planner.value(c), Nf1Planner::kUnreachable) << "scene " << scene;
        ++compared_unreachable;
      } else {
        ASSERT_EQ(planner.value(c), reference[i]) << "scene " << scene << " cell " << c.transpose();
      }
    }
  }
  EXPECT_GT(compared_unreachable, 0);
}

// The descent is 8-connected over free cells, never cuts a blocked corner,
// strictly descends, and its length lies between the 4-connected optimum
// over sqrt(2) and that optimum; the polyline has the exact ends and no
// collinear interior vertices.
TEST(Nf1PlannerTest, PathIsEightConnectedFreeAndNearOptimal) {
  LocalGrid grid(LocalGridOptions{});
  Nf1Planner planner;
  for (int scene = 0; scene < kScenes; ++scene) {
    grid.Build(Eigen::Vector2d::Zero(), RandomScene(scene));
    RandomStream rng(scene, 2);
    const std::optional<GridCell> goal_cell = DrawFree(grid, &rng);
    ASSERT_TRUE(goal_cell);
    const std::vector<int> reference = ReferenceValues(grid, *goal_cell);
    const GridCell start_cell = *DrawReached(grid, reference, &rng);
    const Eigen::Vector2d offset(rng.Uniform(-0.02, 0.02), rng.Uniform(-0.02, 0.02));
    const Eigen::Vector2d start = grid.CenterOf(start_cell) + offset;
    const Eigen::Vector2d goal = grid.CenterOf(*goal_cell) - offset;
    const auto path = planner.Plan(grid, start, goal, 0);
    ASSERT_TRUE(path) << "scene " << scene;
    ASSERT_GE(path->size(), 2u);
    EXPECT_EQ(path->front(), start);
    EXPECT_EQ(path->back(), goal);

    const std::vector<GridCell>& cells = planner.cell_path();
    ASSERT_EQ(cells.front(), start_cell);
    ASSERT_EQ(cells.back(), *goal_cell);
    for (std::size_t k = 0; k < cells.size(); ++k) {
      ASSERT_TRUE(grid.Free(cells[k]));
      if (k == 0) continue;
      const GridCell step = cells[k] - cells[k - 1];
      ASSERT_EQ(step.cwiseAbs().maxCoeff(), 1);
      ASSERT_LT(planner.value(cells[k]), planner.value(cells[k - 1]));
      if (step.x() != 0 && step.y() != 0) {
        ASSERT_TRUE(grid.Free(cells[k - 1] + GridCell(step.x(), 0)));
        ASSERT_TRUE(grid.Free(cells[k - 1] + GridCell(0, step.y())));
      }
    }
    const double optimal4_m = grid.cell_m() * reference[grid.Index(start_cell)];
    const double length_m = CellPathLength(grid, cells);
    EXPECT_LE(length_m, optimal4_m + 1e-9);
    EXPECT_GE(length_m, optimal4_m / std::numbers::sqrt2 - 1e-9);
    for (std::size_t k = 1; k + 1 < path->size(); ++k) {
      const Eigen::Vector2d a = (*path)[k] - (*path)[k - 1];
      const Eigen::Vector2d b = (*path)[k + 1] - (*path)[k];
      EXPECT_GT(std::abs(a.x() * b.y() - a.y() * b.x()), 1e-12) << "collinear vertex " << k;
    }
  }
}

// Two plans of the same scene are identical (deterministic tie-breaking).
TEST(Nf1PlannerTest, PlanIsDeterministic) {
  LocalGrid grid(LocalGridOptions{});
  grid.Build(Eigen::Vector2d::Zero(), RandomScene(7));
  Nf1Planner a;
  Nf1Planner b;
  const Eigen::Vector2d start(-3.1, -2.9);
  const Eigen::Vector2d goal(3.2, 2.7);
  const auto pa = a.Plan(grid, start, goal, 1);
  b.Plan(grid, goal, start, 2);
  const auto pb = b.Plan(grid, start, goal, 3);
  ASSERT_EQ(pa.has_value(), pb.has_value());
  if (pa) {
    EXPECT_EQ(*pa, *pb);
  }
}

// A goal 20 m away becomes the reachable free cell nearest to it.
TEST(Nf1PlannerTest, LocalGoalForOffGridGoalIsNearestReachableCell) {
  LocalGrid grid(LocalGridOptions{});
  for (int scene = 0; scene < 10; ++scene) {
    grid.Build(Eigen::Vector2d::Zero(), RandomScene(100 + scene));
    const Eigen::Vector2d goal(20.0 * std::cos(scene), 20.0 * std::sin(scene));
    RandomStream rng(scene, 3);
    const std::optional<GridCell> start_cell = DrawFree(grid, &rng);
    ASSERT_TRUE(start_cell);
    const Eigen::Vector2d start = grid.CenterOf(*start_cell);
    const auto local = Nf1Planner::LocalGoal(grid, start, goal);
    ASSERT_TRUE(local);
    const std::vector<int> reachable = ReferenceValues(grid, *start_cell);
    ASSERT_GE(reachable[grid.Index(grid.CellOf(*local))], 0);
    EXPECT_NEAR((*local - goal).norm(), NearestReachedDistance(grid, reachable, goal), 1e-9);
    // Plan() keeps the seam's contract: to the goal itself or none; to the
    // local goal the caller picked it plans.
    Nf1Planner planner;
    EXPECT_FALSE(planner.Plan(grid, start, goal, 0));
    const auto path = planner.Plan(grid, start, *local, 0);
    ASSERT_TRUE(path);
    EXPECT_EQ(path->back(), *local);
  }
}

// A goal inside a person (not free), or walled off from the start, becomes the
// nearest free cell reachable from the start; a free reachable goal is kept.
TEST(Nf1PlannerTest, LocalGoalForBlockedOrUnreachableGoal) {
  LocalGrid grid(LocalGridOptions{});
  std::vector<Eigen::Vector2d> points;
  const Eigen::Vector2d person(2.0, 0.0);
  for (double t = 0; t < 2 * std::numbers::pi; t += 0.05) {
    points.push_back(person + 0.25 * Eigen::Vector2d(std::cos(t), std::sin(t)));
  }
  // A closed room around (-2.5, 2.5).
  const Eigen::Vector2d room(-2.5, 2.5);
  for (double s = -1.0; s <= 1.0; s += kPointSpacing_m) {
    for (const Eigen::Vector2d& p : {Eigen::Vector2d(s, -1), Eigen::Vector2d(s, 1),
                                     Eigen::Vector2d(-1, s), Eigen::Vector2d(1, s)}) {
      points.push_back(room + p);
    }
  }
  grid.Build(Eigen::Vector2d::Zero(), points);
  const Eigen::Vector2d start(-1.0, -1.5);
  const std::vector<int> reachable = ReferenceValues(grid, grid.CellOf(start));

  const auto behind_person = Nf1Planner::LocalGoal(grid, start, person);
  ASSERT_TRUE(behind_person);
  EXPECT_TRUE(grid.FreeAt(*behind_person));
  EXPECT_NEAR((*behind_person - person).norm(), NearestReachedDistance(grid, reachable, person),
              1e-9);
  EXPECT_GT((*behind_person - person).norm(), grid.options().robot_radius_m);

  ASSERT_TRUE(grid.FreeAt(room));
  const auto in_room = Nf1Planner::LocalGoal(grid, start, room);
  ASSERT_TRUE(in_room);
  EXPECT_NE(*in_room, room);
  EXPECT_GE(reachable[grid.Index(grid.CellOf(*in_room))], 0);
  EXPECT_NEAR((*in_room - room).norm(), NearestReachedDistance(grid, reachable, room), 1e-9);

  const Eigen::Vector2d free_goal(3.0, -3.0);
  EXPECT_EQ(Nf1Planner::LocalGoal(grid, start, free_goal), free_goal);
}

// A start grazing an obstacle plans from the nearest free cell within one
// robot radius; a start buried in obstacles has no plan.
TEST(Nf1PlannerTest, StartNotFreeUsesNearestFreeCellWithinRadius) {
  LocalGrid grid(LocalGridOptions{});
  std::vector<Eigen::Vector2d> points;
  for (double s = -2.0; s <= 2.0; s += kPointSpacing_m) points.emplace_back(s, 0.0);
  grid.Build(Eigen::Vector2d::Zero(), points);
  const double radius_m = grid.options().robot_radius_m;
  const Eigen::Vector2d grazing(0.3, radius_m - 0.1);
  ASSERT_FALSE(grid.FreeAt(grazing));
  const std::optional<GridCell> start_cell = Nf1Planner::StartCell(grid, grazing);
  ASSERT_TRUE(start_cell);
  EXPECT_TRUE(grid.Free(*start_cell));
  EXPECT_LE((grid.CenterOf(*start_cell) - grazing).norm(), radius_m);
  EXPECT_GT(grid.CenterOf(*start_cell).y(), grazing.y());

  Nf1Planner planner;
  const Eigen::Vector2d goal(0.3, 3.0);
  const auto path = planner.Plan(grid, grazing, goal, 0);
  ASSERT_TRUE(path);
  EXPECT_EQ(path->front(), grazing);
  EXPECT_EQ((*path)[1], grid.CenterOf(*start_cell));
  EXPECT_EQ(path->back(), goal);
  EXPECT_EQ(Nf1Planner::LocalGoal(grid, grazing, goal), goal);

  // On the wall itself every cell within one radius is blocked.
  const Eigen::Vector2d buried(0.3, 0.0);
  EXPECT_FALSE(Nf1Planner::StartCell(grid, buried));
  EXPECT_FALSE(Nf1Planner::LocalGoal(grid, buried, goal));
  EXPECT_FALSE(planner.Plan(grid, buried, goal, 0));
}

}  // namespace
