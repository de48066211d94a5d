#include "sim/crowd/floor_field.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/geometry/segment2.h"
#include "core/random/random_stream.h"

namespace pavilion::sim::crowd {
namespace {

using Segments = std::vector<ObstacleSegment>;
using Vec2 = Eigen::Vector2d;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kStepM = 0.05;  // a person's step when following the field

// The four walls of the room [0, w] x [0, h].
Segments Room(double w, double h) {
  return {{{0, 0}, {w, 0}}, {{w, 0}, {w, h}}, {{w, h}, {0, h}}, {{0, h}, {0, 0}}};
}

// The four sides of the box [lo, hi].
void AddBox(const Vec2& lo, const Vec2& hi, Segments* walls) {
  walls->push_back({lo, {hi.x(), lo.y()}});
  walls->push_back({{hi.x(), lo.y()}, hi});
  walls->push_back({hi, {lo.x(), hi.y()}});
  walls->push_back({{lo.x(), hi.y()}, lo});
}

WalkableGrid Grid(double w, double h, const Segments& walls,
                  const std::vector<ObstacleCircle>& circles = {},
                  const WalkableGridOptions& options = {}) {
  return WalkableGrid({0, 0}, {w, h}, walls, circles, options);
}

// Follows Direction in kStepM steps from `start` until the goal or
// `max_steps`; the positions visited, start first.
std::vector<Vec2> Follow(const DistanceField& field, Vec2 p, int max_steps) {
  std::vector<Vec2> path{p};
  for (int i = 0; i < max_steps && !field.InGoal(p); ++i) {
    const Vec2 d = field.Direction(p);
    if (d.isZero()) break;
    p += kStepM * d;
    path.push_back(p);
  }
  return path;
}

// True when some step of `path` crosses one of `walls`.
bool CrossesWall(const std::vector<Vec2>& path, const Segments& walls) {
  for (std::size_t i = 1; i < path.size(); ++i) {
    for (const ObstacleSegment& w : walls) {
      if (core::SegmentsCross(path[i - 1], path[i], w.a_m, w.b_m)) return true;
    }
  }
  return false;
}

// Steps allowed to walk `distance_m`: 1.5 times the steps of the walking
// distance, plus 20.
int StepBudget(double distance_m) { return static_cast<int>(1.5 * distance_m / kStepM) + 20; }

std::string What(const std::invalid_argument& e) { return e.what(); }

// Options out of range and bad geometry throw std::invalid_argument naming the field.
TEST(FloorFieldTest, BadInputThrowsNamingTheField) {
  auto options_error = [](double cell_m, double clearance_m) -> std::string {
    WalkableGridOptions o;
    o.cell_m = cell_m;
    o.clearance_m = clearance_m;
    try {
      o.Validate();
    } catch (const std::invalid_argument& e) {
      return What(e);
    }
    return "";
  };
  EXPECT_EQ(options_error(0.2, 0.25), "");
  EXPECT_NE(options_error(0.0, 0.25).find("cell_m"), std::string::npos);
  EXPECT_NE(options_error(2.5, 0.25).find("cell_m"), std::string::npos);
  EXPECT_NE(options_error(std::nan(""), 0.25).find("cell_m"), std::string::npos);
  EXPECT_NE(options_error(0.2, -0.01).find("clearance_m"), std::string::npos);
  EXPECT_NE(options_error(0.2, 2.1).find("clearance_m"), std::string::npos);
  EXPECT_NE(options_error(0.2, std::nan("")).find("clearance_m"), std::string::npos);

  WalkableGridOptions bad;
  bad.cell_m = -1.0;
  EXPECT_THROW(Grid(5, 5, {}, {}, bad), std::invalid_argument);
  EXPECT_THROW(WalkableGrid({0, 0}, {0, 5}, {}, {}, {}), std::invalid_argument);
  EXPECT_THROW(WalkableGrid({0, 0}, {kInf, 5}, {}, {}, {}), std::invalid_argument);
  EXPECT_THROW(WalkableGrid({0, 0}, {1e6, 1e6}, {}, {}, {}), std::invalid_argument);
  try {
    Grid(5, 5, {{{1, 1}, {std::nan(""), 2}}});
    ADD_FAILURE() << "a NaN segment was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(What(e).find("segments[0]"), std::string::npos) << e.what();
  }
  try {
    Grid(5, 5, {}, {{{1, 1}, 0.5}, {{2, 2}, -0.1}});
    ADD_FAILURE() << "a negative radius was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(What(e).find("circles[1]"), std::string::npos) << e.what();
  }

  const WalkableGrid grid = Grid(5, 5, Room(5, 5));
  try {
    DistanceField::ToDisc(grid, {2, 2}, -1.0);
    ADD_FAILURE() << "a negative radius was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(What(e).find("radius_m"), std::string::npos) << e.what();
  }
  EXPECT_THROW(DistanceField::ToDisc(grid, {kInf, 2}, 0.5), std::invalid_argument);
  EXPECT_THROW(DistanceField::ToArea(grid, {{1, 1}, {2, 1}}), std::invalid_argument);
  EXPECT_THROW(DistanceField::ToArea(grid, {{1, 1}, {2, 2}, {2, 1}, {1, 2}}),  // a bow tie
               std::invalid_argument);
}

// A cell is free exactly when its centre is at least clearance_m from every
// obstacle (the clearance exceeds half a cell's diagonal, so every touched
// cell is also within it); off the rectangle nothing is free.
TEST(FloorFieldTest, CellsWithinClearanceOfObstaclesAreBlocked) {
  Segments walls = Room(6, 4);
  walls.push_back({{1.03, 1.1}, {4.2, 2.9}});  // diagonal
  const std::vector<ObstacleCircle> circles = {{{5.0, 1.0}, 0.3}};
  const WalkableGridOptions options;  // 0.2 m cells, 0.25 m clearance
  const WalkableGrid grid = Grid(6, 4, walls, circles, options);
  ASSERT_EQ(grid.cols(), 30);
  ASSERT_EQ(grid.rows(), 20);
  const double half_side_m = 0.5 * options.cell_m;
  const double half_diagonal_m = std::numbers::sqrt2 * half_side_m;
  int free = 0;
  int clearance = 0;
  for (int row = 0; row < grid.rows(); ++row) {
    for (int col = 0; col < grid.cols(); ++col) {
      const Vec2 c = grid.CellCenter({col, row});
      double d = (c - circles[0].center_m).norm() - circles[0].radius_m;
      for (const ObstacleSegment& w : walls) {
        d = std::min(d, core::PointSegmentDistance(c, w.a_m, w.b_m));
      }
      // An obstacle touches the cell when it comes within half a side of the
      // centre, and only if it comes within half a diagonal.
      const CellKind kind = grid.kind({col, row});
      if (d < half_side_m) {
        EXPECT_EQ(kind, CellKind::kObstacle) << "cell " << col << "," << row;
      }
      if (d > half_diagonal_m) {
        EXPECT_NE(kind, CellKind::kObstacle) << "cell " << col << "," << row;
      }
      if (std::abs(d - options.clearance_m) < 1e-9) continue;  // on the boundary
      const bool expect_free = d >= options.clearance_m;
      EXPECT_EQ(kind == CellKind::kFree, expect_free)
          << "cell " << col << "," << row << " at " << d << " m";
      EXPECT_EQ(grid.IsFree(c), expect_free);
      free += expect_free;
      clearance += kind == CellKind::kClearance;
    }
  }
  EXPECT_GT(free, 300);
  EXPECT_GT(clearance, 20);
  EXPECT_EQ(grid.kind(*grid.CellAt({3.0, 0.05})), CellKind::kObstacle);
  EXPECT_EQ(grid.kind(*grid.CellAt({5.0, 1.0})), CellKind::kObstacle);
  EXPECT_FALSE(grid.IsFree({3.0, 0.1}));
  EXPECT_TRUE(grid.IsFree({3.0, 0.5}));
  EXPECT_FALSE(grid.IsFree({-0.1, 2.0}));
  EXPECT_FALSE(grid.IsFree({3.0, 4.01}));
  EXPECT_FALSE(grid.CellAt({6.01, 2.0}).has_value());
  EXPECT_EQ(*grid.CellAt({6.0, 4.0}), FloorCell(29, 19));
}

// In an empty room the walking distance to a disc is the Euclidean
// |p - c| - r to within half a cell (the goal is a set of cells) plus 1 %,
// from every direction, whether the disc's centre lies on a cell's centre, on
// a cell corner or neither; Dijkstra's octile metric would be up to 8 % long
// at 22.5 deg. The descent points at the centre to within 2 h / R rad (the
// bilinear secant alone errs by up to h / 2R; octile: 22.5 deg at any range).
TEST(FloorFieldTest, EmptyRoomDistanceIsNearlyEuclidean) {
  const WalkableGrid grid = Grid(30, 30, Room(30, 30));
  const double h = grid.cell_m();
  for (const Vec2& center : {Vec2(15.07, 14.93), Vec2(15.0, 15.0), Vec2(15.1, 15.1)}) {
    for (const double radius : {0.3, 1.0}) {
      const DistanceField field = DistanceField::ToDisc(grid, center, radius);
      EXPECT_TRUE(field.InGoal(center));
      EXPECT_EQ(field.Distance(center), 0.0);
      EXPECT_TRUE(field.Direction(center).isZero());
      for (const double range : {1.5, 3.0, 6.0, 12.0}) {
        const double euclidean = range - radius;
        double lo = kInf;
        double hi = -kInf;
        for (int deg = 0; deg < 360; deg += 5) {
          const double a = deg * std::numbers::pi / 180.0;
          const Vec2 u(std::cos(a), std::sin(a));
          const Vec2 p = center + range * u;
          const double error = field.Distance(p) - euclidean;
          EXPECT_LE(std::abs(error), 0.5 * h + 0.01 * euclidean)
              << "centre " << center.transpose() << ", r " << radius << ", at " << range << " m, "
              << deg << " deg";
          lo = std::min(lo, error);
          hi = std::max(hi, error);
          if (range < 3.0) continue;
          EXPECT_GT(field.Direction(p).dot(-u), std::cos(2.0 * h / range))
              << "centre " << center.transpose() << ", r " << radius << ", at " << range << " m, "
              << deg << " deg";
        }
        EXPECT_LT(hi - lo, 0.5 * h) << "anisotropy at " << range << " m";
      }
    }
  }
}

// A wall closing off the goal makes it unreachable: +inf and no direction,
// also for a wall without clearance thinner than a cell, at a slant.
TEST(FloorFieldTest, GoalBehindClosedWallIsUnreachable) {
  Segments walls = Room(10, 6);
  walls.push_back({{5, 0}, {5, 6}});
  const DistanceField field = DistanceField::ToDisc(Grid(10, 6, walls), {8, 3}, 0.3);
  EXPECT_EQ(field.Distance({2, 3}), kInf);
  EXPECT_FALSE(field.Reachable({2, 3}));
  EXPECT_TRUE(field.Direction({2, 3}).isZero());
  EXPECT_TRUE(field.Reachable({7, 3}));
  EXPECT_NEAR(field.Distance({7, 3}), 0.7, 0.5 * 0.2);  // half a cell

  // Without clearance a wall along a cell boundary blocks the cells on both
  // sides, rounding notwithstanding.
  WalkableGridOptions thin;
  thin.clearance_m = 0.0;
  walls = Room(10, 6);
  walls.push_back({{6, 0}, {6, 6}});
  const WalkableGrid boundary_grid = Grid(10, 6, walls, {}, thin);
  EXPECT_EQ(boundary_grid.kind(*boundary_grid.CellAt({5.9, 3.0})), CellKind::kObstacle);
  EXPECT_EQ(boundary_grid.kind(*boundary_grid.CellAt({6.1, 3.0})), CellKind::kObstacle);
  EXPECT_EQ(DistanceField::ToDisc(boundary_grid, {8, 3}, 0.3).Distance({2, 3}), kInf);
  walls = Room(10, 6);
  walls.push_back({{3.03, 0}, {7.11, 6}});
  const DistanceField slanted =
      DistanceField::ToDisc(Grid(10, 6, walls, {}, thin), {8.5, 1.5}, 0.3);
  EXPECT_TRUE(slanted.Reachable({6.5, 1.0}));
  for (double y = 0.5; y < 6.0; y += 0.37) {
    const Vec2 p(1.0 + 0.5 * y, y);  // left of the wall
    EXPECT_EQ(slanted.Distance(p), kInf) << "leak at y = " << y;
    EXPECT_TRUE(slanted.Direction(p).isZero());
  }
}

// A goal behind a wall with a 0.9 m door is reached through the door: the
// walking distance is that around the door's jamb (not the straight 5.7 m),
// and a person following the field crosses the wall in the gap. A 0.4 m gap
// is narrower than two clearances: no way through.
TEST(FloorFieldTest, DoorGapIsWalkedThrough) {
  auto walls_with_gap = [](double gap_m) {
    Segments walls = Room(10, 10);
    walls.push_back({{5, 0}, {5, 5 - 0.5 * gap_m}});
    walls.push_back({{5, 5 + 0.5 * gap_m}, {5, 10}});
    return walls;
  };
  const Segments walls = walls_with_gap(0.9);
  const Vec2 start(2, 2);
  const Vec2 goal(8, 2);
  const double radius = 0.3;
  const DistanceField field = DistanceField::ToDisc(Grid(10, 10, walls), goal, radius);
  ASSERT_TRUE(field.Reachable(start));
  // Bounds: through the jamb's end (5, 4.55) and through (5, 4.8), the nearest
  // point a centre may pass with 0.25 m clearance.
  const Vec2 jamb(5, 4.55);
  const Vec2 cleared(5, 4.8);
  const double lower = (jamb - start).norm() + (goal - jamb).norm() - radius;
  const double upper = (cleared - start).norm() + (goal - cleared).norm() - radius;
  EXPECT_GT(field.Distance(start), lower);
  EXPECT_LT(field.Distance(start), 1.02 * upper);

  const std::vector<Vec2> path = Follow(field, start, StepBudget(field.Distance(start)));
  EXPECT_TRUE(field.InGoal(path.back())) << "stopped at " << path.back().transpose();
  EXPECT_FALSE(CrossesWall(path, walls));
  for (std::size_t i = 1; i < path.size(); ++i) {
    if ((path[i - 1].x() < 5.0) != (path[i].x() < 5.0)) {
      EXPECT_GT(path[i].y(), 4.55 + 0.1);
      EXPECT_LT(path[i].y(), 5.45 - 0.1);
    }
  }

  const DistanceField narrow = DistanceField::ToDisc(Grid(10, 10, walls_with_gap(0.4)), goal, 0.3);
  EXPECT_EQ(narrow.Distance(start), kInf);
  EXPECT_TRUE(narrow.Direction(start).isZero());
}

// From 30 random free starts (seeded) in a room with an L-shaped wall and a
// box, following Direction in 5 cm steps reaches the goal disc within
// 1.5 x distance / step + 20 steps, never crossing a wall.
TEST(FloorFieldTest, FollowingDirectionReachesGoalAroundWalls) {
  Segments walls = Room(14, 10);
  walls.push_back({{6, 1}, {6, 7}});  // the L: a 1 m gap below it, open round its top right
  walls.push_back({{6, 7}, {10, 7}});
  AddBox({2.5, 4.0}, {3.5, 5.2}, &walls);
  AddBox({8.0, 2.5}, {8.6, 3.4}, &walls);
  const WalkableGrid grid = Grid(14, 10, walls);
  const Vec2 goal(8.5, 4.5);
  const double radius = 0.4;
  const DistanceField field = DistanceField::ToDisc(grid, goal, radius);
  core::RandomStream random(42, core::RandomStream::StreamId("floor_field_test"));
  int walkers = 0;
  while (walkers < 30) {
    const Vec2 start(random.Uniform(0.0, 14.0), random.Uniform(0.0, 10.0));
    if (!grid.IsFree(start)) continue;
    ASSERT_TRUE(field.Reachable(start)) << start.transpose();
    ++walkers;
    const double distance = field.Distance(start);
    const std::vector<Vec2> path = Follow(field, start, StepBudget(distance));
    EXPECT_TRUE(field.InGoal(path.back()))
        << "from " << start.transpose() << " (" << distance << " m) stopped at "
        << path.back().transpose() << " after " << path.size() - 1 << " steps";
    EXPECT_LE((path.back() - goal).norm(), radius + grid.cell_m());
    EXPECT_FALSE(CrossesWall(path, walls)) << "from " << start.transpose();
  }
}

// Right behind a box, on the axis to the goal (where both ways round are
// equally long), the field still leads round a corner of the box; just past
// a corner it points on, not into the box.
TEST(FloorFieldTest, DirectionLeadsRoundConvexCorner) {
  Segments walls = Room(12, 8);
  AddBox({5, 3}, {7, 5}, &walls);
  const Vec2 goal(10, 4);
  const DistanceField field = DistanceField::ToDisc(Grid(12, 8, walls), goal, 0.3);
  for (const Vec2& start : {Vec2(3.0, 4.0), Vec2(4.6, 4.0), Vec2(4.62, 2.6), Vec2(6.0, 5.4)}) {
    const double distance = field.Distance(start);
    ASSERT_LT(distance, kInf) << start.transpose();
    const std::vector<Vec2> path = Follow(field, start, StepBudget(distance));
    EXPECT_TRUE(field.InGoal(path.back()))
        << "from " << start.transpose() << " stopped at " << path.back().transpose();
    EXPECT_FALSE(CrossesWall(path, walls));
  }
  // Above the box's top right corner (7, 5), 0.35 m out: onwards and downwards.
  const Vec2 d = field.Direction({7.2, 5.35});
  EXPECT_GT(d.x(), 0.3);
  EXPECT_LT(d.y(), 0.0);
}

// A person pressed into a wall's clearance (a blocked cell, no distance) is
// led back out of it, forwards; a person on the wall line too.
TEST(FloorFieldTest, BlockedCellDirectionLeadsOutOfClearance) {
  // Walls off the cell boundaries: the cells of rows 0 and 19 are obstacle
  // cells (touched), those of rows 1 and 18 clearance cells.
  const Segments walls = {
      {{0, 0.13}, {10, 0.13}}, {{0, 3.9}, {10, 3.9}}, {{0, 0}, {0, 4}}, {{10, 0}, {10, 4}}};
  const WalkableGrid grid = Grid(10, 4, walls);
  ASSERT_EQ(grid.kind(*grid.CellAt({6.0, 0.3})), CellKind::kClearance);
  ASSERT_EQ(grid.kind(*grid.CellAt({6.0, 3.75})), CellKind::kClearance);
  ASSERT_EQ(grid.kind(*grid.CellAt({6.0, 0.15})), CellKind::kObstacle);
  const DistanceField field = DistanceField::ToDisc(grid, {1, 2}, 0.3);
  for (const Vec2& start : {Vec2(6.0, 0.3), Vec2(6.0, 0.21), Vec2(6.03, 3.75), Vec2(6.0, 0.15)}) {
    EXPECT_FALSE(grid.IsFree(start));
    EXPECT_EQ(field.Distance(start), kInf);
    EXPECT_FALSE(field.Reachable(start));
    const Vec2 d = field.Direction(start);
    EXPECT_NEAR(d.norm(), 1.0, 1e-9);
    EXPECT_LT(d.x(), 0.0) << "not forwards from " << start.transpose();
    // Out at 30 deg or more, not sliding along the wall inside its clearance.
    EXPECT_GT(d.y() * (2.0 - start.y()), 0.5) << "not away from the wall";
    Vec2 p = start;
    int steps = 0;
    while (!grid.IsFree(p) && steps < 20) {
      p += kStepM * field.Direction(p);
      ++steps;
    }
    EXPECT_TRUE(grid.IsFree(p)) << "still blocked at " << p.transpose();
    EXPECT_FALSE(CrossesWall({start, p}, walls));
  }
  EXPECT_TRUE(field.Direction({-1, 2}).isZero());  // off the floor
}

// A person whose centre is in a cell a thin wall passes through, on the far
// side from the goal, is not sent through the wall towards the goal's side
// (lower, but across) but round its end.
TEST(FloorFieldTest, ObstacleCellDirectionStaysOnItsSideOfTheWall) {
  Segments walls = Room(10, 4);
  walls.push_back({{5.03, 0}, {5.03, 3}});  // open above y = 3
  const WalkableGrid grid = Grid(10, 4, walls);
  const Vec2 start(5.01, 1.0);  // in the wall's cell, left of the wall
  ASSERT_EQ(grid.kind(*grid.CellAt(start)), CellKind::kObstacle);
  ASSERT_TRUE(grid.IsFree({5.3, 1.0}));  // the free cell right of the wall
  const DistanceField field = DistanceField::ToDisc(grid, {6.5, 1}, 0.3);
  EXPECT_LT(field.Direction(start).x(), 0.0);
  const std::vector<Vec2> path = Follow(field, start, 400);
  EXPECT_TRUE(field.InGoal(path.back())) << "stopped at " << path.back().transpose();
  EXPECT_FALSE(CrossesWall(path, walls));
}

// An area goal: its cells are at 0, the distance outside is that to the
// polygon, and a disc goal inside a pillar falls back to the nearest free cell.
TEST(FloorFieldTest, AreaGoalAndNearestFreeCellFallback) {
  const std::vector<ObstacleCircle> pillar = {{{5, 2}, 0.5}};
  const WalkableGrid grid = Grid(10, 10, Room(10, 10), pillar);
  const DistanceField area =
      DistanceField::ToArea(grid, {{7.0, 7.0}, {9.0, 7.0}, {9.0, 9.0}, {7.0, 9.0}});
  EXPECT_TRUE(area.InGoal({8, 8}));
  EXPECT_EQ(area.Distance({8, 8}), 0.0);
  EXPECT_NEAR(area.Distance({2, 8}), 5.0, 0.02 * 5.0);
  EXPECT_NEAR(area.Distance({8, 2}), 5.0, 0.02 * 5.0);
  EXPECT_NEAR(area.Distance({3, 3}), std::hypot(4.0, 4.0), 0.02 * std::hypot(4.0, 4.0));
  EXPECT_GT(area.Direction({2, 8}).x(), 0.99);

  const Vec2 in_pillar(5, 2);
  const DistanceField fallback = DistanceField::ToDisc(grid, in_pillar, 0.1);
  EXPECT_FALSE(fallback.InGoal(in_pillar));
  std::vector<Vec2> goal_cells;
  for (int row = 0; row < grid.rows(); ++row) {
    for (int col = 0; col < grid.cols(); ++col) {
      const Vec2 c = grid.CellCenter({col, row});
      if (fallback.InGoal(c)) goal_cells.push_back(c);
    }
  }
  ASSERT_EQ(goal_cells.size(), 1u);
  EXPECT_TRUE(grid.IsFree(goal_cells[0]));
  // No free centre lies nearer to the disc than the goal cell's.
  const double nearest = (goal_cells[0] - in_pillar).norm();
  EXPECT_GE(nearest, 0.5 + 0.25);
  EXPECT_LT(nearest, 0.5 + 0.25 + grid.cell_m());
  const Vec2 far = goal_cells[0] + Vec2(-3.5, 0.2);  // in the open, beside the pillar
  EXPECT_NEAR(fallback.Distance(far), 3.5, 0.02 * 3.5);
}

// The same inputs give bit-identical fields.
TEST(FloorFieldTest, FieldsAreDeterministic) {
  Segments walls = Room(12, 8);
  AddBox({5, 3}, {7, 5}, &walls);
  const WalkableGrid grid = Grid(12, 8, walls);
  const DistanceField a = DistanceField::ToDisc(grid, {10, 4}, 0.3);
  const DistanceField b = DistanceField::ToDisc(grid, {10, 4}, 0.3);
  core::RandomStream random(3, 4);
  for (int i = 0; i < 1000; ++i) {
    const Vec2 p(random.Uniform(0.0, 12.0), random.Uniform(0.0, 8.0));
    EXPECT_EQ(a.Distance(p), b.Distance(p));
    EXPECT_EQ(a.Direction(p), b.Direction(p));
  }
}

}  // namespace
}  // namespace pavilion::sim::crowd
