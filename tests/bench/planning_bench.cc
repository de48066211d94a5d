// Navigation benchmarks (issue 14).
//
// BM_GlobalPlanExpoGraph: one global plan (§6.3.2, priority-first search) on a
// graph shaped like the Expo.02 map (15 station + 37 via nodes, 68 edges over
// a 26 m x 12 m hall; thesis: "a matter of a few milliseconds" on a 380 MHz
// G3) between seeded random station pairs. Baseline in the same run:
// BM_ShortestRouteExpoMap, the id-based wrapper that builds the graph from the
// map on every call.
//
// BM_OmplInitialPath/<planner>: one initial path for the elastic band on an
// 8 m, 5 cm local grid built from 720 scan-like points (a room with a partition
// and six visitors seen by a 360 deg, 0.5 deg laser from the grid's centre),
// start at the robot, goal behind the partition; seeds cycle over 16 values.
// Counters: path length (m) and clearance (m, least distance from the path to
// an obstacle point), averaged over iterations.
#include <benchmark/benchmark.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "core/geometry/segment2.h"
#include "core/random/random_stream.h"
#include "nav/local/local_grid.h"
#include "nav/local/ompl_path_planner.h"
#include "nav/planning/graph_planner.h"
#include "nav/planning/topology_graph.h"
#include "nav/route/route_planner.h"

