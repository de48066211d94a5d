#include "sim/raycast/ray_shapes.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/random/random_stream.h"

namespace pavilion::sim {
namespace {

TEST(RayShapes, SphereHitFromOutsideWithOutwardNormal) {
  const auto h = RaySphere({-5, 0, 0}, {10, 0, 0}, 1.0, 1.0);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 0.4, 1e-12);
  EXPECT_NEAR(h->normal.x(), -1.0, 1e-12);
  EXPECT_FALSE(RaySphere({-5, 0, 0}, {10, 0, 0}, 1.0, 0.39));  // beyond t_max
  EXPECT_FALSE(RaySphere({0, 0, 0}, {10, 0, 0}, 1.0, 1.0));    // starts inside
  EXPECT_FALSE(RaySphere({-5, 1.01, 0}, {10, 0, 0}, 1.0, 1.0));
}

TEST(RayShapes, BoxFacesAndNormals) {
  const Eigen::Vector3d half(1, 2, 3);
  auto h = RayBox({0, -10, 0}, {0, 20, 0}, half, 1.0);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 8.0 / 20.0, 1e-12);
  EXPECT_NEAR(h->normal.y(), -1.0, 1e-12);
  h = RayBox({0, 0, 10}, {0, 0, -20}, half, 1.0);
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 7.0 / 20.0, 1e-12);
  EXPECT_NEAR(h->normal.z(), 1.0, 1e-12);
  EXPECT_FALSE(RayBox({1.01, -10, 0}, {0, 20, 0}, half, 1.0));
}

TEST(RayShapes, CylinderSideAndCaps) {
  auto h = RayCylinderZ({-3, 0.6, 0.2}, {6, 0, 0}, 1.0, 0.5, 1.0);
  ASSERT_TRUE(h);
  const double x = -std::sqrt(1.0 - 0.36);
  EXPECT_NEAR(h->t, (x + 3) / 6, 1e-12);
  EXPECT_NEAR(h->normal.x(), x, 1e-12);
  EXPECT_NEAR(h->normal.y(), 0.6, 1e-12);
  h = RayCylinderZ({0.3, 0, 2}, {0, 0, -4}, 1.0, 0.5, 1.0);  // through the top cap
  ASSERT_TRUE(h);
  EXPECT_NEAR(h->t, 1.5 / 4, 1e-12);
  EXPECT_NEAR(h->normal.z(), 1.0, 1e-12);
  EXPECT_FALSE(RayCylinderZ({-3, 0, 0.51}, {6, 0, 0}, 1.0, 0.5, 1.0));  // above it
}

TEST(RayShapes, PrismMatchesTheBoxItDescribes) {
  const std::vector<Eigen::Vector2d> square = {{-1, -2}, {1, -2}, {1, 2}, {-1, 2}};
  core::RandomStream rng(3, 4);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d o(rng.Uniform(-4, 4), rng.Uniform(-4, 4), rng.Uniform(-4, 4));
    const Eigen::Vector3d d(rng.Uniform(-8, 8), rng.Uniform(-8, 8), rng.Uniform(-8, 8));
    const auto a = RayPrismZ(o, d, square, -3, 3, 1.0);
    const auto b = RayBox(o, d, {1, 2, 3}, 1.0);
    ASSERT_EQ(a.has_value(), b.has_value());
    if (a) {
      ++hits;
      EXPECT_NEAR(a->t, b->t, 1e-12);
      EXPECT_NEAR((a->normal - b->normal).norm(), 0.0, 1e-12);
    }
  }
  EXPECT_GT(hits, 100);
}

}  // namespace
}  // namespace pavilion::sim
