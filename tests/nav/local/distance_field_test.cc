#include "nav/local/distance_field.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "core/random/random_stream.h"
#include "nav/local/local_grid.h"

namespace {

using pavilion::core::RandomStream;
using pavilion::nav::DistanceField;
using pavilion::nav::DistanceFieldOptions;
using pavilion::nav::LocalGrid;
using pavilion::nav::LocalGridOptions;

struct BruteNearest {
  double distance_m = std::numeric_limits<double>::infinity();
  double second_m = std::numeric_limits<double>::infinity();  // the runner-up
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
};

BruteNearest Brute(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& p) {
  BruteNearest result;
  for (const Eigen::Vector2d& q : points) {
    const double d = (q - p).norm();
    if (d < result.distance_m) {
      result.second_m = result.distance_m;
      result.distance_m = d;
      result.point = q;
    } else if (d < result.second_m) {
      result.second_m = d;
    }
  }
  return result;
}

// Clustered random points: a few clumps and a sprinkle, seeded.
std::vector<Eigen::Vector2d> RandomPoints(RandomStream* rng, const Eigen::Vector2d& center) {
  std::vector<Eigen::Vector2d> points;
  const int clumps = static_cast<int>(rng->UniformInt(1, 6));
  for (int c = 0; c < clumps; ++c) {
    const Eigen::Vector2d mid = center + Eigen::Vector2d(rng->Uniform(-4, 4), rng->Uniform(-4, 4));
    const int count = static_cast<int>(rng->UniformInt(5, 80));
    for (int k = 0; k < count; ++k) {
      points.push_back(mid + Eigen::Vector2d(rng->Normal(0, 0.3), rng->Normal(0, 0.3)));
    }
  }
  const int sprinkle = static_cast<int>(rng->UniformInt(0, 20));
  for (int k = 0; k < sprinkle; ++k) {
    points.push_back(center + Eigen::Vector2d(rng->Uniform(-4, 4), rng->Uniform(-4, 4)));
  }
  return points;
}

// Distances equal the brute-force nearest point (on the grid's points) to
// rounding, capped; gradients are the unit vector from that point, on 30
// seeded scenes, with the grid off the origin.
TEST(DistanceFieldTest, MatchesBruteForceNearestPoint) {
  LocalGrid grid(LocalGridOptions{});
  DistanceField field;
  const double cap = field.cap_m();
  for (int scene = 0; scene < 30; ++scene) {
    RandomStream rng(scene, RandomStream::StreamId("distance_field_test"));
    const Eigen::Vector2d center(rng.Uniform(-50, 50), rng.Uniform(-50, 50));
    grid.Build(center, RandomPoints(&rng, center));
    field.Build(grid);
    const std::vector<Eigen::Vector2d>& points = grid.obstacles();
    for (int k = 0; k < 400; ++k) {
      const Eigen::Vector2d p =
          center + Eigen::Vector2d(rng.Uniform(-3.99, 3.99), rng.Uniform(-3.99, 3.99));
      const DistanceField::Query q = field.Nearest(p);
      const BruteNearest brute = Brute(points, p);
      if (brute.distance_m >= cap) {
        EXPECT_EQ(q.distance_m, cap);
        EXPECT_EQ(q.gradient, Eigen::Vector2d::Zero());
        continue;
      }
      ASSERT_NEAR(q.distance_m, brute.distance_m, 1e-12) << "scene " << scene;
      if (brute.second_m - brute.distance_m > 1e-9) {
        const Eigen::Vector2d expected = (p - brute.point) / brute.distance_m;
        EXPECT_NEAR((q.gradient - expected).norm(), 0.0, 1e-9);
      }
    }
  }
}

// The gradient matches central differences of the distance away from ties.
TEST(DistanceFieldTest, GradientMatchesNumericalDifferences) {
  LocalGrid grid(LocalGridOptions{});
  DistanceField field;
  RandomStream rng(5, 0);
  grid.Build(Eigen::Vector2d::Zero(), RandomPoints(&rng, Eigen::Vector2d::Zero()));
  field.Build(grid);
  constexpr double kH = 1e-6;
  int checked = 0;
  for (int k = 0; k < 500; ++k) {
    const Eigen::Vector2d p(rng.Uniform(-3.5, 3.5), rng.Uniform(-3.5, 3.5));
    const BruteNearest brute = Brute(grid.obstacles(), p);
    if (brute.second_m - brute.distance_m < 1e-3 || brute.distance_m >= field.cap_m() - 1e-3) {
      continue;
    }
    const Eigen::Vector2d numeric(
        (field.Distance(p + Eigen::Vector2d(kH, 0)) - field.Distance(p - Eigen::Vector2d(kH, 0))) /
            (2 * kH),
        (field.Distance(p + Eigen::Vector2d(0, kH)) - field.Distance(p - Eigen::Vector2d(0, kH))) /
            (2 * kH));
    EXPECT_NEAR((field.Nearest(p).gradient - numeric).norm(), 0.0, 1e-6);
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

// Off the grid, on an empty grid and far from every point the distance is the cap.
TEST(DistanceFieldTest, CapOffGridAndEmpty) {
  LocalGrid grid(LocalGridOptions{});
  DistanceField field(DistanceFieldOptions{.cap_m = 1.5, .bucket_m = 0.25});
  grid.Build(Eigen::Vector2d::Zero(), std::vector<Eigen::Vector2d>{});
  field.Build(grid);
  EXPECT_EQ(field.Distance(Eigen::Vector2d(0.1, 0.2)), 1.5);
  const std::vector<Eigen::Vector2d> one{Eigen::Vector2d(3.9, 3.9)};
  grid.Build(Eigen::Vector2d::Zero(), one);
  field.Build(grid);
  EXPECT_NEAR(field.Distance(Eigen::Vector2d(3.0, 3.9)), 0.9, 1e-12);
  EXPECT_EQ(field.Distance(Eigen::Vector2d(-3.0, -3.0)), 1.5);
  EXPECT_EQ(field.Distance(Eigen::Vector2d(4.1, 3.9)), 1.5);  // off the grid, 0.2 m from it
  EXPECT_EQ(field.Distance(Eigen::Vector2d(3.9, 3.9)), 0.0);
}

// Out-of-range options are rejected naming the field.
TEST(DistanceFieldTest, ValidateNamesTheField) {
  EXPECT_THROW(DistanceField(DistanceFieldOptions{.cap_m = 0.0}), std::invalid_argument);
  try {
    DistanceFieldOptions{.bucket_m = 5.0}.Validate();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("bucket_m"), std::string::npos);
  }
}

}  // namespace
