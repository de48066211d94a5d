// Global localization (thesis chapter 5) on the Expo hall map (Release, one
// core): hypothesis generation (Algorithm 1) from the six longest lines of a
// scan at the map's first station, at the default limits, and hypothesis
// tracking (Algorithm 2 and the EKF estimate of its supporting set) of one
// hypothesis from the whole scan. Issue 18's budgets: generation median
// <= 5 ms with no limit hit (the thesis: 105-633 ms on 300-380 MHz PowerPCs),
// tracking <= 0.2 ms per hypothesis (the thesis: 10 ms). And the free-space
// constraint (negative evidence) of one hypothesis on one scan, on the Expo
// map (44 segments) and the office floor's (200 features), which it is for.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <string>

#include "core/localization/free_space_constraint.h"
#include "core/localization/global/global_localizer.h"
#include "core/localization/global/interpretation_tree.h"
#include "core/localization/scan_observations.h"
#include "tests/bench/expo_scan.h"

namespace {

using namespace pavilion;

// The first map node whose scan yields at least six lines: the benchmark's view.
core::Pose2 ViewPose(const core::RobotMap& map) {
  for (const core::MapNode& n : map.nodes) {
    const core::LaserScan scan = bench::CastAgainstMap(map, n.pose);
    if (core::ScanObservations(scan, scan, core::LaserSensorOptions{}).observations.size() >= 6) {
      return n.pose;
    }
  }
  return bench::ScanPose(map);
}

// The scan's observations as one local map, its `count` longest lines only
// (0: all).
core::LocalMap ScanLocalMap(const core::RobotMap& map, std::size_t count) {
  const core::LaserScan scan = bench::CastAgainstMap(map, ViewPose(map));
  core::ObservationBatch batch = core::ScanObservations(scan, scan, core::LaserSensorOptions{});
  auto length = [](const core::Observation& o) {
    double l = 0.0;
    for (const core::ObservedSegment& s : o.segments) {
      l = std::max(l, (s.last.position_m - s.first.position_m).norm());
    }
    return l;
  };
  std::stable_sort(batch.observations.begin(), batch.observations.end(),
                   [&](const auto& a, const auto& b) { return length(a) > length(b); });
  if (count > 0 && batch.observations.size() > count) batch.observations.resize(count);
  core::LocalMap local;
  local.stamp_s = batch.stamp_s;
  core::AddToLocalMap(batch, &local);
  return local;
}

void BM_GlobalGeneration(benchmark::State& state) {
  const core::RobotMap map = bench::ExpoMap();
  const core::MeasurementPredictor predictor(map, core::PredictionOptions{0.95, true});
  const core::InterpretationTree tree(predictor);
  const core::LocalMap local = ScanLocalMap(map, static_cast<std::size_t>(state.range(0)));
  core::TreeSearchStats stats;
  std::size_t hypotheses = 0;
  for (auto _ : state) {
    stats = {};
    hypotheses = tree.Generate(local, &stats).size();
    benchmark::DoNotOptimize(hypotheses);
  }
  state.counters["observations"] = static_cast<double>(local.features.size());
  state.counters["tree_nodes"] = static_cast<double>(stats.nodes);
  state.counters["hypotheses"] = static_cast<double>(hypotheses);
  state.counters["limit_hit"] = stats.node_limit_hit || stats.hypothesis_limit_hit ? 1.0 : 0.0;
}
BENCHMARK(BM_GlobalGeneration)
    ->Arg(6)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);

void BM_GlobalTrackOneHypothesis(benchmark::State& state) {
  const core::RobotMap map = bench::ExpoMap();
  const core::MeasurementPredictor predictor(map, core::PredictionOptions{0.95, true});
  const core::InterpretationTree tree(predictor);
  const core::LocalMap local = ScanLocalMap(map, 0);
  // A hypothesis predicted with some doubt: 5 cm and 2 deg (1 sigma).
  const core::PoseWithCovariance predicted{ViewPose(map),
                                           Eigen::Vector3d(0.0025, 0.0025, 0.0012).asDiagonal()};
  core::TreeSearchStats stats;
  std::size_t sets = 0;
  for (auto _ : state) {
    stats = {};
    sets = tree.Track(local, predicted, nullptr, &stats).size();
    benchmark::DoNotOptimize(sets);
  }
  state.counters["observations"] = static_cast<double>(local.features.size());
  state.counters["supporting_sets"] = static_cast<double>(sets);
}
BENCHMARK(BM_GlobalTrackOneHypothesis)->Unit(benchmark::kMicrosecond);

// One hypothesis checked against one 361-reading scan taken at it (every beam
// cast: the cost of the truth, which no early exit shortens). Arg 0: the Expo
// map at its first station; 1: the office floor's map in office_02.
void BM_FreeSpaceCheck(benchmark::State& state) {
  const core::RobotMap map = state.range(0) == 0
                                 ? bench::ExpoMap()
                                 : scenarios::LoadMapFile(std::string(PAVILION_SOURCE_DIR) +
                                                          "/worlds/office_floor/map.yaml");
  const core::Pose2 pose = state.range(0) == 0 ? bench::ScanPose(map) : core::Pose2{42.0, 3.0, 1.2};
  const core::LaserScan scan = bench::CastAgainstMap(map, pose);
  const core::FreeSpaceConstraint constraint(map);
  const core::PoseWithCovariance location{pose, Eigen::Vector3d(1e-4, 1e-4, 3e-5).asDiagonal()};
  core::FreeSpaceCheck check;
  for (auto _ : state) {
    check = constraint.Check(scan, location);
    benchmark::DoNotOptimize(check);
  }
  state.counters["beams"] = check.beams;
  state.counters["see_through"] = check.see_through;
}
BENCHMARK(BM_FreeSpaceCheck)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace
