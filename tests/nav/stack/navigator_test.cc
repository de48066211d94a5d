// The robot stack (nav::Navigator): dead reckoning from encoder readings, the
// belief it steers from, and the order in which estimator and controller see
// a tick's readings.
#include "nav/stack/navigator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <string>
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
  std::vector<LocationHypothesis> hypotheses() const override {
    if (mode_ == LocalizationMode::kLost) return {};
    return std::vector<LocationHypothesis>(hypotheses_, LocationHypothesis{estimate_, 0, 0.0});
  }
  void OnContact(const BumperContact& contact) override {
    collisions += contact.press ? 1 : 0;
    held_s += contact.held_s;
    ++contacts;
    if (contact.press) turned_rad = 0.0;
    // Each report's earlier turn is the sum of the collision's reports so far.
    EXPECT_NEAR(contact.turned_before_rad, turned_rad, 1e-12);
    turned_rad += contact.turned_rad;
  }

  int collisions = 0;  // presses
  double held_s = 0.0;
  double turned_rad = 0.0;  // the odometry's turn reported since the last press
  int contacts = 0;         // calls
  int encoders_seen = 0;
  int scans_seen = 0;
  core::PoseWithCovariance estimate_{core::Pose2{5.0, -1.0, 0.5}, Eigen::Matrix3d::Identity()};
  LocalizationMode mode_ = LocalizationMode::kLocalized;
  std::size_t hypotheses_ = 1;  // while not localized
};

