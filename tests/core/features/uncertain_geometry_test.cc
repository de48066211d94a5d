#include "core/features/uncertain_geometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "core/features/line_fit.h"
#include "core/random/random_stream.h"

namespace pavilion::core {
namespace {

constexpr double kPi = std::numbers::pi;

Line RandomLine(RandomStream& rng) {
  Line line;
  line.alpha_rad = rng.Uniform(-kPi, kPi);
  line.r_m = rng.Uniform(-5.0, 5.0);  // both visibility signs (eq. B.4)
  const double sa = rng.Uniform(0.001, 0.05);
  const double sr = rng.Uniform(0.001, 0.05);
  const double rho = rng.Uniform(-0.9, 0.9);
  line.covariance << sa * sa, rho * sa * sr, rho * sa * sr, sr * sr;
  return line;
}

Pose2 RandomPose(RandomStream& rng) {
  return {rng.Uniform(-5.0, 5.0), rng.Uniform(-5.0, 5.0), rng.Uniform(-kPi, kPi)};
}

Eigen::Vector2d Params(const Line& l, double ref) {
  return {NormalizeAngle(l.alpha_rad - ref), l.r_m};
}

// The analytic Jacobians of both line transforms (eqs. B.12-B.15) match central
// differences at random lines and poses.
TEST(UncertainGeometryTest, LineTransformJacobiansMatchNumerical) {
  RandomStream rng(21, 1);
  constexpr double kStep = 1e-6;
  for (int trial = 0; trial < 50; ++trial) {
    const Line line = RandomLine(rng);
    const Pose2 pose = RandomPose(rng);
    for (bool to_child : {true, false}) {
      auto f = [&](const Line& l, const Pose2& p) {
        return to_child ? LineInChild(l, p) : LineInParent(l, p);
      };
      LineTransformJacobians J;
      const Line out = to_child ? LineInChild(line, pose, Eigen::Matrix3d::Zero(), &J)
                                : LineInParent(line, pose, Eigen::Matrix3d::Zero(), &J);
      for (int k = 0; k < 2; ++k) {
        Line plus = line;
        Line minus = line;
        (k == 0 ? plus.alpha_rad : plus.r_m) += kStep;
        (k == 0 ? minus.alpha_rad : minus.r_m) -= kStep;
        const Eigen::Vector2d d =
            (Params(f(plus, pose), out.alpha_rad) - Params(f(minus, pose), out.alpha_rad)) /
            (2 * kStep);
        EXPECT_NEAR(d(0), J.J_line_line(0, k), 1e-6);
        EXPECT_NEAR(d(1), J.J_line_line(1, k), 1e-6);
      }
      for (int k = 0; k < 3; ++k) {
        Pose2 plus = pose;
        Pose2 minus = pose;
        double* pp = k == 0 ? &plus.x_m : k == 1 ? &plus.y_m : &plus.theta_rad;
        double* pm = k == 0 ? &minus.x_m : k == 1 ? &minus.y_m : &minus.theta_rad;
        *pp += kStep;
        *pm -= kStep;
        const Eigen::Vector2d d =
            (Params(f(line, plus), out.alpha_rad) - Params(f(line, minus), out.alpha_rad)) /
            (2 * kStep);
        EXPECT_NEAR(d(0), J.J_line_pose(0, k), 1e-6);
        EXPECT_NEAR(d(1), J.J_line_pose(1, k), 1e-6);
      }
    }
  }
}

// Eq. B.16: the transformed covariance is J_l C_l J_l^T + J_x C_x J_x^T, and the
// two transforms are inverse to each other.
TEST(UncertainGeometryTest, TransformsPropagateCovarianceAndRoundTrip) {
  RandomStream rng(22, 1);
  for (int trial = 0; trial < 50; ++trial) {
    const Line line = RandomLine(rng);
    const Pose2 pose = RandomPose(rng);
    Eigen::Matrix3d pose_cov;
    pose_cov << 0.01, 0.002, 0.001, 0.002, 0.02, -0.001, 0.001, -0.001, 0.003;
    LineTransformJacobians J;
    const Line child = LineInChild(line, pose, pose_cov, &J);
    const Eigen::Matrix2d expected = J.J_line_line * line.covariance * J.J_line_line.transpose() +
                                     J.J_line_pose * pose_cov * J.J_line_pose.transpose();
    EXPECT_TRUE(child.covariance.isApprox(expected, 1e-12));
    const Line back = LineInParent(child, pose);
    EXPECT_NEAR(NormalizeAngle(back.alpha_rad - line.alpha_rad), 0.0, 1e-12);
    EXPECT_NEAR(back.r_m, line.r_m, 1e-12);
  }
}

// The visibility sign of eq. B.4 survives frame changes: a line is visible from a
// point (eq. B.21) iff its r in a frame at that point is positive (eq. B.24),
// whatever the frame's heading, and a line fitted in a sensor frame (r > 0) is
// visible from the sensor's position after transforming it to the world.
TEST(UncertainGeometryTest, VisibilitySignUnderFrameChanges) {
  RandomStream rng(23, 1);
  int visible = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    const Line world_line = RandomLine(rng);
    const Pose2 world_from_sensor = RandomPose(rng);
    const Line sensor_line = LineInChild(world_line, world_from_sensor);
    const bool seen = world_line.IsVisibleFrom(world_from_sensor.translation());
    visible += seen;
    EXPECT_EQ(seen, sensor_line.IsVisibleFromOrigin());
    // Seen from the sensor the line is in front of it: the foot point n * r
    // lies on the line and the sensor is on the visible side.
    if (seen) {
      const Eigen::Vector2d foot_in_world =
          world_from_sensor * (sensor_line.r_m * sensor_line.normal());
      EXPECT_NEAR(world_line.SignedDistance(foot_in_world), 0.0, 1e-9);
    }
    // Chaining through a second frame keeps the sign.
    const Pose2 sensor_from_other = RandomPose(rng);
    const Line other_line = LineInChild(sensor_line, sensor_from_other);
    EXPECT_EQ(other_line.IsVisibleFromOrigin(),
              world_line.IsVisibleFrom((world_from_sensor * sensor_from_other).translation()));
    // A line extracted in the sensor frame (r >= 0) is visible from the sensor in the world.
    Line extracted = sensor_line;
    if (extracted.r_m < 0.0) {
      extracted.r_m = -extracted.r_m;
      extracted.alpha_rad = NormalizeAngle(extracted.alpha_rad + kPi);
    }
    const Line in_world = LineInParent(extracted, world_from_sensor);
    EXPECT_TRUE(in_world.IsVisibleFrom(world_from_sensor.translation()));
  }
  EXPECT_GT(visible, 300);
  EXPECT_LT(visible, 700);
}

// Endpoint covariances (eqs. 5.3-5.9) and the length variance (eqs. 5.15-5.16)
// match the scatter of endpoints and lengths over 4000 draws of a noisy fit and
// noisy endpoint bearings (sigma_theta = angular resolution, eq. 5.2) within 10%.
TEST(UncertainGeometryTest, EndpointAndLengthVariancesMatchMonteCarlo) {
  const double resolution = 0.5 * kPi / 180.0;
  struct Case {
    double alpha, r, first, last;
  };
  // Wall seen head-on, obliquely, and at a grazing angle on one side.
  const Case cases[] = {{0.2, 2.0, -0.3, 0.6}, {1.0, 3.0, 0.1, 0.7}, {-0.4, 1.5, 0.2, 0.6}};
  RandomStream rng(24, 1);
  for (const Case& c : cases) {
    SCOPED_TRACE(c.alpha);
    const int n = static_cast<int>(std::round((c.last - c.first) / resolution)) + 1;
    std::vector<PolarPoint> truth;
    for (int i = 0; i < n; ++i) {
      const double theta = c.first + i * resolution;
      truth.push_back({c.r / std::cos(theta - c.alpha), theta, 0.01});
    }
    const Line line = *FitLine(truth);
    const Segment predicted = MakeSegment(line, truth.front().bearing_rad, truth.back().bearing_rad,
                                          resolution, n, 0, n - 1);
    std::vector<Eigen::Vector2d> first;
    std::vector<Eigen::Vector2d> last;
    std::vector<double> lengths;
    for (int draw = 0; draw < 4000; ++draw) {
      std::vector<PolarPoint> noisy = truth;
      for (PolarPoint& p : noisy) p.range_m += rng.Normal(0.0, p.range_sigma_m);
      const Line fit = *FitLine(noisy);
      const Segment s =
          MakeSegment(fit, truth.front().bearing_rad + rng.Normal(0.0, resolution),
                      truth.back().bearing_rad + rng.Normal(0.0, resolution), 0.0, n, 0, n - 1);
      first.push_back(s.first_endpoint.position_m);
      last.push_back(s.last_endpoint.position_m);
      lengths.push_back(s.length_m);
    }
    auto cov = [](const std::vector<Eigen::Vector2d>& xs) {
      Eigen::Vector2d m = Eigen::Vector2d::Zero();
      for (const auto& x : xs) m += x;
      m /= static_cast<double>(xs.size());
      Eigen::Matrix2d c = Eigen::Matrix2d::Zero();
      for (const auto& x : xs) c += (x - m) * (x - m).transpose();
      return Eigen::Matrix2d(c / static_cast<double>(xs.size() - 1));
    };
    for (const auto& [p, samples] :
         {std::pair{predicted.first_endpoint, first}, std::pair{predicted.last_endpoint, last}}) {
      const Eigen::Matrix2d e = cov(samples);
      EXPECT_NEAR(p.covariance(0, 0), e(0, 0), 0.1 * e(0, 0));
      EXPECT_NEAR(p.covariance(1, 1), e(1, 1), 0.1 * e(1, 1));
      EXPECT_NEAR(p.covariance(0, 1), e(0, 1), 0.1 * std::sqrt(e(0, 0) * e(1, 1)));
    }
    double mean = 0.0;
    for (double l : lengths) mean += l;
    mean /= static_cast<double>(lengths.size());
    double var = 0.0;
    for (double l : lengths) var += (l - mean) * (l - mean);
    var /= static_cast<double>(lengths.size() - 1);
    EXPECT_NEAR(predicted.length_variance_m2, var, 0.1 * var);
    EXPECT_NEAR(predicted.length_m, mean, 3.0 * std::sqrt(var / 4000.0) + 1e-4);
  }
}

}  // namespace
}  // namespace pavilion::core
