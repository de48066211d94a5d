// Monte Carlo localization baseline on the Expo hall map (Release, one core):
// the sensor update (likelihood field scoring of 60 beams, Augmented_MCL
// averages, low-variance resampling, estimate) for 500, 1000 and 2000
// particles, the motion update of one encoder reading, and the likelihood
// field build. The scan is ray cast against the map's own geometry (361
// readings over 180 deg, 8 m) at the first station node of the map.
#include <benchmark/benchmark.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "core/geometry/segment2.h"
#include "core/localization/mcl/likelihood_field.h"
#include "core/localization/mcl/monte_carlo_localizer.h"
#include "scenarios/maps/map_file.h"
#include "tests/bench/expo_scan.h"

namespace {

using namespace pavilion;
using bench::CastAgainstMap;
using bench::ExpoMap;
using bench::ScanPose;

// A cloud of 0.3 m and 0.2 rad (1 sigma) around the scan pose: a filter
// that is tracking with some doubt.
core::PoseWithCovariance Cloud(const core::Pose2& pose) {
  return {pose, Eigen::Vector3d(0.09, 0.09, 0.04).asDiagonal()};
}

void BM_MclSensorUpdate(benchmark::State& state) {
  const core::RobotMap map = ExpoMap();
  const core::Pose2 pose = ScanPose(map);
  const core::LaserScan scan = CastAgainstMap(map, pose);
  core::MonteCarloOptions options;
  options.particles = static_cast<int>(state.range(0));
  core::MonteCarloLocalizer mcl(map, core::EncoderOdometryOptions{}, options);
  mcl.Initialize(Cloud(pose));
  mcl.AddScan(scan);  // builds the per-cell log-likelihood table once
  for (auto _ : state) {
    state.PauseTiming();
    mcl.Initialize(Cloud(pose));  // the next scan updates
    state.ResumeTiming();
    benchmark::DoNotOptimize(mcl.AddScan(scan));
  }
  state.counters["beams"] = mcl.last_beams();
  state.counters["free_cells"] = mcl.free_space().free_cells();
  state.counters["ns_per_particle_beam"] = benchmark::Counter(
      static_cast<double>(options.particles) * mcl.last_beams(),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_MclSensorUpdate)->Arg(500)->Arg(1000)->Arg(2000)->Unit(benchmark::kMicrosecond);

// One encoder reading (10 mm of travel per wheel) moving 1000 particles.
void BM_MclMotionUpdate(benchmark::State& state) {
  const core::RobotMap map = ExpoMap();
  core::MonteCarloLocalizer mcl(map, core::EncoderOdometryOptions{}, core::MonteCarloOptions{});
  mcl.Initialize(Cloud(ScanPose(map)));
  constexpr int kTicksPerRevolution = 4096;
  constexpr std::int64_t kTicksPerStep = 72;  // ~10 mm at r = 0.09 m
  core::EncoderReading reading{0.0, 0, 0, kTicksPerRevolution};
  mcl.AddEncoders(reading);
  for (auto _ : state) {
    reading.left_ticks += kTicksPerStep;
    reading.right_ticks += kTicksPerStep;
    mcl.AddEncoders(reading);
  }
  benchmark::DoNotOptimize(mcl.particles().data());
}
BENCHMARK(BM_MclMotionUpdate)->Unit(benchmark::kMicrosecond);

void BM_MclLikelihoodFieldBuild(benchmark::State& state) {
  const core::RobotMap map = ExpoMap();
  long cells = 0;
  for (auto _ : state) {
    const core::LikelihoodField field(map);
    cells = field.cell_count();
    benchmark::DoNotOptimize(cells);
  }
  state.counters["cells"] = static_cast<double>(cells);
}
BENCHMARK(BM_MclLikelihoodFieldBuild)->Unit(benchmark::kMillisecond);

}  // namespace
