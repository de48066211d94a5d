// OMPL initial paths: seeded determinism (same bytes for the same seed, in any
// creation order and on concurrent threads), the cell-exact segment test, the
// shortcut and the options.
#include "nav/local/ompl_path_planner.h"

#include <gtest/gtest.h>
#include <ompl/util/RandomNumbers.h>

#include <cstring>
#include <memory>
#include <stdexcept>
#include <thread>
#include <vector>

namespace pavilion::nav {
namespace {

using Path = std::vector<Eigen::Vector2d>;

constexpr double kPointSpacingM = 0.03;

void AddWall(std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& a,
             const Eigen::Vector2d& b) {
  const int n = static_cast<int>((b - a).norm() / kPointSpacingM);
  for (int k = 0; k <= n; ++k) points.push_back(a + (b - a) * k / n);
}

// A partition across the grid with a door whose position depends on `variant`,
// and a second partition with a door at the other end: start and goal have no
// line of sight, so the planners must search.
LocalGrid DoorScene(int variant) {
  std::vector<Eigen::Vector2d> points;
  const double door_x = -2.0 + 0.5 * variant;
  AddWall(points, {-4.0, -1.0}, {door_x - 0.6, -1.0});
  AddWall(points, {door_x + 0.6, -1.0}, {4.0, -1.0});
  AddWall(points, {-4.0, 1.2}, {2.2, 1.2});
  LocalGrid grid(LocalGridOptions{});
  grid.Build(Eigen::Vector2d::Zero(), points);
  return grid;
}

const Eigen::Vector2d kStart(-3.0, -3.0);
const Eigen::Vector2d kGoal(-3.0, 3.0);

bool SameBytes(const std::optional<Path>& a, const std::optional<Path>& b) {
  if (a.has_value() != b.has_value()) return false;
  if (!a) return true;
  return a->size() == b->size() &&
         std::memcmp(a->data(), b->data(), a->size() * sizeof(Eigen::Vector2d)) == 0;
}

OmplPathPlanner Planner(OmplPlannerType type) {
  OmplPlannerOptions options;
  options.type = type;
  return OmplPathPlanner(options);
}

// Confirms the same seed gives the same path bytes, and different seeds differ
// (the seed is what drives the sampling).
TEST(OmplPathPlannerTest, SameSeedSameBytes) {
  for (OmplPlannerType type : {OmplPlannerType::kRrtConnect, OmplPlannerType::kRrtStar}) {
    OmplPathPlanner planner = Planner(type);
    const LocalGrid grid = DoorScene(1);
    const auto first = planner.Plan(grid, kStart, kGoal, 7);
    ASSERT_TRUE(first.has_value()) << planner.name();
    EXPECT_TRUE(SameBytes(first, planner.Plan(grid, kStart, kGoal, 7))) << planner.name();
    EXPECT_TRUE(SameBytes(first, Planner(type).Plan(grid, kStart, kGoal, 7))) << planner.name();
    int differing = 0;
    for (std::uint64_t seed = 8; seed < 12; ++seed) {
      if (!SameBytes(first, planner.Plan(grid, kStart, kGoal, seed))) ++differing;
    }
    EXPECT_GT(differing, 0) << planner.name();
  }
}

// Plans for scenes 0..3 with seeds 100 + scene.
std::vector<std::optional<Path>> RunScenes(OmplPathPlanner& planner) {
  std::vector<std::optional<Path>> paths;
  for (int scene = 0; scene < 4; ++scene) {
    paths.push_back(planner.Plan(DoorScene(scene), kStart, kGoal, 100 + scene));
  }
  return paths;
}

// Confirms the paths do not depend on creation order, on other OMPL RNGs
// created in between (which advance OMPL's process-wide seed generator), or on
// running the two planners on two threads at once.
TEST(OmplPathPlannerTest, IndependentOfCreationOrderAndThreads) {
  OmplPathPlanner connect = Planner(OmplPlannerType::kRrtConnect);
  OmplPathPlanner star = Planner(OmplPlannerType::kRrtStar);
  const auto connect_serial = RunScenes(connect);
  const auto star_serial = RunScenes(star);
  for (const auto& path : connect_serial) ASSERT_TRUE(path.has_value());
  for (const auto& path : star_serial) ASSERT_TRUE(path.has_value());

  std::vector<std::unique_ptr<ompl::RNG>> bystanders;
  for (int k = 0; k < 5; ++k) bystanders.push_back(std::make_unique<ompl::RNG>());
  OmplPathPlanner star_first = Planner(OmplPlannerType::kRrtStar);
  OmplPathPlanner connect_second = Planner(OmplPlannerType::kRrtConnect);
  const auto star_reordered = RunScenes(star_first);
  const auto connect_reordered = RunScenes(connect_second);

  std::vector<std::optional<Path>> connect_threaded;
  std::vector<std::optional<Path>> star_threaded;
  std::thread a([&] { connect_threaded = RunScenes(connect_second); });
  std::thread b([&] { star_threaded = RunScenes(star_first); });
  a.join();
  b.join();
  for (std::size_t k = 0; k < connect_serial.size(); ++k) {
    EXPECT_TRUE(SameBytes(connect_serial[k], connect_reordered[k])) << "scene " << k;
    EXPECT_TRUE(SameBytes(connect_serial[k], connect_threaded[k])) << "scene " << k;
    EXPECT_TRUE(SameBytes(star_serial[k], star_reordered[k])) << "scene " << k;
    EXPECT_TRUE(SameBytes(star_serial[k], star_threaded[k])) << "scene " << k;
  }
}

// A grid whose cells are blocked one by one: 1/8 m cells from the world origin
// (exact in binary) and a tiny robot, so an obstacle point blocks its own cell only.
LocalGrid UnitGrid(const std::vector<Eigen::Vector2d>& points) {
  LocalGridOptions options;
  options.cell_m = 0.125;
  options.robot_radius_m = 0.01;
  LocalGrid grid(options);
  grid.Build({4.0, 4.0}, points);
  return grid;
}

// Confirms a segment is blocked by any cell it touches, including a side cell
// at an exact corner crossing, and free otherwise.
TEST(OmplPathPlannerTest, SegmentTestTouchesEveryCell) {
  const Eigen::Vector2d a(0.0625, 0.0625);  // centre of cell (0, 0)
  const Eigen::Vector2d b(0.1875, 0.1875);  // centre of cell (1, 1), through corner (1, 1)
  EXPECT_TRUE(SegmentFreeOnGrid(UnitGrid({}), a, b));
  EXPECT_FALSE(SegmentFreeOnGrid(UnitGrid({{0.0625, 0.1875}}), a, b));  // side cell (0, 1)
  EXPECT_FALSE(SegmentFreeOnGrid(UnitGrid({{0.1875, 0.0625}}), a, b));  // side cell (1, 0)
  const LocalGrid wall = UnitGrid({{1.06, 0.5}});                       // cell (8, 4)
  EXPECT_FALSE(SegmentFreeOnGrid(wall, {0.3, 0.55}, {2.0, 0.55}));
  EXPECT_TRUE(SegmentFreeOnGrid(wall, {0.3, 0.3}, {2.0, 0.3}));
  EXPECT_FALSE(SegmentFreeOnGrid(wall, {0.3, 0.3}, {1.06, 0.5}));  // ends in the blocked cell
}

// Confirms the shortcut keeps the ends, drops points in line of sight and
// keeps the corner that a wall makes necessary.
TEST(OmplPathPlannerTest, ShortcutKeepsOnlyNecessaryCorners) {
  const LocalGrid free_grid = UnitGrid({});
  const Path zigzag = {{0.5, 0.5}, {1.0, 1.5}, {1.5, 0.5}, {2.0, 1.5}, {3.0, 0.5}};
  EXPECT_EQ(ShortcutPath(free_grid, zigzag), (Path{{0.5, 0.5}, {3.0, 0.5}}));
  std::vector<Eigen::Vector2d> wall;
  for (double y = 0.0; y < 1.05; y += 0.1) wall.push_back({1.5, y});  // cells (12, 0..8)
  const Path over = {{0.5, 0.5}, {1.0, 1.25}, {1.5, 2.0}, {2.5, 1.0}, {3.0, 0.5}};
  EXPECT_EQ(ShortcutPath(UnitGrid(wall), over), (Path{{0.5, 0.5}, {1.5, 2.0}, {3.0, 0.5}}));
}

// Confirms none for a start or goal in a blocked cell and the straight segment
// when it is free.
TEST(OmplPathPlannerTest, HandlesBlockedEndsAndLineOfSight) {
  OmplPathPlanner planner = Planner(OmplPlannerType::kRrtConnect);
  const LocalGrid grid = DoorScene(0);
  EXPECT_FALSE(planner.Plan(grid, {0.0, -1.0}, kGoal, 1).has_value());  // on the wall
  EXPECT_FALSE(planner.Plan(grid, kStart, {9.0, 0.0}, 1).has_value());  // off the grid
  const auto straight = planner.Plan(grid, kStart, {3.0, -3.0}, 1);
  ASSERT_TRUE(straight.has_value());
  EXPECT_EQ(straight->size(), 2u);
}

// Confirms names and the validation of every option.
TEST(OmplPathPlannerTest, NamesAndValidatesOptions) {
  EXPECT_EQ(Planner(OmplPlannerType::kRrtConnect).name(), "ompl_rrt_connect");
  EXPECT_EQ(Planner(OmplPlannerType::kRrtStar).name(), "ompl_rrt_star");
  const auto rejects = [](auto edit) {
    OmplPlannerOptions options;
    edit(options);
    EXPECT_THROW(options.Validate(), std::invalid_argument);
    EXPECT_THROW(OmplPathPlanner{options}, std::invalid_argument);
  };
  rejects([](OmplPlannerOptions& o) { o.max_iterations = 0; });
  rejects([](OmplPlannerOptions& o) { o.range_m = 0.0; });
  rejects([](OmplPlannerOptions& o) { o.range_m = 41.0; });
  rejects([](OmplPlannerOptions& o) { o.goal_bias = 1.0; });
  rejects([](OmplPlannerOptions& o) { o.type = static_cast<OmplPlannerType>(7); });
  EXPECT_NO_THROW(OmplPlannerOptions{}.Validate());
}

}  // namespace
}  // namespace pavilion::nav
