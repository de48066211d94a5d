// The Localizer (thesis §4.4) end to end without the simulator: synthetic
// maps, encoder streams and observations generated from the true poses.
#include "core/localization/localizer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/math/chi_square.h"
#include "core/random/random_stream.h"
#include "tests/support/localization_world.h"
#include "tests/support/synthetic_room.h"

namespace pavilion::core {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr int kTicksPerRevolution = 25000;
constexpr double kWheelRadiusM = 0.09;
constexpr double kWheelbaseM = 0.5;
constexpr double kOdometryPeriodS = 0.005;  // 200 Hz (robox.yaml, §4.4.3)
// ~0.3 m/s: 66 ticks of 22.6 um per 5 ms.
constexpr int kCruiseTicks = 66;
// An extracted line's covariance (sigma_alpha 0.2 deg, sigma_r 5 mm).
const Eigen::Matrix2d kLineR = testing::LineCovariance(0.2 * kDeg, 0.005);

LocalizerOptions BaseOptions(double k_m = 5e-6) {
  LocalizerOptions o;
  o.odometry = {kWheelRadiusM, kWheelRadiusM, kWheelbaseM, k_m, k_m};
  return o;
}

// The true robot, driven by whole encoder ticks. With no noise the filter's
// odometry model reproduces its motion exactly.
struct TrueRobot {
  explicit TrueRobot(const Pose2& start) : pose(start) {}

  // One odometry period; with `rng`, the true wheel travel departs from the
  // measured one by N(0, k|s|) per wheel (eq. 2.9).
  EncoderReading Step(std::int64_t left, std::int64_t right, RandomStream* rng = nullptr,
                      double k_m = 0.0) {
    stamp_s += kOdometryPeriodS;
    WheelTravel actual = encoders.Travel(left, right);
    if (rng != nullptr) {
      actual.left_m += rng->Normal(0.0, std::sqrt(k_m * std::abs(actual.left_m)));
      actual.right_m += rng->Normal(0.0, std::sqrt(k_m * std::abs(actual.right_m)));
    }
    last_travel = actual;
    previous = pose;
    pose = DiffDriveStep(pose, actual, kWheelbaseM);
    return encoders.Step(stamp_s, left, right);
  }
  // The true pose a fraction f into the last step (the piecewise model).
  Pose2 Within(double f) const {
    return DiffDriveStep(previous, {f * last_travel.left_m, f * last_travel.right_m}, kWheelbaseM);
  }
  EncoderReading Start() { return encoders.Step(stamp_s, 0, 0); }

