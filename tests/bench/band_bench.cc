// Time of the path-planning sublayer's steps (thesis §6.3.4; issue 14) on a
// typical 8 m scene: the robot at the centre of a 7.2 m x 6.6 m room with six
// visitors (discs of 0.25 m), seen by a 360-degree scan at 0.5 degrees (720
// beams, all hits on the grid). Budgets: NF1 (wavefront and path) <= 0.5 ms
// on the default 160x160 grid; one elastic-band update <= 0.2 ms. Baseline in
// the same run: building the local grid from the scan (BM_LocalGridBuild).
// BM_Nf1FarGoal plans to a node 20 m away (the local-goal search adds a
// wavefront from the start and one from the local goal); BM_DistanceFieldBuild
// is the per-scan cost the band's updates share.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "nav/local/distance_field.h"
#include "nav/local/elastic_band.h"
#include "nav/local/local_grid.h"
#include "nav/local/nf1.h"

namespace {

using namespace pavilion::nav;

constexpr int kBeams = 720;
constexpr double kMaxRange_m = 8.0;
constexpr double kRoomHalfWidth_m = 3.6;
constexpr double kRoomHalfHeight_m = 3.3;
constexpr double kVisitorRadius_m = 0.25;
constexpr int kSettleUpdates = 50;  // the band converges before it is timed

struct Scene {
  std::vector<Eigen::Vector2d> scan_in_world;
  Eigen::Vector2d robot = Eigen::Vector2d::Zero();
  Eigen::Vector2d goal = Eigen::Vector2d(3.0, 2.6);        // a station behind a visitor
  Eigen::Vector2d far_goal = Eigen::Vector2d(14.0, 14.3);  // a node 20 m away
};

// Range along unit `dir` from the origin to the circle (c, r), or infinity.
double RayCircle(const Eigen::Vector2d& dir, const Eigen::Vector2d& c, double r) {
  const double b = dir.dot(c);
  const double disc = b * b - (c.squaredNorm() - r * r);
  if (disc < 0.0) return std::numeric_limits<double>::infinity();
  const double t = b - std::sqrt(disc);
  return t > 0.0 ? t : std::numeric_limits<double>::infinity();
}

const Scene& TheScene() {
  static const Scene scene = [] {
    Scene s;
    const Eigen::Vector2d visitors[] = {{1.6, 1.3},   {1.0, -1.5}, {-1.8, 0.8},
                                        {-1.0, -2.0}, {2.7, 1.9},  {0.3, 2.4}};
    for (int k = 0; k < kBeams; ++k) {
      const double angle = 2.0 * std::numbers::pi * k / kBeams;
      const Eigen::Vector2d dir(std::cos(angle), std::sin(angle));
      double range = kMaxRange_m;
      if (dir.x() != 0.0) range = std::min(range, kRoomHalfWidth_m / std::abs(dir.x()));
      if (dir.y() != 0.0) range = std::min(range, kRoomHalfHeight_m / std::abs(dir.y()));
      for (const Eigen::Vector2d& v : visitors) {
        range = std::min(range, RayCircle(dir, v, kVisitorRadius_m));
      }
      s.scan_in_world.push_back(s.robot + range * dir);
    }
    return s;
  }();
  return scene;
}

void BM_LocalGridBuild(benchmark::State& state) {
  const Scene& scene = TheScene();
  LocalGrid grid{LocalGridOptions{}};
  for (auto _ : state) {
    grid.Build(scene.robot, scene.scan_in_world);
    benchmark::DoNotOptimize(grid.obstacles().data());
  }
  state.counters["points"] = static_cast<double>(grid.obstacles().size());
  state.counters["cells_per_side"] = grid.cells_per_side();
}
BENCHMARK(BM_LocalGridBuild)->Unit(benchmark::kMicrosecond);

void Nf1Plan(benchmark::State& state, const Eigen::Vector2d& goal) {
  const Scene& scene = TheScene();
  LocalGrid grid{LocalGridOptions{}};
  grid.Build(scene.robot, scene.scan_in_world);
  Nf1Planner planner;
  std::size_t vertices = 0;
  for (auto _ : state) {
    const auto path = planner.Plan(grid, scene.robot, goal, 0);
    if (!path) state.SkipWithError("no NF1 path");
    vertices = path ? path->size() : 0;
    benchmark::DoNotOptimize(vertices);
  }
  state.counters["path_cells"] = static_cast<double>(planner.cell_path().size());
  state.counters["vertices"] = static_cast<double>(vertices);
}

void BM_Nf1DefaultGrid(benchmark::State& state) { Nf1Plan(state, TheScene().goal); }
BENCHMARK(BM_Nf1DefaultGrid)->Unit(benchmark::kMicrosecond);

void BM_Nf1FarGoal(benchmark::State& state) { Nf1Plan(state, TheScene().far_goal); }
BENCHMARK(BM_Nf1FarGoal)->Unit(benchmark::kMicrosecond);

void BM_DistanceFieldBuild(benchmark::State& state) {
  const Scene& scene = TheScene();
  LocalGrid grid{LocalGridOptions{}};
  grid.Build(scene.robot, scene.scan_in_world);
  DistanceField field;
  for (auto _ : state) {
    field.Build(grid);
    benchmark::DoNotOptimize(&field);
  }
}
BENCHMARK(BM_DistanceFieldBuild)->Unit(benchmark::kMicrosecond);

void BM_ElasticBandUpdate(benchmark::State& state) {
  const Scene& scene = TheScene();
  LocalGrid grid{LocalGridOptions{}};
  grid.Build(scene.robot, scene.scan_in_world);
  DistanceField field;
  field.Build(grid);
  Nf1Planner planner;
  const auto path = planner.Plan(grid, scene.robot, scene.goal, 0);
  ElasticBand band;
  if (!path) {
    state.SkipWithError("no NF1 path");
    return;
  }
  band.Reset(*path);
  for (int k = 0; k < kSettleUpdates; ++k) {
    if (!band.Update(scene.robot, field)) {
      state.SkipWithError("band snapped while settling");
      return;
    }
  }
  for (auto _ : state) {
    const bool ok = band.Update(scene.robot, field);
    benchmark::DoNotOptimize(ok);
  }
  state.counters["bubbles"] = static_cast<double>(band.bubbles().size());
  state.counters["band_length_m"] = band.length_m();
}
BENCHMARK(BM_ElasticBandUpdate)->Unit(benchmark::kMicrosecond);

}  // namespace
