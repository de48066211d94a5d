// Fleet coordination benchmarks (issue 15, thesis §6.3.5).
//
// BM_FleetTick: one tick of the coordinator for ten robots on the Expo-like
// graph of planning_bench.cc — each robot weights its plan (PlanWeights over
// an 8-node plan) and sends it with its pose, then the server merges the
// outboxes in robot order. Counter: bytes per robot and tick.
//
// BM_FleetPlanOnWeights: one robot's global plan on the superposed weights of
// nine others (AddOthersCosts + PlanGraphPath), the planning a fleet replan
// costs every fleet_replan_s.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "core/random/random_stream.h"
#include "nav/fleet/coordinator.h"
#include "nav/planning/graph_planner.h"
#include "nav/planning/topology_graph.h"

namespace {

using namespace pavilion;

constexpr int kRobots = 10;
constexpr int kPlanNodes = 8;

// A 13 x 4 grid graph over a 26 m x 12 m hall, chains along rows and columns.
nav::TopologyGraph HallGraph() {
  nav::TopologyGraph g;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 13; ++c) {
      std::string id("n");  // by append: GCC 12's -Wrestrict misfires on "n" + to_string
      id.append(std::to_string(r * 13 + c));
      g.AddNode(id, {c * 26.0 / 12, r * 4.0}, r % 3 == 0);
    }
  }
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 13; ++c) {
      const int n = r * 13 + c;
      if (c + 1 < 13) {
        g.AddArc(n, n + 1, 26.0 / 12);
        g.AddArc(n + 1, n, 26.0 / 12);
      }
      if (r + 1 < 4) {
        g.AddArc(n, n + 13, 4.0);
        g.AddArc(n + 13, n, 4.0);
      }
    }
  }
  return g;
}

// Robot k's plan: a row walk of kPlanNodes nodes.
std::vector<int> Plan(int k) {
  std::vector<int> nodes;
  const int row = k % 4;
  for (int i = 0; i < kPlanNodes; ++i) nodes.push_back(row * 13 + (k + i) % 13);
  return nodes;
}

void BM_FleetTick(benchmark::State& state) {
  const nav::TopologyGraph g = HallGraph();
  nav::FleetCoordinator fleet(kRobots, {});
  std::vector<std::vector<int>> plans;
  std::vector<std::vector<Eigen::Vector2d>> positions;
  for (int k = 0; k < kRobots; ++k) {
    plans.push_back(Plan(k));
    positions.emplace_back();
    for (int n : plans.back()) positions.back().push_back(g.position(n));
  }
  double t = 0.0;
  for (auto _ : state) {
    t += 0.1;
    for (int k = 0; k < kRobots; ++k) {
      const Eigen::Vector2d at = positions[k].front() + Eigen::Vector2d(0.01 * t, 0.0);
      nav::FleetMessage m;
      m.path = nav::PlanWeights(at, plans[k], positions[k], fleet.options());
      m.pose = core::Pose2{at.x(), at.y(), 0.0};
      m.speed_mps = 0.5;
      m.reserved_station = plans[k].back();
      fleet.Send(k, std::move(m));
    }
    fleet.Merge();
  }
  std::int64_t bytes = 0;
  for (int k = 0; k < kRobots; ++k) bytes += fleet.bytes_up(k) + fleet.bytes_down(k);
  state.counters["bytes_per_robot_tick"] =
      static_cast<double>(bytes) / (static_cast<double>(fleet.merges()) * kRobots);
}
BENCHMARK(BM_FleetTick);

void BM_FleetPlanOnWeights(benchmark::State& state) {
  const nav::TopologyGraph g = HallGraph();
  nav::FleetCoordinator fleet(kRobots, {});
  for (int k = 1; k < kRobots; ++k) {
    std::vector<Eigen::Vector2d> at;
    for (int n : Plan(k)) at.push_back(g.position(n));
    fleet.Send(k, {nav::PlanWeights(at.front(), Plan(k), at, fleet.options()),
                   std::nullopt,
                   0.0,
                   Plan(k).back(),
                   -1,
                   {}});
  }
  fleet.Merge();
  core::RandomStream random(15, 1);
  std::vector<double> costs;
  for (auto _ : state) {
    const int from = static_cast<int>(random.UniformInt(0, g.node_count() - 1));
    const int to = static_cast<int>(random.UniformInt(0, g.node_count() - 1));
    costs.assign(static_cast<std::size_t>(g.node_count()), 0.0);
    fleet.board().AddOthersCosts(0, fleet.options().occupied_station_cost_m, &costs);
    auto path = nav::PlanGraphPath(g, from, to, costs);
    benchmark::DoNotOptimize(path);
  }
}
BENCHMARK(BM_FleetPlanOnWeights);

}  // namespace