// A controller double: remembers the belief of its last tick, answers scans.
class RecordingController : public Controller {
 public:
  std::optional<WheelSpeeds> OnTick(const ControlTick& tick) override {
    last_belief = tick.belief;
    last_lost = tick.localization_lost;
    last_position_sigma_m = tick.position_sigma_m;
    last_heading_sigma_rad = tick.heading_sigma_rad;
    last_localized = tick.last_localized;
    lone_hypothesis = tick.lone_hypothesis;
    return WheelSpeeds{1.0, 2.0};
  }
  std::optional<WheelSpeeds> OnScan(const core::LaserScan& scan,
                                    const ScanContext& /*context*/) override {
    return WheelSpeeds{scan.stamp_s, -scan.stamp_s};
  }
  core::Pose2 last_belief;
  bool last_lost = false;
  double last_position_sigma_m = -1.0;
  double last_heading_sigma_rad = -1.0;
  std::optional<core::Pose2> last_localized;
  bool lone_hypothesis = false;
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

// Without an estimator the controller is told no uncertainty.
TEST(NavigatorTest, WithoutAnEstimatorTheBeliefHasNoSigma) {
  auto controller = std::make_unique<RecordingController>();
  RecordingController* c = controller.get();
  Navigator navigator(Options(), nullptr, std::move(controller));
  navigator.Control(0, 0.0);
  EXPECT_EQ(c->last_position_sigma_m, 0.0);
  EXPECT_EQ(c->last_heading_sigma_rad, 0.0);
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
  // ... and is told the estimate's sigmas: its position covariance's major
  // half-axis (eigenvalues 0.04 and 0.02 m^2) and its heading's.
  e->estimate_.covariance << 0.03, 0.01, 0.0, 0.01, 0.03, 0.0, 0.0, 0.0, 0.0025;
  navigator.Control(1, 0.005);
  EXPECT_NEAR(c->last_position_sigma_m, 0.2, 1e-12);
  EXPECT_NEAR(c->last_heading_sigma_rad, 0.05, 1e-12);

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

// Not localized, the controller is also told where the robot was when it
// was last localized, carried on by its dead reckoning since — whatever the
// estimator believes now.
TEST(NavigatorTest, WhileNotLocalizedTellsWhereItWasLastLocalizedCarriedOn) {
  auto estimator = std::make_unique<FakeEstimator>();
  auto controller = std::make_unique<RecordingController>();
  FakeEstimator* e = estimator.get();
  RecordingController* c = controller.get();
  Navigator navigator(Options(), std::move(estimator), std::move(controller));
  const std::vector<core::EncoderReading> start{Reading(0.0, 0, 0)};
  navigator.Sense(SensorFrame{0.0, start, {}, {}, {}});
  navigator.Control(0, 0.0);  // localized at (5, -1, 0.5), odometry at (1, 2, 0)
  EXPECT_FALSE(c->last_localized);
  // Lost; the estimate jumps to a look-alike while the wheels turn once
  // forward (2 pi r = 0.628 m straight on).
  e->mode_ = LocalizationMode::kLost;
  e->estimate_.pose = {20.0, 20.0, -2.0};
  const std::vector<core::EncoderReading> turn{Reading(1.0, kTicksPerTurn, kTicksPerTurn)};
  navigator.Sense(SensorFrame{1.0, turn, {}, {}, {}});
  navigator.Control(1, 1.0);
  const double d = 2.0 * std::numbers::pi * 0.1;
  ASSERT_TRUE(c->last_localized);
  EXPECT_NEAR(c->last_localized->x_m, 5.0 + d * std::cos(0.5), 1e-12);
  EXPECT_NEAR(c->last_localized->y_m, -1.0 + d * std::sin(0.5), 1e-12);
  EXPECT_NEAR(c->last_localized->theta_rad, 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(c->last_belief.x_m, 20.0);  // the belief is the estimator's
  // Localized again: nothing more to say.
  e->mode_ = LocalizationMode::kLocalized;
  navigator.Control(2, 1.5);
  EXPECT_FALSE(c->last_localized);
}

// The controller is told when the estimator, not localized, holds a single
// hypothesis (its belief): not while localized, lost or among several.
TEST(NavigatorTest, TellsTheControllerWhenItsOneHypothesisIsNotYetDetermined) {
  auto estimator = std::make_unique<FakeEstimator>();
  auto controller = std::make_unique<RecordingController>();
  FakeEstimator* e = estimator.get();
  RecordingController* c = controller.get();
  Navigator navigator(Options(), std::move(estimator), std::move(controller));
  navigator.Control(0, 0.0);
  EXPECT_FALSE(c->lone_hypothesis);
  e->mode_ = LocalizationMode::kNotLocalized;
  e->hypotheses_ = 3;
  navigator.Control(1, 0.1);
  EXPECT_FALSE(c->lone_hypothesis);
  e->hypotheses_ = 1;
  navigator.Control(2, 0.2);
  EXPECT_TRUE(c->lone_hypothesis);
  e->mode_ = LocalizationMode::kLost;
  navigator.Control(3, 0.3);
  EXPECT_FALSE(c->lone_hypothesis);
}

// Without a controller the stack commands nothing.
TEST(NavigatorTest, WithoutAControllerCommandsNothing) {
  Navigator navigator(Options(), nullptr, nullptr);
  EXPECT_FALSE(navigator.Control(0, 0.0));
}

// A bumper press adds a collision's jump to the estimator once per refractory
// period (a visitor's bump flickers the zones on and off, and each flicker is
// not another collision), and the time the zones stay pressed counts in full,
// to the end of each tick: bumper readings come only on a change.
TEST(NavigatorTest, FeelsEachCollisionOnceAndTheTimeItIsHeld) {
  auto estimator = std::make_unique<FakeEstimator>();
  FakeEstimator* e = estimator.get();
  NavigatorOptions options = Options();
  options.collision_refractory_s = 1.0;
  Navigator navigator(options, std::move(estimator), nullptr);
  const auto tick = [&](double now_s, std::optional<double> stamp_s = std::nullopt,
                        std::uint32_t zones = 0) {
    std::vector<core::BumperReading> readings;
    if (stamp_s) readings.push_back({*stamp_s, zones});
    navigator.Sense(SensorFrame{now_s, {}, {}, readings, {}});
  };
  tick(10.00, 9.99, 0b01);  // pressed 10 ms before the tick's end: a collision
  EXPECT_EQ(e->collisions, 1);
  EXPECT_NEAR(e->held_s, 0.01, 1e-9);
  tick(10.02);  // no reading: still pressed
  EXPECT_NEAR(e->held_s, 0.03, 1e-9);
  tick(10.08, 10.07, 0);  // released: held 80 ms in all
  EXPECT_NEAR(e->held_s, 0.08, 1e-9);
  const int calls = e->contacts;
  tick(10.10);  // nothing pressed, nothing felt
  EXPECT_EQ(e->contacts, calls);
  tick(10.20, 10.19, 0b01);  // the bump flickers within the second: held, no new press
  tick(10.40, 10.39, 0b11);
  tick(10.50, 10.49, 0);
  EXPECT_EQ(e->collisions, 1);
  EXPECT_NEAR(e->held_s, 0.38, 1e-9);
  tick(11.50, 11.49, 0b10);  // a second and more after the first: counted
  EXPECT_EQ(e->collisions, 2);
  tick(14.00);  // held 2.5 s
  tick(14.02, 14.01, 0);
  EXPECT_EQ(e->collisions, 2);  // a release is no collision
  EXPECT_NEAR(e->held_s, 0.38 + 2.52, 1e-9);

  NavigatorOptions zero = Options();
  zero.collision_refractory_s = 0.0;  // every press counts
  auto counted = std::make_unique<FakeEstimator>();
  FakeEstimator* c = counted.get();
  Navigator every(zero, std::move(counted), nullptr);
  for (double t : {1.0, 1.1, 1.2, 1.3}) {
    const std::vector<core::BumperReading> readings{{t, t == 1.0 || t == 1.2 ? 1u : 0u}};
    every.Sense(SensorFrame{t, {}, {}, readings, {}});
  }
  EXPECT_EQ(c->collisions, 2);
  EXPECT_NEAR(c->held_s, 0.2, 1e-9);

  NavigatorOptions bad = Options();
  bad.collision_refractory_s = -1.0;
  EXPECT_THROW(Navigator(bad, nullptr, nullptr), std::invalid_argument);
}

// The odometry's turn counts from a collision's press, while the zones stay
// pressed and for the refractory period after the press (robox_15 in
// expo_rush: its wheels turned 14 deg in the half second after a 0.16 s
// press while its body stood); before the press and after that, not at all.
TEST(NavigatorTest, ReportsTheOdometrysTurnDuringACollision) {
  auto estimator = std::make_unique<FakeEstimator>();
  FakeEstimator* e = estimator.get();
  NavigatorOptions options = Options();
  options.collision_refractory_s = 1.0;
  Navigator navigator(options, std::move(estimator), nullptr);
  // Turning on the spot: 10 ticks a wheel every 10 ms, 2 (2 pi 0.1 / 100) / 0.5 rad.
  const double per_tick_rad = 2.0 * (2.0 * std::numbers::pi * 0.1 * 10.0 / kTicksPerTurn) / 0.5;
  std::int64_t ticks = 0;
  const auto tick = [&](double now_s, std::optional<double> stamp_s = std::nullopt,
                        std::uint32_t zones = 0) {
    const std::vector<core::EncoderReading> encoders{Reading(now_s, -ticks, ticks)};
    ticks += 10;
    std::vector<core::BumperReading> readings;
    if (stamp_s) readings.push_back({*stamp_s, zones});
    navigator.Sense(SensorFrame{now_s, encoders, {}, readings, {}});
  };
  tick(10.00);  // the first reading sets the counts: no motion
  for (int k = 1; k <= 4; ++k) tick(10.00 + 0.01 * k);
  EXPECT_EQ(e->contacts, 0);  // turning before any press is odometry's own
  tick(10.05, 10.045, 0b01);  // pressed
  for (int k = 6; k <= 19; ++k) tick(10.00 + 0.01 * k);
  tick(10.20, 10.195, 0);  // released after 0.15 s; the wheels go on turning
  for (int k = 21; k <= 150; ++k) tick(10.00 + 0.01 * k);
  // Counted in the frames from 10.05 to 11.04: within a second of the press.
  EXPECT_EQ(e->collisions, 1);
  EXPECT_NEAR(e->turned_rad, 100 * per_tick_rad, 1e-9);
  const int calls = e->contacts;
  tick(11.51);
  EXPECT_EQ(e->contacts, calls);
  tick(11.52, 11.515, 0b10);  // a new collision counts its own turn from zero
  tick(11.53);
  EXPECT_EQ(e->collisions, 2);
  EXPECT_NEAR(e->turned_rad, 2 * per_tick_rad, 1e-9);
}

// A collision's noise: the press's jump, plus a random walk while held (the
// added variance grows linearly with the time held, its sigma with the root).
TEST(CollisionNoiseTest, AJumpAtThePressAndARandomWalkWhileHeld) {
  CollisionNoiseOptions o;
  o.press_sigma_m = 0.02;
  o.press_sigma_rad = 0.05;
  o.hold_sigma_m = 0.10;
  o.hold_sigma_rad = 0.15;
  const Eigen::Matrix3d press = o.Covariance({true, 0.0});
  EXPECT_NEAR(std::sqrt(press(0, 0)), 0.02, 1e-12);
  EXPECT_NEAR(std::sqrt(press(1, 1)), 0.02, 1e-12);
  EXPECT_NEAR(std::sqrt(press(2, 2)), 0.05, 1e-12);
  EXPECT_EQ(press(0, 1), 0.0);
  const Eigen::Matrix3d held = o.Covariance({false, 4.0});  // 4 s: twice the 1 s sigma
  EXPECT_NEAR(std::sqrt(held(0, 0)), 0.20, 1e-12);
  EXPECT_NEAR(std::sqrt(held(2, 2)), 0.30, 1e-12);
  const Eigen::Matrix3d both = o.Covariance({true, 0.25});
  EXPECT_NEAR(both(0, 0), 0.02 * 0.02 + 0.25 * 0.01, 1e-12);
  EXPECT_TRUE(o.Covariance({false, 0.0}).isZero());
  // The odometry's turn adds one error over the whole collision: reports of
  // 0.1 then 0.2 rad add up to the variance of (fraction x 0.3 rad)^2, with
  // no position.
  o.turn_slip_fraction = 0.5;
  const Eigen::Matrix3d first = o.Covariance({false, 0.0, 0.0, 0.1});
  const Eigen::Matrix3d second = o.Covariance({false, 0.0, 0.1, 0.2});
  EXPECT_NEAR(first(2, 2), 0.05 * 0.05, 1e-12);
  EXPECT_NEAR(first(2, 2) + second(2, 2), 0.15 * 0.15, 1e-12);
  EXPECT_EQ(second(0, 0), 0.0);
  EXPECT_EQ(second(1, 1), 0.0);
  EXPECT_NO_THROW(o.Validate("Test"));
  o.hold_sigma_rad = -0.1;
  try {
    o.Validate("EkfPoseEstimatorOptions");
    FAIL() << "a negative sigma passed";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("EkfPoseEstimatorOptions.collision.hold_sigma_rad"),
              std::string::npos);
  }
}

}  // namespace
}  // namespace pavilion::nav