  Pose2 pose;
  Pose2 previous;
  WheelTravel last_travel;
  double stamp_s = 0.0;
  testing::EncoderStream encoders{kTicksPerRevolution, kWheelRadiusM, kWheelRadiusM};
};

ObservationBatch LineBatch(const RobotMap& map, const Pose2& truth, double stamp_s,
                           const SensorView& view, RandomStream* rng = nullptr,
                           const Eigen::Matrix2d& R = kLineR) {
  ObservationBatch b;
  b.sensor_id = "laser";
  b.stamp_s = stamp_s;
  b.view = view;
  b.types = {ObservationType::kLine};
  b.observations = testing::ObserveVisibleLines(map, truth * view.robot_from_sensor, R, rng,
                                                view.perception_radius_m);
  return b;
}

SensorView MountedView() {
  SensorView v = testing::CentredView();
  v.robot_from_sensor = {0.2, 0.0, 0.0};
  return v;
}

Eigen::Vector3d Error(const Pose2& estimate, const Pose2& truth) {
  return {estimate.x_m - truth.x_m, estimate.y_m - truth.y_m,
          NormalizeAngle(estimate.theta_rad - truth.theta_rad)};
}

// Perfect odometry and noise-free line observations in a square room: the
// estimate stays on the truth (1e-6) over a 30 s loop with turns.
TEST(LocalizerTest, PerfectDataKeepsTheEstimateOnTheTruth) {
  const RobotMap map = testing::RectangularRoom(-4, -4, 4, 4);
  Localizer localizer(map, BaseOptions());
  TrueRobot robot({-1.5, -1.5, 0.0});
  localizer.AddEncoders(robot.Start());
  localizer.Initialize(robot.pose, Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal());
  int step = 0;
  int cycles = 0;
  for (int leg = 0; leg < 4; ++leg) {
    for (int phase = 0; phase < 2; ++phase) {
      const int steps = phase == 0 ? 1000 : 579;  // 1.5 m straight, ~90 deg on the spot
      for (int k = 0; k < steps; ++k) {
        const EncoderReading reading =
            phase == 0 ? robot.Step(kCruiseTicks, kCruiseTicks) : robot.Step(-30, 30);
        localizer.AddEncoders(reading);
        if (++step % 20 == 0) {  // 10 Hz
          ASSERT_EQ(
              localizer.AddObservations(LineBatch(map, robot.pose, reading.stamp_s, MountedView())),
              ObservationStatus::kIntegrated);
          ++cycles;
          EXPECT_EQ(localizer.last_cycle().matches.size(), 4u);
          EXPECT_LT(Error(localizer.estimate().pose, robot.pose).cwiseAbs().maxCoeff(), 1e-6)
              << "at step " << step;
        }
      }
    }
  }
  EXPECT_EQ(localizer.counters().cycles, cycles);
  EXPECT_EQ(localizer.status().state, LocalizationState::kTracking);
}

// From a 30 cm / 5 deg initial error, with three non-parallel walls in view,
// the estimate is within 2 cm / 0.5 deg of the truth in at most 10 cycles —
// with noise-free observations and with noise drawn from their covariance.
TEST(LocalizerTest, ConvergesFromThirtyCentimetresAndFiveDegrees) {
  RobotMap map;
  map.lines.push_back(testing::MapLineThrough("east", {4, -5}, {4, 5}, {0, 0}));
  map.lines.push_back(testing::MapLineThrough("north", {-5, 3}, {5, 3}, {0, 0}));
  map.lines.push_back(testing::MapLineThrough("diagonal", {-3, 0}, {0, -3}, {0, 0}));
  for (bool noisy : {false, true}) {
    RandomStream rng(91, noisy ? 2 : 1);
    Localizer localizer(map, BaseOptions());
    TrueRobot robot({0.0, 0.0, 0.0});
    localizer.AddEncoders(robot.Start());
    const Pose2 start{robot.pose.x_m + 0.20, robot.pose.y_m - 0.22, 5.0 * kDeg};  // 0.297 m
    localizer.Initialize(start, Eigen::Vector3d(0.09, 0.09, std::pow(5.0 * kDeg, 2)).asDiagonal());
    int converged_at = -1;
    for (int cycle = 1; cycle <= 10 && converged_at < 0; ++cycle) {
      EncoderReading reading;
      for (int k = 0; k < 20; ++k) reading = robot.Step(22, 22);  // 0.1 m/s
      localizer.AddEncoders(reading);
      localizer.AddObservations(
          LineBatch(map, robot.pose, reading.stamp_s, MountedView(), noisy ? &rng : nullptr));
      const Eigen::Vector3d e = Error(localizer.estimate().pose, robot.pose);
      if (e.head<2>().norm() < 0.02 && std::abs(e.z()) < 0.5 * kDeg) converged_at = cycle;
    }
    EXPECT_GT(converged_at, 0) << (noisy ? "noisy" : "noise-free");
    EXPECT_EQ(localizer.last_cycle().matches.size(), 3u);
  }
}

// Pose covariance in the robot frame: (frontal, lateral) standard deviations.
Eigen::Vector2d FrontalLateralSigma(const PoseWithCovariance& s) {
  const double c = std::cos(s.pose.theta_rad);
  const double si = std::sin(s.pose.theta_rad);
  const Eigen::Vector2d f(c, si);
  const Eigen::Vector2d l(-si, c);
  const Eigen::Matrix2d P = s.covariance.topLeftCorner<2, 2>();
  return {std::sqrt(f.dot(P * f)), std::sqrt(l.dot(P * l))};
}

// A corridor of two parallel walls (thesis §4.5.1, Table 4.1, Fig. 4.4): the
// lines bound the lateral and angular uncertainty while the frontal one grows
// with the distance driven. Vertical edges from a camera, integrated after
// the laser in the same cycle (§4.4.2), bound the frontal one too (Fig. 4.5).
TEST(LocalizerTest, CorridorBoundsLateralButNotFrontalUncertainty) {
  RobotMap map;
  map.lines.push_back(testing::MapLineThrough("left", {-10, 1.5}, {100, 1.5}, {0, 0}));
  map.lines.push_back(testing::MapLineThrough("right", {-10, -1.5}, {100, -1.5}, {0, 0}));
  for (int x = 0; x <= 30; x += 2) {  // door frames every 2 m on the left wall
    map.points.push_back(
        {"edge" + std::to_string(x), {{x + 0.5, 1.5}, Eigen::Matrix2d::Zero()}, 0});
  }
  for (bool with_edges : {false, true}) {
    Localizer localizer(map, BaseOptions(2e-5));
    TrueRobot robot({0.0, 0.0, 0.0});
    localizer.AddEncoders(robot.Start());
    localizer.Initialize(robot.pose, Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal());
    SensorView camera = testing::CentredView(6.0);
    camera.min_bearing_rad = -30 * kDeg;  // forward camera, 60 deg field of view
    camera.max_bearing_rad = 30 * kDeg;
    double previous_frontal = 0.0;
    Eigen::Vector2d sigma;
    for (int cycle = 0; cycle < 200; ++cycle) {  // 20 s at 0.3 m/s: 6 m
      EncoderReading reading;
      for (int k = 0; k < 20; ++k) reading = robot.Step(kCruiseTicks, kCruiseTicks);
      localizer.AddEncoders(reading);
      localizer.AddObservations(LineBatch(map, robot.pose, reading.stamp_s, MountedView()));
      if (with_edges) {
        ObservationBatch edges;
        edges.sensor_id = "camera";
        edges.stamp_s = reading.stamp_s;
        edges.view = camera;
        edges.types = {ObservationType::kVerticalEdge};
        for (const MapPoint& p : map.points) {
          const Eigen::Vector2d q = robot.pose.Inverse() * p.point.position_m;
          const double bearing = std::atan2(q.y(), q.x());
          if (q.norm() > 6.0 || std::abs(bearing) > 30 * kDeg) continue;
          Observation o;
          o.type = ObservationType::kVerticalEdge;
          o.z = {bearing, 0.0};
          o.covariance(0, 0) = std::pow(0.3 * kDeg, 2);
          edges.observations.push_back(o);
        }
        localizer.AddObservations(edges);
      }
      sigma = FrontalLateralSigma(localizer.estimate());
      if (!with_edges) {
        EXPECT_GE(sigma.x(), previous_frontal - 1e-15) << "cycle " << cycle;
      }
      previous_frontal = sigma.x();
      EXPECT_LT(sigma.y(), 0.006) << "cycle " << cycle;
      EXPECT_LT(std::sqrt(localizer.estimate().covariance(2, 2)), 0.3 * kDeg);
    }
    if (with_edges) {
      EXPECT_LT(sigma.x(), 0.01);
    } else {
      // The walls say nothing along the corridor: the frontal variance is
      // odometry's alone, 1e-4 + (k/4)(S_r + S_l) for straight travel (eq. 2.13).
      const double travelled = 2.0 * 200 * 20 * robot.encoders.Travel(kCruiseTicks, 0).left_m;
      EXPECT_NEAR(sigma.x(), std::sqrt(1e-4 + 0.25 * 2e-5 * travelled), 1e-9);
      EXPECT_GT(sigma.x(), 10.0 * sigma.y());
    }
    EXPECT_LT(Error(localizer.estimate().pose, robot.pose).cwiseAbs().maxCoeff(), 1e-6);
  }
}

// Consistency (Bar-Shalom): over 200 Monte-Carlo runs with odometry noise
// drawn from the wheel-space model (eq. 2.9, propagated by eq. 2.13) and line
// observations drawn from their covariance, stamped between encoder readings
// and delivered 15 ms late, the run-averaged NEES at each of the 40 cycles
// lies in the two-sided 95% band of chi^2(3R)/R, R = 200, at about the rate
// that band promises.
// The ANEES at each of `kMonteCarloCycles` cycles over `runs` Monte-Carlo
// runs: a robot on an arc with wheel noise (10x the thesis' k), delayed line
// observations of a rectangular room. With map_sigma_alpha/map_sigma_r > 0,
// each run gives the robot a map whose lines' (alpha, r) depart from the true
// room by one draw of that covariance (a fresh hand measurement per run),
// while the observations come from the true room.
constexpr int kMonteCarloCycles = 40;

std::vector<double> MonteCarloAnees(int runs, double map_sigma_alpha_rad, double map_sigma_r_m,
                                    bool map_correlations) {
  constexpr double kNoiseK = 5e-5;
  const RobotMap room = testing::RectangularRoom(-4, -3, 4, 3);
  const Eigen::Matrix2d R = testing::LineCovariance(0.5 * kDeg, 0.01);
  const Eigen::Matrix2d M = testing::LineCovariance(map_sigma_alpha_rad, map_sigma_r_m);
  // The validation gate truncates the innovations it accepts, so a gated
  // filter is slightly optimistic: at alpha = 0.95 the ANEES comes out ~10%
  // high (3.30 here; 3.03 at 0.999). The estimator, not the gate, is under
  // test, so the gate is opened to alpha = 0.999.
  LocalizerOptions options = BaseOptions(kNoiseK);
  options.significance = 0.999;
  options.map_correlations = map_correlations;
  std::vector<double> nees_sum(kMonteCarloCycles, 0.0);
  RandomStream rng(101, 1);
  for (int run = 0; run < runs; ++run) {
    RobotMap map = room;
    for (MapLine& line : map.lines) {
      const Eigen::Vector2d error = testing::SampleGaussian<2>(M, rng);
      line.line.alpha_rad = NormalizeAngle(line.line.alpha_rad + error.x());
      line.line.r_m += error.y();
      line.line.covariance = M;
    }
    Localizer localizer(map, options);
    const Eigen::Matrix3d P0 =
        Eigen::Vector3d(0.02 * 0.02, 0.02 * 0.02, std::pow(kDeg, 2)).asDiagonal();
    TrueRobot robot({-1.0, -1.0, 0.3});
    localizer.AddEncoders(robot.Start());
    const Eigen::Vector3d e0 = testing::SampleGaussian<3>(P0, rng);
    localizer.Initialize(
        {robot.pose.x_m + e0.x(), robot.pose.y_m + e0.y(), robot.pose.theta_rad + e0.z()}, P0);
    std::vector<ObservationBatch> in_flight;
    int cycle = 0;
    for (int step = 1; step <= 20 * kMonteCarloCycles + 3; ++step) {
      const EncoderReading reading = robot.Step(50, 70, &rng, kNoiseK);  // an arc
      if (step % 20 == 10) {  // observation 2.5 ms into this step
        const Pose2 at = robot.Within(0.5);
        in_flight.push_back(
            LineBatch(room, at, reading.stamp_s - 0.5 * kOdometryPeriodS, MountedView(), &rng, R));
      }
      localizer.AddEncoders(reading);
      if (step % 20 == 13 && !in_flight.empty()) {  // delivered 15 ms later
        EXPECT_EQ(localizer.AddObservations(in_flight.front()), ObservationStatus::kIntegrated);
        in_flight.erase(in_flight.begin());
        if (cycle < kMonteCarloCycles) {
          nees_sum[cycle++] += testing::Nees(localizer.estimate(), robot.pose);
        }
      }
    }
    EXPECT_EQ(cycle, kMonteCarloCycles);
  }
  for (double& s : nees_sum) s /= runs;
  return nees_sum;
}

// Cycles whose ANEES lies in the two-sided 95% band of `runs` runs.
int InsideBand(const std::vector<double>& anees, int runs, double* mean) {
  const double lo = ChiSquareQuantile(0.025, 3 * runs) / runs;
  const double hi = ChiSquareQuantile(0.975, 3 * runs) / runs;
  int inside = 0;
  *mean = 0.0;
  for (double a : anees) {
    inside += a >= lo && a <= hi;
    *mean += a / static_cast<double>(anees.size());
  }
  return inside;
}

TEST(LocalizerTest, MonteCarloNeesIsConsistent) {
  constexpr int kRuns = 200;
  double mean = 0.0;
  const int inside = InsideBand(MonteCarloAnees(kRuns, 0.0, 0.0, true), kRuns, &mean);
  RecordProperty("anees_mean", std::to_string(mean));
  // 95% expected; below 85% (34 of 40) is > 3 binomial sigma off.
  EXPECT_GE(inside, 34) << "mean ANEES " << mean;
  EXPECT_GT(mean, ChiSquareQuantile(0.025, 3 * kRuns) / kRuns);
  EXPECT_LT(mean, ChiSquareQuantile(0.975, 3 * kRuns) / kRuns);
}

// A map measured to 1 cm and 0.3 deg (comparable to one observation's R, far
// coarser than 40 cycles of them): the map's error is the same at every
// cycle. With the pose-map cross-covariances (map_cross_covariance.h) the
// filter stays consistent; the thesis' filter, which adds the map covariance
// to every innovation as if it were drawn afresh (eq. 4.9), grows
// overconfident as the cycles average the observation noise away.
TEST(LocalizerTest, MonteCarloNeesIsConsistentWithAHandMeasuredMap) {
  constexpr int kRuns = 200;
  const double lo = ChiSquareQuantile(0.025, 3 * kRuns) / kRuns;
  const double hi = ChiSquareQuantile(0.975, 3 * kRuns) / kRuns;
  double mean = 0.0;
  const int inside = InsideBand(MonteCarloAnees(kRuns, 0.3 * kDeg, 0.01, true), kRuns, &mean);
  double thesis_mean = 0.0;
  const std::vector<double> thesis = MonteCarloAnees(kRuns, 0.3 * kDeg, 0.01, false);
  InsideBand(thesis, kRuns, &thesis_mean);
  std::printf(
      "[ info ] ANEES with map correlations %.2f (%d of %d cycles in [%.2f, %.2f]); "
      "thesis filter %.2f, at the last cycle %.2f\n",
      mean, inside, kMonteCarloCycles, lo, hi, thesis_mean, thesis.back());
  EXPECT_GE(inside, 34) << "mean ANEES " << mean;
  EXPECT_GT(mean, lo);
  EXPECT_LT(mean, hi);
  EXPECT_GT(thesis.back(), 2.0 * hi);  // the inconsistency the correlations remove
}

// §4.4.3: an observation stamped T in the past is matched against the state
// predicted at T. With no motion since T, that is the same as integrating it
// now.
TEST(LocalizerTest, DelayedObservationWithoutMotionEqualsImmediate) {
  const RobotMap map = testing::RectangularRoom(-4, -3, 4, 3);
  const Pose2 truth{0.5, -0.2, 0.4};
  const Pose2 start{0.58, -0.15, 0.4 + 2.0 * kDeg};
  const Eigen::Matrix3d P0 = Eigen::Vector3d(0.01, 0.01, 0.003).asDiagonal();
  const auto run = [&](double observation_stamp_s) {
    Localizer localizer(map, BaseOptions());
    TrueRobot robot(truth);
    localizer.AddEncoders(robot.Start());
    localizer.Initialize(start, P0);
    for (int k = 0; k < 200; ++k) localizer.AddEncoders(robot.Step(0, 0));  // 1 s standing
    EXPECT_EQ(localizer.AddObservations(LineBatch(map, truth, observation_stamp_s, MountedView())),
              ObservationStatus::kIntegrated);
    return localizer.estimate();
  };
  const PoseWithCovariance delayed = run(0.5);
  const PoseWithCovariance immediate = run(200 * kOdometryPeriodS);
  EXPECT_LT(Error(delayed.pose, immediate.pose).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((delayed.covariance - immediate.covariance).cwiseAbs().maxCoeff(), 1e-18);
  EXPECT_GT(Error(start, truth).norm(), 10 * Error(delayed.pose, truth).norm());
}

// §4.4.3: the correction made at T and carried forward by the buffered
// odometry equals what a filter gets that processed every input in time
// order — for stamps on and between encoder readings — whereas integrating
// the late observation as if taken now does not.
TEST(LocalizerTest, CarriedForwardCorrectionMatchesTimeOrderedFilter) {
  const RobotMap map = testing::RectangularRoom(-4, -3, 4, 3);
  const Pose2 start_truth{-1.0, 0.0, 0.2};
  const Pose2 start{-0.95, 0.04, 0.2 - 1.5 * kDeg};
  const Eigen::Matrix3d P0 = Eigen::Vector3d(0.01, 0.01, 0.003).asDiagonal();
  for (double fraction : {0.0, 0.4}) {  // observation stamp: on / inside an odometry step
    // All inputs of one run: encoder readings and batches with their stamps.
    TrueRobot robot(start_truth);
    const EncoderReading first = robot.Start();
    std::vector<EncoderReading> readings;
    std::vector<ObservationBatch> batches;
    for (int step = 1; step <= 400; ++step) {
      readings.push_back(robot.Step(60, 75));
      if (step % 20 == 0 && step <= 380) {
        const double stamp = readings.back().stamp_s - (1.0 - fraction) * kOdometryPeriodS;
        batches.push_back(LineBatch(map, robot.Within(fraction),
                                    fraction == 0.0 ? readings[step - 2].stamp_s : stamp,
                                    MountedView()));
      }
    }
    const auto fresh = [&](Localizer& l) {
      l.AddEncoders(first);
      l.Initialize(start, P0);
    };
    // In time order: a batch is handed over before the encoder reading that
    // reaches its stamp (integrated at once when odometry is already there,
    // otherwise deferred until that reading).
    Localizer ordered(map, BaseOptions());
    fresh(ordered);
    std::size_t next = 0;
    for (const EncoderReading& r : readings) {
      while (next < batches.size() && batches[next].stamp_s <= r.stamp_s) {
        ordered.AddObservations(batches[next++]);
      }
      ordered.AddEncoders(r);
    }
    // Late: each batch 12 readings (60 ms) after its stamp.
    Localizer late(map, BaseOptions());
    Localizer naive(map, BaseOptions());
    fresh(late);
    fresh(naive);
    next = 0;
    for (const EncoderReading& r : readings) {
      late.AddEncoders(r);
      naive.AddEncoders(r);
      if (next < batches.size() && r.stamp_s >= batches[next].stamp_s + 0.06) {
        EXPECT_EQ(late.AddObservations(batches[next]), ObservationStatus::kIntegrated);
        ObservationBatch now = batches[next];
        now.stamp_s = r.stamp_s;
        naive.AddObservations(now);
        ++next;
      }
    }
    ASSERT_EQ(next, batches.size());
    EXPECT_EQ(ordered.counters().cycles, late.counters().cycles);
    EXPECT_LT(Error(late.estimate().pose, ordered.estimate().pose).cwiseAbs().maxCoeff(), 1e-12)
        << "fraction " << fraction;
    EXPECT_LT((late.estimate().covariance - ordered.estimate().covariance).cwiseAbs().maxCoeff(),
              1e-15);
    EXPECT_LT(Error(late.estimate().pose, robot.pose).head<2>().norm(), 0.005);
    EXPECT_GT(Error(naive.estimate().pose, late.estimate().pose).head<2>().norm(), 0.005);
  }
}

// Batches stamped after the latest encoder reading wait for odometry; those
// older than the buffer or than an integrated batch are refused; nothing is
// integrated before Initialize; bad input throws.
TEST(LocalizerTest, HandlesObservationTimingAndBadInput) {
  const RobotMap map = testing::RectangularRoom(-4, -3, 4, 3);
  LocalizerOptions options = BaseOptions();
  options.odometry_buffer_s = 0.5;
  Localizer localizer(map, options);
  TrueRobot robot({0, 0, 0});
  localizer.AddEncoders(robot.Start());
  EXPECT_EQ(localizer.AddObservations(LineBatch(map, robot.pose, 0.0, MountedView())),
            ObservationStatus::kNotInitialized);
  localizer.Initialize(robot.pose, 1e-4 * Eigen::Matrix3d::Identity());
  for (int k = 0; k < 200; ++k) localizer.AddEncoders(robot.Step(20, 20));  // to t = 1 s
  EXPECT_EQ(localizer.AddObservations(LineBatch(map, robot.pose, 0.3, MountedView())),
            ObservationStatus::kTooOld);
  EXPECT_EQ(localizer.AddObservations(LineBatch(map, robot.pose, 0.9, MountedView())),
            ObservationStatus::kIntegrated);
  EXPECT_EQ(localizer.AddObservations(LineBatch(map, robot.pose, 0.8, MountedView())),
            ObservationStatus::kOutOfOrder);
  TrueRobot ahead = robot;  // where the robot will be two readings later
  ahead.Step(20, 20);
  ahead.Step(20, 20);
  EXPECT_EQ(localizer.AddObservations(LineBatch(map, ahead.pose, ahead.stamp_s, MountedView())),
            ObservationStatus::kDeferred);
  EXPECT_EQ(localizer.counters().cycles, 1);
  localizer.AddEncoders(robot.Step(20, 20));
  EXPECT_EQ(localizer.counters().cycles, 1);
  localizer.AddEncoders(robot.Step(20, 20));
  EXPECT_EQ(localizer.counters().cycles, 2);
  EXPECT_EQ(localizer.last_cycle().matches.size(), 4u);
  const LocalizerCounters& c = localizer.counters();
  EXPECT_EQ(c.too_old, 1);
  EXPECT_EQ(c.out_of_order, 1);
  EXPECT_EQ(c.deferred, 1);
  EXPECT_EQ(c.matches, 8);

  EncoderReading backwards = robot.Step(0, 0);
  backwards.stamp_s -= 1.0;
  EXPECT_THROW(localizer.AddEncoders(backwards), std::invalid_argument);
  ObservationBatch bad = LineBatch(map, robot.pose, robot.stamp_s, MountedView());
  bad.observations[0].z[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(localizer.AddObservations(bad), std::invalid_argument);
  bad = LineBatch(map, robot.pose, robot.stamp_s, MountedView());
  bad.view.perception_radius_m = -1.0;
  EXPECT_THROW(localizer.AddObservations(bad), std::invalid_argument);
}

// Sequential integration in time-stamp order (§4.4.3): a batch stamped while
// a slow scan still waits for odometry to cover its sweep waits behind it,
// instead of being integrated first and making the scan out of order.
TEST(LocalizerTest, LaterBatchesWaitBehindAWaitingScan) {
  const RobotMap map = testing::RectangularRoom(-4, -3, 4, 3);
  Localizer localizer(map, BaseOptions());
  TrueRobot robot({0, 0, 0});
  localizer.AddEncoders(robot.Start());
  localizer.Initialize(robot.pose, 1e-4 * Eigen::Matrix3d::Identity());
  for (int k = 0; k < 10; ++k) localizer.AddEncoders(robot.Step(20, 20));
  LaserScan slow;  // 50 ms sweep starting now
  slow.sensor_id = "slow";
  slow.stamp_s = robot.stamp_s;
  for (int i = 0; i < 11; ++i) slow.readings.push_back({3.0, 0.1 * i, 0.005 * i, true, false});
  EXPECT_EQ(localizer.AddScan(slow), ObservationStatus::kDeferred);
  localizer.AddEncoders(robot.Step(20, 20));
  // 5 ms later: odometry covers this batch, but the scan is still waiting.
  EXPECT_EQ(localizer.AddObservations(LineBatch(map, robot.pose, robot.stamp_s, MountedView())),
            ObservationStatus::kDeferred);
  for (int k = 0; k < 9; ++k) localizer.AddEncoders(robot.Step(20, 20));
  EXPECT_EQ(localizer.counters().cycles, 2);
  EXPECT_EQ(localizer.counters().out_of_order, 0);
  EXPECT_EQ(localizer.last_cycle().sensor_id, "laser");
  EXPECT_EQ(localizer.last_cycle().matches.size(), 4u);
}

// Lost detection: no match for longer than the timeout over more than the
// wheel travel bound; a kidnapped robot whose observations fall in no gate
// for lost_failed_cycles cycles; an uncertainty beyond lost_position_sigma_m.
// Lost is sticky until Initialize.
TEST(LocalizerTest, DetectsLostSituations) {
  const RobotMap map = testing::RectangularRoom(-4, -3, 4, 3);
  const Eigen::Matrix3d P0 = 1e-4 * Eigen::Matrix3d::Identity();
  // No observations at all, the wheels turning `ticks` per period (66: 0.3 m/s).
  const auto blind = [&](const LocalizerOptions& options, std::int64_t ticks, double until_s) {
    auto localizer = std::make_unique<Localizer>(map, options);
    TrueRobot robot({0, 0, 0});
    localizer->AddEncoders(robot.Start());
    localizer->Initialize(robot.pose, P0);
    while (robot.stamp_s < until_s - 1e-9) localizer->AddEncoders(robot.Step(ticks, ticks));
    return localizer;
  };
  {  // driving at 0.3 m/s: 6 m by the timeout, lost at 20 s
    EXPECT_EQ(blind(BaseOptions(), kCruiseTicks, 19.9)->status().state,
              LocalizationState::kTracking);
    const auto lost = blind(BaseOptions(), kCruiseTicks, 20.1);
    EXPECT_EQ(lost->status().state, LocalizationState::kLost);
    EXPECT_EQ(lost->status().reason, LostReason::kNoMatchTimeout);
    EXPECT_NEAR(lost->status().lost_since_s, 20.0, 0.006);
    lost->Initialize({0, 0, 0}, P0);
    EXPECT_EQ(lost->status().state, LocalizationState::kTracking);
  }
  {  // creeping at 0.1 m/s: lost when the wheels have rolled 5 m, at 50 s
    const std::int64_t creep = kCruiseTicks / 3;  // 22 ticks: 0.0995 m/s
    const double five_metres_s =
        5.0 / (creep * 2.0 * kPi * kWheelRadiusM / kTicksPerRevolution) * kOdometryPeriodS;
    EXPECT_EQ(blind(BaseOptions(), creep, 20.1)->status().state, LocalizationState::kTracking);
    EXPECT_EQ(blind(BaseOptions(), creep, five_metres_s - 0.05)->status().state,
              LocalizationState::kTracking);
    const auto lost = blind(BaseOptions(), creep, five_metres_s + 0.05);
    EXPECT_EQ(lost->status().reason, LostReason::kNoMatchTimeout);
    EXPECT_NEAR(lost->status().lost_since_s, five_metres_s, 0.006);
  }
  {  // standing: never lost by the timeout; with no travel bound, lost at 20 s
    EXPECT_EQ(blind(BaseOptions(), 0, 120.0)->status().state, LocalizationState::kTracking);
    LocalizerOptions time_alone = BaseOptions();
    time_alone.lost_no_match_travel_m = 0.0;
    EXPECT_EQ(blind(time_alone, 0, 19.9)->status().state, LocalizationState::kTracking);
    EXPECT_EQ(blind(time_alone, 0, 20.1)->status().reason, LostReason::kNoMatchTimeout);
  }
  {  // kidnapped: the truth jumps 1.5 m, the estimate does not
    Localizer localizer(map, BaseOptions());
    TrueRobot robot({0, 0, 0});
    localizer.AddEncoders(robot.Start());
    localizer.Initialize(robot.pose, P0);
    const Pose2 kidnapped{1.5, 1.0, 0.5};
    for (int cycle = 1; cycle <= 25; ++cycle) {
      EncoderReading reading;
      for (int k = 0; k < 20; ++k) reading = robot.Step(0, 0);
      localizer.AddEncoders(reading);
      localizer.AddObservations(LineBatch(map, kidnapped, reading.stamp_s, MountedView()));
      EXPECT_TRUE(localizer.last_cycle().matches.empty());
      EXPECT_EQ(localizer.status().state,
                cycle < 20 ? LocalizationState::kTracking : LocalizationState::kLost)
          << cycle;
    }
    EXPECT_EQ(localizer.status().reason, LostReason::kRepeatedGateFailures);
  }
  {  // hopelessly uncertain
    Localizer localizer(map, BaseOptions());
    TrueRobot robot({0, 0, 0});
    localizer.AddEncoders(robot.Start());
    localizer.Initialize(robot.pose, Eigen::Vector3d(4.0, 0.01, 0.01).asDiagonal());
    localizer.AddEncoders(robot.Step(0, 0));
    EXPECT_EQ(localizer.status().reason, LostReason::kUncertaintyTooLarge);
  }
}

// The map of testing::RoomWithPillar(): the room's walls seen from inside,
// the pillar's faces from outside.
RobotMap RoomWithPillarMap(const testing::SyntheticWorld& world) {
  RobotMap map;
  const Eigen::Vector2d room_centre(4.0, 2.5);
  const Eigen::Vector2d pillar_centre(5.8, 3.5);
  for (int i = 0; i < static_cast<int>(world.walls.size()); ++i) {
    const testing::WallElement& w = world.walls[i];
    const Eigen::Vector2d mid = 0.5 * (w.a + w.b);
    const Eigen::Vector2d seen_from = i < 4 ? room_centre : mid + (mid - pillar_centre);
    map.lines.push_back(testing::MapLineThrough("wall" + std::to_string(i), w.a, w.b, seen_from));
  }
  return map;
}

// Line extraction in the loop: two back-to-back LMS 200 scans per cycle
// (simulated ranges with 1 cm noise) in an 8 x 5 m room with a pillar, robot
// driving; from a 6 cm / 2 deg error the estimate gets within 2 cm / 0.5 deg.
TEST(LocalizerTest, TracksWithExtractedLinesFromTwoLasers) {
  testing::SyntheticWorld world;
  world.walls = testing::RoomWithPillar();
  const RobotMap map = RoomWithPillarMap(world);
  LocalizerOptions options = BaseOptions();
  LaserSensorOptions rear = options.default_laser;
  rear.id = "rear";
  options.lasers.push_back(rear);
  Localizer localizer(map, options);
  const Pose2 front_mount{0.2, 0.0, 0.0};
  const Pose2 rear_mount{-0.2, 0.0, kPi};
  TrueRobot robot({1.5, 1.2, 0.35});
  localizer.AddEncoders(robot.Start());
  localizer.Initialize({1.54, 1.16, 0.35 + 2.0 * kDeg},
                       Eigen::Vector3d(0.01, 0.01, std::pow(3.0 * kDeg, 2)).asDiagonal());
  RandomStream rng(111, 1);
  for (int cycle = 1; cycle <= 20; ++cycle) {
    EncoderReading reading;
    for (int k = 0; k < 20; ++k) reading = robot.Step(40, 44);  // gentle left arc
    localizer.AddEncoders(reading);
    for (const auto& [id, mount] :
         {std::pair{"front", front_mount}, std::pair{"rear", rear_mount}}) {
      LaserScan scan = testing::SimulateScan(world, robot.pose * mount, &rng).scan;
      scan.sensor_id = id;
      scan.stamp_s = reading.stamp_s;
      scan.robot_from_sensor = mount;
      EXPECT_EQ(localizer.AddScan(scan), ObservationStatus::kIntegrated);
      EXPECT_GE(localizer.last_cycle().matches.size(), 1u) << id << " cycle " << cycle;
      for (const FeatureMatch& m : localizer.last_cycle().matches) {
        EXPECT_LT(m.innovation.nis, ChiSquareQuantile(0.95, 2));
      }
    }
  }
  const Eigen::Vector3d e = Error(localizer.estimate().pose, robot.pose);
  EXPECT_LT(e.head<2>().norm(), 0.02);
  EXPECT_LT(std::abs(e.z()), 0.5 * kDeg);
  EXPECT_EQ(localizer.counters().cycles, 40);
  EXPECT_EQ(localizer.status().state, LocalizationState::kTracking);
}

// A slow scanner (0.1 s per scan, §2.2.1.4) on a robot turning at 1 rad/s:
// each scan waits until odometry covers its last reading (kDeferred), is
// registered into the frame of its first reading and then extracted. With
// registration the pose stays within millimetres; without it the bent scans
// pull the estimate off.
TEST(LocalizerTest, DeskewsScansFromASlowScannerWhileTurning) {
  testing::SyntheticWorld world;
  world.walls = testing::RoomWithPillar();
  const RobotMap map = RoomWithPillarMap(world);
  const Pose2 mount{0.2, 0.0, 0.0};
  constexpr std::int64_t kTurnTicks = 55;  // +-55 ticks per 5 ms: ~1 rad/s on the spot
  constexpr double kScanS = 0.099;
  std::vector<double> errors;
  for (bool deskew : {true, false}) {
    LocalizerOptions options = BaseOptions();
    options.default_laser.deskew = deskew;
    Localizer localizer(map, options);
    TrueRobot robot({3.0, 2.0, 0.2});
    localizer.AddEncoders(robot.Start());
    localizer.Initialize(robot.pose,
                         Eigen::Vector3d(1e-4, 1e-4, std::pow(0.5 * kDeg, 2)).asDiagonal());
    const WheelTravel step_travel = robot.encoders.Travel(-kTurnTicks, kTurnTicks);
    double worst = 0.0;
    for (int cycle = 1; cycle <= 10; ++cycle) {
      // The scan starts now; reading i is taken i/360 of 99 ms later, from
      // the pose the (constant) turning motion has then reached.
      const Pose2 start = robot.pose;
      LaserScan scan;
      scan.sensor_id = "slow";
      scan.stamp_s = robot.stamp_s;
      scan.robot_from_sensor = mount;
      for (int i = 0; i < 361; ++i) {
        const double offset = kScanS * i / 360.0;
        const double steps = offset / kOdometryPeriodS;
        const int whole = static_cast<int>(steps);
        Pose2 at = start;
        for (int k = 0; k < whole; ++k) at = DiffDriveStep(at, step_travel, kWheelbaseM);
        const double f = steps - whole;
        at = DiffDriveStep(at, {f * step_travel.left_m, f * step_travel.right_m}, kWheelbaseM);
        LaserReading r = testing::SimulateScan(world, at * mount, nullptr).scan.readings[i];
        r.time_offset_s = offset;
        scan.readings.push_back(r);
      }
      // Registration needs odometry up to the last reading; an unregistered
      // scan is integrated at once, at its stamp.
      EXPECT_EQ(localizer.AddScan(scan),
                deskew ? ObservationStatus::kDeferred : ObservationStatus::kIntegrated);
      for (int k = 0; k < 20; ++k) localizer.AddEncoders(robot.Step(-kTurnTicks, kTurnTicks));
      EXPECT_EQ(localizer.counters().cycles, cycle);
      const Eigen::Vector3d e = Error(localizer.estimate().pose, robot.pose);
      worst = std::max(worst, std::max(e.head<2>().norm(), std::abs(e.z())));
    }
    errors.push_back(worst);
  }
  RecordProperty("worst_error_deskewed", std::to_string(errors[0]));
  RecordProperty("worst_error_raw", std::to_string(errors[1]));
  EXPECT_LT(errors[0], 0.003);
  EXPECT_GT(errors[1], 0.01);
}

// Every option is validated, naming the field.
TEST(LocalizerTest, ValidatesOptions) {
  const auto expect_field = [](const LocalizerOptions& o, const std::string& field) {
    try {
      Localizer localizer(RobotMap{}, o);
      ADD_FAILURE() << "no throw for " << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  EXPECT_NO_THROW(Localizer(RobotMap{}, BaseOptions()));
  LocalizerOptions o = BaseOptions();
  o.significance = 1.5;
  expect_field(o, "significance");
  o = BaseOptions();
  o.odometry_buffer_s = 0.0;
  expect_field(o, "odometry_buffer_s");
  o = BaseOptions();
  o.odometry.wheelbase_m = -0.5;
  expect_field(o, "odometry.wheelbase_m");
  o = BaseOptions();
  o.lost_no_match_timeout_s = std::numeric_limits<double>::infinity();
  expect_field(o, "lost_no_match_timeout_s");
  o = BaseOptions();
  o.lost_no_match_travel_m = -1.0;
  expect_field(o, "lost_no_match_travel_m");
  o = BaseOptions();
  o.lost_failed_cycles = 0;
  expect_field(o, "lost_failed_cycles");
  o = BaseOptions();
  o.min_observations_for_failure = 0;
  expect_field(o, "min_observations_for_failure");
  o = BaseOptions();
  o.lost_position_sigma_m = 0.0;
  expect_field(o, "lost_position_sigma_m");
  o = BaseOptions();
  o.default_laser.perception_radius_m = -1.0;
  expect_field(o, "perception_radius_m");
  o = BaseOptions();
  o.default_laser.min_view_angle_rad = 4.0;
  expect_field(o, "min_view_angle_rad");
  o = BaseOptions();
  o.lasers.push_back({});
  o.lasers.back().id = "front";
  o.lasers.back().lines.window_size = 4;
  expect_field(o, "lasers[front].");
  expect_field(o, "window_size");
  o = BaseOptions();
  o.lasers.resize(2);
  o.lasers[0].id = o.lasers[1].id = "front";
  expect_field(o, "lasers[front].id");
}

}  // namespace
}  // namespace pavilion::core
