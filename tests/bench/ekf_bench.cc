// Time of one EKF localization cycle (thesis §4.4.1): measurement prediction
// with visibility tests, matching (strongest observation, chi^2 gate) and the
// iterated estimation with re-prediction after each pairing. The scene: a
// room with a chamfered corner, a partition and two pillars, 10 map lines
// visible from the robot, 8 of them observed with noise drawn from their
// covariance (seeded; one draw ends up outside the 95% gate once the other 7
// are integrated), from a prior 5 cm / 1 deg off. Baseline in the same run:
// prediction alone (the 10 lines with Jacobians, covariances, visibility).
// BM_EkfCycleWithMapCorrelations is the same cycle as the Localizer runs it
// by default (pose-map cross-covariances). BM_LocalizerCycle adds what the Localizer does around
// the cycle: the odometry-buffer look-up at the observation's time stamp (a step split) and
// carrying the correction forward over the 20 odometry steps (100 ms)
// buffered since.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "core/localization/localizer.h"
#include "core/localization/matching.h"
#include "core/localization/measurement_prediction.h"
#include "core/random/random_stream.h"
#include "tests/support/localization_world.h"

namespace {

using namespace pavilion;

constexpr double kDeg = std::numbers::pi / 180.0;

struct Scene {
  core::RobotMap map;
  core::PoseWithCovariance prior;
  core::Pose2 truth;
  core::ObservationBatch batch;
};

const Scene& TheScene() {
  static const Scene scene = [] {
    Scene s;
    s.map = testing::RectangularRoom(-5, -4, 5, 4);
    const Eigen::Vector2d inside(0.0, 0.0);
    // A partition wall (both faces) and two square pillars (four faces each).
    s.map.lines.push_back(testing::MapLineThrough("partition_s", {-5, 2.0}, {-2, 2.0}, inside));
    s.map.lines.push_back(
        testing::MapLineThrough("partition_n", {-5, 2.2}, {-2, 2.2}, {-3.0, 3.0}));
    int pillar = 0;
    for (const Eigen::Vector2d& c : {Eigen::Vector2d(2.5, -1.5), Eigen::Vector2d(-2.5, -2.0)}) {
      ++pillar;
      const Eigen::Vector2d corners[4] = {
          c + Eigen::Vector2d(-0.3, -0.3), c + Eigen::Vector2d(0.3, -0.3),
          c + Eigen::Vector2d(0.3, 0.3), c + Eigen::Vector2d(-0.3, 0.3)};
      for (int i = 0; i < 4; ++i) {
        const Eigen::Vector2d mid = 0.5 * (corners[i] + corners[(i + 1) % 4]);
        s.map.lines.push_back(
            testing::MapLineThrough("pillar" + std::to_string(pillar) + "_" + std::to_string(i),
                                    corners[i], corners[(i + 1) % 4], mid + (mid - c)));
      }
    }
    s.map.lines.push_back(testing::MapLineThrough("chamfer", {4, 4}, {5, 3}, inside));
    s.truth = {0.0, 0.5, 0.3};
    s.prior = {{0.04, 0.53, 0.3 + kDeg},
               Eigen::Vector3d(0.05 * 0.05, 0.05 * 0.05, std::pow(2 * kDeg, 2)).asDiagonal()};
    s.batch.sensor_id = "laser";
    s.batch.view = testing::CentredView();
    s.batch.types = {core::ObservationType::kLine};
    core::RandomStream rng(121, 1);
    const Eigen::Matrix2d R = testing::LineCovariance(0.2 * kDeg, 0.005);
    for (const core::MapLine& l : s.map.lines) {
      if (s.batch.observations.size() == 8) break;
      if (core::LineInChild(l.line, s.truth).r_m > 0.0) {
        s.batch.observations.push_back(testing::ObserveLine(l.line, s.truth, R, &rng));
      }
    }
    return s;
  }();
  return scene;
}

void BM_PredictionOnly(benchmark::State& state) {
  const Scene& s = TheScene();
  const core::MeasurementPredictor predictor(s.map);
  std::vector<core::PredictedMeasurement> out;
  for (auto _ : state) {
    out.clear();
    predictor.PredictVisible(core::ObservationType::kLine, s.prior, s.batch.view, &out);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["predicted"] = static_cast<double>(out.size());
}
BENCHMARK(BM_PredictionOnly)->Unit(benchmark::kMicrosecond);

void BM_EkfCycle(benchmark::State& state) {
  const Scene& s = TheScene();
  const core::MeasurementPredictor predictor(s.map);
  core::IterativeMatcher matcher;
  core::MatchingResult result;
  for (auto _ : state) {
    core::PoseWithCovariance estimate = s.prior;
    result = matcher.MatchAndUpdate(predictor, s.batch, &estimate);
    benchmark::DoNotOptimize(estimate);
  }
  state.counters["predicted"] = result.predictions;
  state.counters["observed"] = result.observations;
  state.counters["matched"] = static_cast<double>(result.matches.size());
}
BENCHMARK(BM_EkfCycle)->Unit(benchmark::kMicrosecond);

// The same cycle with the pose-map cross-covariances (the Localizer's
// default, map_cross_covariance.h): cross terms in S, the Schmidt-Kalman
// update, and (I - W H) applied to the correlations already kept.
void BM_EkfCycleWithMapCorrelations(benchmark::State& state) {
  const Scene& s = TheScene();
  const core::MeasurementPredictor predictor(s.map, core::PredictionOptions{0.95, true});
  core::IterativeMatcher matcher;
  core::MatchingResult result;
  core::PoseMapCrossCovariance correlations(s.map);
  for (auto _ : state) {
    core::PoseWithCovariance estimate = s.prior;
    correlations.Clear();
    result = matcher.MatchAndUpdate(predictor, s.batch, &estimate, &correlations);
    benchmark::DoNotOptimize(estimate);
  }
  state.counters["matched"] = static_cast<double>(result.matches.size());
}
BENCHMARK(BM_EkfCycleWithMapCorrelations)->Unit(benchmark::kMicrosecond);

void BM_LocalizerCycle(benchmark::State& state) {
  const Scene& s = TheScene();
  core::LocalizerOptions options;
  options.odometry_buffer_s = 0.2;
  core::Localizer localizer(s.map, options);
  testing::EncoderStream encoders(25000, options.odometry.left_wheel_radius_m,
                                  options.odometry.right_wheel_radius_m);
  double t = 0.0;
  localizer.AddEncoders(encoders.Step(t, 0, 0));
  localizer.Initialize(s.prior.pose, s.prior.covariance);
  core::ObservationBatch batch = s.batch;
  std::size_t matched = 0;
  for (auto _ : state) {
    state.PauseTiming();
    localizer.Initialize(s.prior.pose, s.prior.covariance);
    for (int k = 0; k < 20; ++k) localizer.AddEncoders(encoders.Step(t += 0.005, 0, 0));
    batch.stamp_s = t - 0.1 + 0.0025;  // 100 ms old, inside an odometry step
    state.ResumeTiming();
    localizer.AddObservations(batch);
    matched = localizer.last_cycle().matches.size();
  }
  state.counters["matched"] = static_cast<double>(matched);
}
BENCHMARK(BM_LocalizerCycle)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