namespace {

using namespace pavilion;

// The Expo-like topology: 13 x 4 jittered nodes, rows joined as chains and
// rows joined by 20 rungs; 15 of the nodes are stations.
constexpr int kColumns = 13;
constexpr int kRows = 4;
constexpr double kColumnSpacingM = 26.0 / (kColumns - 1);
constexpr double kRowSpacingM = 12.0 / (kRows - 1);
constexpr double kJitterM = 0.4;
constexpr int kStationPairs = 64;

std::string NodeName(int row, int column) {
  std::string name("n");
  name.append(std::to_string(row)).append("_").append(std::to_string(column));
  return name;
}

core::RobotMap ExpoLikeMap() {
  core::RobotMap map;
  map.name = "expo_like";
  core::RandomStream rng(2002, core::RandomStream::StreamId("expo_like_graph"));
  for (int r = 0; r < kRows; ++r) {
    for (int c = 0; c < kColumns; ++c) {
      const bool station = ((r == 0 || r == kRows - 1) && c % 2 == 0) || (r == 1 && c == 6);
      map.nodes.push_back({NodeName(r, c),
                           {c * kColumnSpacingM + rng.Uniform(-kJitterM, kJitterM),
                            r * kRowSpacingM + rng.Uniform(-kJitterM, kJitterM), 0.0},
                           station});
    }
  }
  auto position = [&](int r, int c) { return map.nodes[r * kColumns + c].pose.translation(); };
  auto join = [&](int r0, int c0, int r1, int c1) {
    map.edges.push_back(
        {NodeName(r0, c0), NodeName(r1, c1), (position(r0, c0) - position(r1, c1)).norm()});
  };
  for (int r = 0; r < kRows; ++r) {
    for (int c = 0; c + 1 < kColumns; ++c) join(r, c, r, c + 1);
  }
  for (int r = 0; r + 1 < kRows; ++r) {
    for (int c = 0; c < kColumns; ++c) {
      if ((c + r) % 2 == 0) join(r, c, r + 1, c);
    }
  }
  return map;
}

std::vector<std::pair<int, int>> StationPairs(const nav::TopologyGraph& graph) {
  std::vector<int> stations;
  for (int v = 0; v < graph.node_count(); ++v) {
    if (graph.station(v)) stations.push_back(v);
  }
  core::RandomStream rng(2002, core::RandomStream::StreamId("expo_like_pairs"));
  std::vector<std::pair<int, int>> pairs;
  while (static_cast<int>(pairs.size()) < kStationPairs) {
    const int a = stations[rng.UniformInt(0, static_cast<int>(stations.size()) - 1)];
    const int b = stations[rng.UniformInt(0, static_cast<int>(stations.size()) - 1)];
    if (a != b) pairs.emplace_back(a, b);
  }
  return pairs;
}

void BM_GlobalPlanExpoGraph(benchmark::State& state) {
  const core::RobotMap map = ExpoLikeMap();
  const nav::TopologyGraph graph(map);
  const auto pairs = StationPairs(graph);
  std::size_t k = 0;
  double nodes = 0.0;
  for (auto _ : state) {
    const auto& [from, to] = pairs[k++ % pairs.size()];
    auto path = nav::PlanGraphPath(graph, from, to);
    benchmark::DoNotOptimize(path);
    nodes += static_cast<double>(path->nodes.size());
  }
  state.counters["graph_nodes"] = graph.node_count();
  state.counters["graph_edges"] = static_cast<double>(map.edges.size());
  state.counters["path_nodes"] = benchmark::Counter(nodes, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_GlobalPlanExpoGraph)->Unit(benchmark::kMicrosecond);

void BM_ShortestRouteExpoMap(benchmark::State& state) {
  const core::RobotMap map = ExpoLikeMap();
  const nav::TopologyGraph graph(map);
  const auto pairs = StationPairs(graph);
  std::size_t k = 0;
  for (auto _ : state) {
    const auto& [from, to] = pairs[k++ % pairs.size()];
    auto route = nav::ShortestRoute(map, graph.id(from), graph.id(to));
    benchmark::DoNotOptimize(route);
  }
}
BENCHMARK(BM_ShortestRouteExpoMap)->Unit(benchmark::kMicrosecond);

// The local scene: walls and visitors around the robot at the origin.
constexpr int kLaserRays = 720;  // two 180 deg scanners at 0.5 deg
constexpr double kLaserRangeM = 8.0;
constexpr int kVisitors = 6;
constexpr double kVisitorRadiusM = 0.2;
constexpr int kSeedCycle = 16;

std::vector<Eigen::Vector2d> ScanLikePoints() {
  const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> walls = {
      {{-3.6, -3.6}, {3.6, -3.6}},
      {{3.6, -3.6}, {3.6, 3.6}},
      {{3.6, 3.6}, {-3.6, 3.6}},
      {{-3.6, 3.6}, {-3.6, -3.6}},
      {{-3.6, 0.8}, {1.0, 0.8}}};
  core::RandomStream rng(14, core::RandomStream::StreamId("scan_like_visitors"));
  std::vector<Eigen::Vector2d> visitors;
  while (static_cast<int>(visitors.size()) < kVisitors) {
    const Eigen::Vector2d p(rng.Uniform(-3.0, 3.0), rng.Uniform(-3.0, 0.3));
    if (p.norm() > 1.2) visitors.push_back(p);  // not on the robot
  }
  const Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  std::vector<Eigen::Vector2d> points;
  for (int k = 0; k < kLaserRays; ++k) {
    const double angle = 2.0 * std::numbers::pi * k / kLaserRays;
    const Eigen::Vector2d end = kLaserRangeM * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    double t = std::numeric_limits<double>::infinity();
    for (const auto& [a, b] : walls) t = std::min(t, core::RaySegmentHit(origin, end, a, b));
    for (const Eigen::Vector2d& v : visitors) {
      for (double hit : core::LineCircleHits(origin, end, v, kVisitorRadiusM)) {
        if (hit >= 0.0 && hit <= 1.0) t = std::min(t, hit);
      }
    }
    if (std::isfinite(t)) points.push_back(t * end);
  }
  return points;
}

double Clearance(const std::vector<Eigen::Vector2d>& path,
                 const std::vector<Eigen::Vector2d>& obstacles) {
  double clearance = std::numeric_limits<double>::infinity();
  for (std::size_t k = 1; k < path.size(); ++k) {
    for (const Eigen::Vector2d& p : obstacles) {
      clearance = std::min(clearance, core::PointSegmentDistance(p, path[k - 1], path[k]));
    }
  }
  return clearance;
}

void BM_OmplInitialPath(benchmark::State& state, nav::OmplPlannerType type) {
  nav::LocalGrid grid(nav::LocalGridOptions{});
  grid.Build(Eigen::Vector2d::Zero(), ScanLikePoints());
  nav::OmplPlannerOptions options;
  options.type = type;
  nav::OmplPathPlanner planner(options);
  const Eigen::Vector2d start = Eigen::Vector2d::Zero();
  const Eigen::Vector2d goal(-2.5, 2.4);
  std::uint64_t seed = 0;
  double length_m = 0.0;
  double clearance_m = 0.0;
  double failures = 0.0;
  for (auto _ : state) {
    auto path = planner.Plan(grid, start, goal, seed++ % kSeedCycle);
    benchmark::DoNotOptimize(path);
    state.PauseTiming();
    if (path) {
      length_m += nav::PathLength(*path);
      clearance_m += Clearance(*path, grid.obstacles());
    } else {
      ++failures;
    }
    state.ResumeTiming();
  }
  state.counters["points"] = static_cast<double>(grid.obstacles().size());
  state.counters["length_m"] = benchmark::Counter(length_m, benchmark::Counter::kAvgIterations);
  state.counters["clearance_m"] =
      benchmark::Counter(clearance_m, benchmark::Counter::kAvgIterations);
  state.counters["failures"] = failures;
  state.counters["straight_m"] = (goal - start).norm();
}
BENCHMARK_CAPTURE(BM_OmplInitialPath, rrt_connect, nav::OmplPlannerType::kRrtConnect)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_OmplInitialPath, rrt_star, nav::OmplPlannerType::kRrtStar)
    ->Unit(benchmark::kMillisecond);

}  // namespace
