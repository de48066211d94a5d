// The robot stack (nav::Navigator): dead reckoning from encoder readings, the
// belief it steers from, and the order in which estimator and controller see
// a tick's readings.
#include "nav/stack/navigator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "nav/control/drive_profile.h"

namespace pavilion::nav {
namespace {

constexpr int kTicksPerTurn = 1000;

core::EncoderReading Reading(double t, std::int64_t left, std::int64_t right) {
  core::EncoderReading r;
  r.stamp_s = t;
  r.left_ticks = left;
  r.right_ticks = right;
  r.ticks_per_revolution = kTicksPerTurn;
  return r;
}

// An estimator double: counts what it was fed, reports a cycle every
// `cycle_every` calls, and holds a fixed estimate.
class FakeEstimator : public PoseEstimator {
 public:
  std::optional<EstimatorCycle> Update(std::span<const core::EncoderReading> encoders,
                                       const std::vector<const core::LaserScan*>& scans) override {
    encoders_seen += static_cast<int>(encoders.size());
    scans_seen += static_cast<int>(scans.size());
    if (scans.empty()) return std::nullopt;
    EstimatorCycle c;
    c.observations = static_cast<int>(scans.size());
    return c;
  }
  const core::PoseWithCovariance& estimate() const override { return estimate_; }
  std::string lost_reason() const override { return "none"; }
  LocalizationMode mode() const override { return mode_; }
  void OnCollision() override { ++collisions; }

