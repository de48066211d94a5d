// The odometry buffer of on-the-fly localization (thesis §4.4.3): recording,
// splitting a step at an observation's time stamp, carrying a correction
// forward, and interpolated dead-reckoned poses.
#include "core/localization/odometry_buffer.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <stdexcept>

#include "core/random/random_stream.h"

namespace pavilion::core {
namespace {

constexpr double kWheelbaseM = 0.5;
const WheelNoise kNoise{5e-6, 5e-6};

double MaxDiff(const PoseWithCovariance& a, const PoseWithCovariance& b) {
  return std::max({std::abs(a.pose.x_m - b.pose.x_m), std::abs(a.pose.y_m - b.pose.y_m),
                   std::abs(NormalizeAngle(a.pose.theta_rad - b.pose.theta_rad)),
                   (a.covariance - b.covariance).cwiseAbs().maxCoeff()});
}

OdometryBuffer Filled(RandomStream& rng, int steps, std::vector<WheelTravel>* travels = nullptr) {
  OdometryBuffer buffer(kWheelbaseM, kNoise, 100.0);
  buffer.Reset(0.0, {{1.0, 2.0, 0.3}, 1e-4 * Eigen::Matrix3d::Identity()}, {1.0, 2.0, 0.3});
  for (int k = 1; k <= steps; ++k) {
    const WheelTravel t{rng.Uniform(0.0, 0.004), rng.Uniform(0.0, 0.004)};
    if (travels != nullptr) travels->push_back(t);
    buffer.Append(0.005 * k, t);
  }
  return buffer;
}

// Appending is the state prediction of eqs. 4.6-4.7 step by step.
TEST(OdometryBufferTest, AppendPropagatesTheOdometryModel) {
  RandomStream rng(81, 1);
  std::vector<WheelTravel> travels;
  const OdometryBuffer buffer = Filled(rng, 50, &travels);
  PoseWithCovariance expected{{1.0, 2.0, 0.3}, 1e-4 * Eigen::Matrix3d::Identity()};
  Pose2 odometry{1.0, 2.0, 0.3};
  for (const WheelTravel& t : travels) {
    expected = DiffDriveStepWithCovariance(expected, t, kWheelbaseM, kNoise);
    odometry = DiffDriveStep(odometry, t, kWheelbaseM);
  }
  EXPECT_EQ(buffer.size(), 51u);
  EXPECT_LT(MaxDiff(buffer.latest().state, expected), 1e-15);
  EXPECT_EQ(buffer.latest().odometry_pose, odometry);
  EXPECT_TRUE(buffer.Covers(0.1));
  EXPECT_FALSE(buffer.Covers(0.26));
}

// Splitting at a node's stamp inserts nothing; splitting inside a step inserts
// a node whose two parts add up to the original travel, and for straight
// motion leave the later nodes' poses as they were.
TEST(OdometryBufferTest, SplitAtInsertsANodeAtTheStamp) {
  OdometryBuffer buffer(kWheelbaseM, kNoise, 100.0);
  buffer.Reset(0.0, {{0, 0, 0}, Eigen::Matrix3d::Zero()}, {0, 0, 0});
  buffer.Append(0.01, {0.01, 0.01});
  buffer.Append(0.02, {0.01, 0.01});
  EXPECT_EQ(buffer.SplitAt(0.01), 1u);
  EXPECT_EQ(buffer.size(), 3u);
  const std::size_t i = buffer.SplitAt(0.0125);
  EXPECT_EQ(i, 2u);
  EXPECT_EQ(buffer.size(), 4u);
  EXPECT_DOUBLE_EQ(buffer.node(i).stamp_s, 0.0125);
  EXPECT_NEAR(buffer.node(i).state.pose.x_m, 0.0125, 1e-15);
  EXPECT_NEAR(buffer.node(i).travel.left_m + buffer.node(i + 1).travel.left_m, 0.01, 1e-15);
  EXPECT_NEAR(buffer.node(i + 1).state.pose.x_m, 0.02, 1e-15);
  // U = diag(k|s|) is additive in s: for straight motion the split step gives
  // the same x and heading variances as the unsplit one; the lateral terms
  // differ by the chord approximation's O(k s^3 / b^2) (a finer piecewise
  // model tends to the continuous 2ks^3/(3b^2) from the single step's
  // ks^3/(2b^2)).
  OdometryBuffer unsplit(kWheelbaseM, kNoise, 100.0);
  unsplit.Reset(0.0, {{0, 0, 0}, Eigen::Matrix3d::Zero()}, {0, 0, 0});
  unsplit.Append(0.01, {0.01, 0.01});
  unsplit.Append(0.02, {0.01, 0.01});
  buffer.CorrectAt(i, buffer.node(i).state);  // re-propagate through the split step
  const Eigen::Matrix3d& a = buffer.latest().state.covariance;
  const Eigen::Matrix3d& b = unsplit.latest().state.covariance;
  EXPECT_NEAR(a(0, 0), b(0, 0), 1e-20);
  EXPECT_NEAR(a(2, 2), b(2, 2), 1e-20);
  EXPECT_NEAR(a(1, 1), b(1, 1), 0.05 * b(1, 1));
  EXPECT_NEAR(a(1, 2), b(1, 2), 0.05 * b(1, 2));
  EXPECT_THROW(buffer.SplitAt(0.03), std::out_of_range);
}

// A correction at a past node is carried forward: later states equal the
// corrected state propagated with the recorded inputs.
TEST(OdometryBufferTest, CorrectAtCarriesTheCorrectionForward) {
  RandomStream rng(82, 1);
  OdometryBuffer buffer = Filled(rng, 40);
  const std::size_t at = buffer.SplitAt(0.1234);
  const Pose2 dead_reckoned = buffer.node(at).odometry_pose;
  PoseWithCovariance corrected = buffer.node(at).state;
  corrected.pose.x_m += 0.05;
  corrected.pose.theta_rad -= 0.02;
  corrected.covariance *= 0.1;
  buffer.CorrectAt(at, corrected);
  PoseWithCovariance expected = corrected;
  for (std::size_t k = at + 1; k < buffer.size(); ++k) {
    expected = DiffDriveStepWithCovariance(expected, buffer.node(k).travel, kWheelbaseM, kNoise);
  }
  EXPECT_LT(MaxDiff(buffer.latest().state, expected), 1e-15);
  // The dead-reckoned track is never corrected.
  EXPECT_EQ(buffer.node(at).odometry_pose, dead_reckoned);
}

// Interpolated odometry poses lie on the recorded steps; outside the buffer
// there is none.
// Transition(a, b) is the first-order map of a pose error at node a to node
// b: perturbing node a's state and re-running the steps moves node b by
// Phi times the perturbation (to second order), and Phi has determinant 1.
TEST(OdometryBufferTest, TransitionPropagatesPoseErrors) {
  RandomStream rng(83, 1);
  OdometryBuffer buffer = Filled(rng, 40);
  const Eigen::Matrix3d phi = buffer.Transition(10, 40);
  EXPECT_NEAR(phi.determinant(), 1.0, 1e-12);
  EXPECT_TRUE(buffer.Transition(7, 7).isIdentity(0.0));
  const PoseWithCovariance at10 = buffer.node(10).state;
  const Pose2 at40 = buffer.node(40).state.pose;
  const Eigen::Vector3d delta(2e-4, -1e-4, 3e-4);
  PoseWithCovariance moved = at10;
  moved.pose = {at10.pose.x_m + delta.x(), at10.pose.y_m + delta.y(),
                at10.pose.theta_rad + delta.z()};
  buffer.CorrectAt(10, moved);
  const Pose2 after = buffer.node(40).state.pose;
  const Eigen::Vector3d change(after.x_m - at40.x_m, after.y_m - at40.y_m,
                               NormalizeAngle(after.theta_rad - at40.theta_rad));
  EXPECT_LT((change - phi * delta).norm(), 1e-7);
  EXPECT_GT((phi * delta - delta).norm(), 1e-6);  // the heading error moved the position
  EXPECT_THROW(buffer.Transition(20, 10), std::out_of_range);
  EXPECT_THROW(buffer.Transition(0, buffer.size()), std::out_of_range);
}

TEST(OdometryBufferTest, OdometryPoseAtInterpolatesWithinSteps) {
  OdometryBuffer buffer(kWheelbaseM, kNoise, 100.0);
  buffer.Reset(1.0, {}, {0, 0, 0});
  buffer.Append(1.1, {0.1, 0.1});
  const std::optional<Pose2> mid = buffer.OdometryPoseAt(1.04);
  ASSERT_TRUE(mid.has_value());
  EXPECT_NEAR(mid->x_m, 0.04, 1e-15);
  EXPECT_FALSE(buffer.OdometryPoseAt(0.99).has_value());
  EXPECT_FALSE(buffer.OdometryPoseAt(1.11).has_value());
}

// Nodes older than the span are dropped, keeping the span covered.
TEST(OdometryBufferTest, KeepsOnlyTheSpan) {
  OdometryBuffer buffer(kWheelbaseM, kNoise, 0.1);
  buffer.Reset(0.0, {}, {});
  for (int k = 1; k <= 100; ++k) buffer.Append(0.005 * k, {0.001, 0.001});
  EXPECT_LE(buffer.oldest_stamp_s(), 0.5 - 0.1);
  EXPECT_GT(buffer.oldest_stamp_s(), 0.5 - 0.1 - 0.0051);
  EXPECT_THROW(buffer.Append(0.1, {}), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::core