  int collisions = 0;
  int encoders_seen = 0;
  int scans_seen = 0;
  core::PoseWithCovariance estimate_{core::Pose2{5.0, -1.0, 0.5}, Eigen::Matrix3d::Identity()};
  LocalizationMode mode_ = LocalizationMode::kLocalized;
};

// A controller double: remembers the belief of its last tick, answers scans.
class RecordingController : public Controller {
 public:
  std::optional<WheelSpeeds> OnTick(const ControlTick& tick) override {
    last_belief = tick.belief;
    last_lost = tick.localization_lost;
    return WheelSpeeds{1.0, 2.0};
  }
  std::optional<WheelSpeeds> OnScan(const core::LaserScan& scan,
                                    const ScanContext& /*context*/) override {
    return WheelSpeeds{scan.stamp_s, -scan.stamp_s};
  }
  core::Pose2 last_belief;
  bool last_lost = false;
};

NavigatorOptions Options() {
  NavigatorOptions o;
  o.odometry.left_wheel_radius_m = 0.1;
  o.odometry.right_wheel_radius_m = 0.1;
  o.odometry.wheelbase_m = 0.5;
  o.start_pose = {1.0, 2.0, 0.0};
  return o;
}

// Both wheels one turn forward: the odometry moves 2 pi r straight ahead.
TEST(NavigatorTest, DeadReckonsFromEncoderCounts) {
  Navigator navigator(Options(), nullptr, nullptr);
  const std::vector<core::EncoderReading> first{Reading(0.0, 0, 0)};
  const std::vector<core::EncoderReading> second{Reading(1.0, kTicksPerTurn, kTicksPerTurn)};
  navigator.Sense(SensorFrame{0.0, first, {}, {}, {}});
  navigator.Sense(SensorFrame{1.0, second, {}, {}, {}});
  EXPECT_NEAR(navigator.odometry_pose().x_m, 1.0 + 2.0 * std::numbers::pi * 0.1, 1e-12);
  EXPECT_NEAR(navigator.odometry_pose().y_m, 2.0, 1e-12);
  EXPECT_NEAR(navigator.belief().x_m, navigator.odometry_pose().x_m, 1e-12);
}

// With an estimator the controller steers from the estimate, not odometry;
// the estimator sees every reading and the controller every scan.
TEST(NavigatorTest, SteersFromTheEstimateAndPassesScansOn) {
  auto estimator = std::make_unique<FakeEstimator>();
  auto controller = std::make_unique<RecordingController>();
  FakeEstimator* e = estimator.get();
  RecordingController* c = controller.get();
  Navigator navigator(Options(), std::move(estimator), std::move(controller));
  const std::optional<WheelSpeeds> command = navigator.Control(0, 0.0);
  ASSERT_TRUE(command);
  EXPECT_DOUBLE_EQ(command->right_radps, 2.0);
  EXPECT_DOUBLE_EQ(c->last_belief.x_m, 5.0);
  EXPECT_DOUBLE_EQ(c->last_belief.theta_rad, 0.5);

  core::LaserScan a, b;
  a.stamp_s = 0.1;
  b.stamp_s = 0.2;
  const std::vector<core::EncoderReading> encoders{Reading(0.2, 0, 0), Reading(0.205, 1, 1)};
  const SenseResult result = navigator.Sense(SensorFrame{0.205, encoders, {&a, &b}, {}, {}});
  EXPECT_EQ(e->encoders_seen, 2);
  EXPECT_EQ(e->scans_seen, 2);
  ASSERT_TRUE(result.cycle);
  EXPECT_EQ(result.cycle->observations, 2);
  ASSERT_TRUE(result.command);  // the reaction to the last scan wins
  EXPECT_DOUBLE_EQ(result.command->left_radps, 0.2);
}

// Not localized (lost, or several hypotheses), the controller is told so and
// still drives: the chapter 6 navigation explores by its senses then.
TEST(NavigatorTest, TellsTheControllerWhenTheEstimatorIsNotLocalized) {
  auto estimator = std::make_unique<FakeEstimator>();
  auto controller = std::make_unique<RecordingController>();
  FakeEstimator* e = estimator.get();
  RecordingController* c = controller.get();
  Navigator navigator(Options(), std::move(estimator), std::move(controller));
  EXPECT_DOUBLE_EQ(navigator.Control(0, 0.5)->right_radps, 2.0);
  EXPECT_FALSE(c->last_lost);
  for (const LocalizationMode mode : {LocalizationMode::kLost, LocalizationMode::kNotLocalized}) {
    e->mode_ = mode;
    EXPECT_DOUBLE_EQ(navigator.Control(0, 1.0)->right_radps, 2.0);
    EXPECT_TRUE(c->last_lost);
  }
  e->mode_ = LocalizationMode::kLocalized;
  navigator.Control(0, 1.5);
  EXPECT_FALSE(c->last_lost);
}

// Without a controller the stack commands nothing.
TEST(NavigatorTest, WithoutAControllerCommandsNothing) {
  Navigator navigator(Options(), nullptr, nullptr);
  EXPECT_FALSE(navigator.Control(0, 0.0));
}

// A bumper press and its release add a collision's pose noise to the
// estimator, once per refractory period: a visitor's bump flickers the zones
// on and off, and each flicker is not another collision.
TEST(NavigatorTest, AddsCollisionNoiseOncePerRefractoryPeriod) {
  auto estimator = std::make_unique<FakeEstimator>();
  FakeEstimator* e = estimator.get();
  NavigatorOptions options = Options();
  options.collision_refractory_s = 1.0;
  Navigator navigator(options, std::move(estimator), nullptr);
  const auto bump = [&](double t, std::uint32_t zones) {
    const std::vector<core::BumperReading> readings{{t, zones}};
    navigator.Sense(SensorFrame{t, {}, {}, readings, {}});
  };
  bump(10.00, 0b01);  // pressed: a collision
  EXPECT_EQ(e->collisions, 1);
  bump(10.08, 0);  // flickers within the second: the same collision
  bump(10.20, 0b01);
  bump(10.28, 0);
  bump(10.40, 0b11);
  EXPECT_EQ(e->collisions, 1);
  bump(11.10, 0);  // released more than a second after the first: counted
  EXPECT_EQ(e->collisions, 2);
  bump(11.50, 0b10);  // pressed again within a second of that: not
  EXPECT_EQ(e->collisions, 2);
  bump(13.00, 0b10);  // no change: no reading would be sent, nothing added
  EXPECT_EQ(e->collisions, 2);
  bump(13.20, 0);  // the release, long after
  EXPECT_EQ(e->collisions, 3);

  NavigatorOptions zero = Options();
  zero.collision_refractory_s = 0.0;  // every press and release
  auto counted = std::make_unique<FakeEstimator>();
  FakeEstimator* c = counted.get();
  Navigator every(zero, std::move(counted), nullptr);
  for (double t : {1.0, 1.1, 1.2, 1.3}) {
    const std::vector<core::BumperReading> readings{{t, t == 1.0 || t == 1.2 ? 1u : 0u}};
    every.Sense(SensorFrame{t, {}, {}, readings, {}});
  }
  EXPECT_EQ(c->collisions, 4);

  NavigatorOptions bad = Options();
  bad.collision_refractory_s = -1.0;
  EXPECT_THROW(Navigator(bad, nullptr, nullptr), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::nav
