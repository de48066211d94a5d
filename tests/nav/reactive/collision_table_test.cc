// The clearance look-up table (nav/reactive/collision_table.h): conservative
// against the exact geometry and no earlier than one grown cell.
#include "nav/reactive/collision_table.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "core/random/random_stream.h"

namespace pavilion::nav {
namespace {

constexpr double kFlat_m = 0.34;
const double kMitre = 1.0 / std::cos(std::numbers::pi / 8.0);  // octagon corner factor

core::Polygon2 Octagon() {
  core::Polygon2 p;
  for (int k = 0; k < 8; ++k) {
    const double a = std::numbers::pi / 8.0 + k * std::numbers::pi / 4.0;
    p.emplace_back(kFlat_m * kMitre * std::cos(a), kFlat_m * kMitre * std::sin(a));
  }
  return p;
}

const CollisionTable& Table() {
  static const CollisionTable table(CollisionTableOptions{}, Octagon());
  return table;
}

// For random points within reach and every direction bin the table's arc is
// never later than the exact arc of the margin-grown polygon at the bin's
// direction, and not earlier than the exact arc of the polygon grown by the
// margin plus one cell's worth (half diagonal, mitred, plus half diagonal).
TEST(CollisionTableTest, ConservativeAndWithinOneCell) {
  const CollisionTable& table = Table();
  const CollisionTableOptions& o = table.options();
  const core::Polygon2 margin = InflateConvexPolygon(Octagon(), o.safety_margin_m);
  const double h = std::sqrt(0.5) * o.cell_m;
  const core::Polygon2 loose =
      InflateConvexPolygon(Octagon(), o.safety_margin_m + h * (kMitre + 1));
  const double quantum_m = o.lookahead_m / std::numeric_limits<std::uint16_t>::max();
  core::RandomStream rng(14, 2);
  int finite = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const double r_m = rng.Uniform(0.0, table.reach_m());
    const double a_rad = rng.Uniform(-std::numbers::pi, std::numbers::pi);
    const Eigen::Vector2d p(r_m * std::cos(a_rad), r_m * std::sin(a_rad));
    const int bin = static_cast<int>(rng.UniformInt(0, table.bins() - 1));
    const BodyTwist direction = table.BinDirection(bin);
    const int cell = table.CellOf(p);
    ASSERT_GE(cell, 0);
    const double lut_m = table.ArcToCollision(bin, cell);
    const double exact_m = std::min(ExactTimeToCollision(margin, direction, p), o.lookahead_m);
    const double early_m = std::min(ExactTimeToCollision(loose, direction, p), o.lookahead_m);
    EXPECT_LE(lut_m, exact_m + 1e-12) << "trial " << trial;
    EXPECT_GE(lut_m, early_m - quantum_m - 1e-12) << "trial " << trial;
    if (exact_m < o.lookahead_m) ++finite;
  }
  EXPECT_GT(finite, 800);  // most draws are real contacts, not the cap
}

// The minimum over a cell list is the smallest single entry.
TEST(CollisionTableTest, MinOverCellsIsEarliest) {
  const CollisionTable& table = Table();
  const int bin = 0;
  const int near = table.CellOf({0.6, 0.0});
  const int far = table.CellOf({1.0, 0.0});
  const int side = table.CellOf({0.0, 1.0});
  const int cells[] = {far, side, near};
  EXPECT_DOUBLE_EQ(table.MinArcToCollision(bin, cells), table.ArcToCollision(bin, near));
  EXPECT_LT(table.ArcToCollision(bin, near), table.ArcToCollision(bin, far));
  EXPECT_DOUBLE_EQ(table.ArcToCollision(bin, side), table.options().lookahead_m);
  EXPECT_DOUBLE_EQ(table.MinArcToCollision(bin, {}), table.options().lookahead_m);
}

// Straight ahead, on the spot and backwards fall on bin centres.
TEST(CollisionTableTest, BinsOfCardinalDirections) {
  const CollisionTable& table = Table();
  const int n = table.bins();
  EXPECT_EQ(table.BinOf({0.5, 0.0}), 0);
  EXPECT_EQ(table.BinOf({0.0, 1.0}), n / 4);
  EXPECT_EQ(table.BinOf({-0.5, 0.0}), n / 2);
  EXPECT_EQ(table.BinOf({0.0, -1.0}), 3 * n / 4);
  EXPECT_NEAR(table.GeneralizedSpeed(table.BinDirection(5)), 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(table.reference_radius_m(), kFlat_m * kMitre);
}

// Points off the table have no cell.
TEST(CollisionTableTest, OffTableHasNoCell) {
  const CollisionTable& table = Table();
  EXPECT_EQ(table.CellOf({table.reach_m() + 0.1, 0.0}), -1);
  EXPECT_EQ(table.CellOf({0.0, -table.reach_m() - 0.1}), -1);
  EXPECT_EQ(table.CellOf({std::nan(""), 0.0}), -1);
}

// Bad options and polygons name what is wrong.
TEST(CollisionTableTest, RejectsBadOptions) {
  CollisionTableOptions o;
  o.direction_bins = 30;
  EXPECT_THROW(
      try { o.Validate(); } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("direction_bins"), std::string::npos);
        throw;
      },
      std::invalid_argument);
  core::Polygon2 clockwise = Octagon();
  std::reverse(clockwise.begin(), clockwise.end());
  EXPECT_THROW(CollisionTable(CollisionTableOptions{}, clockwise), std::invalid_argument);
}

// SharedCollisionTable: the same (options, polygon) share one table while it
// is held, equal to a table built alone; other inputs get their own.
TEST(CollisionTableTest, SharedTableIsOnePerInputs) {
  CollisionTableOptions o;
  o.cell_m = 0.05;  // small tables: this test builds three
  const std::shared_ptr<const CollisionTable> a = SharedCollisionTable(o, Octagon());
  const std::shared_ptr<const CollisionTable> b = SharedCollisionTable(o, Octagon());
  EXPECT_EQ(a.get(), b.get());
  const CollisionTable alone(o, Octagon());
  ASSERT_EQ(a->cells(), alone.cells());
  for (int bin = 0; bin < alone.bins(); bin += 7) {
    for (int cell = 0; cell < alone.cells(); cell += 13) {
      EXPECT_EQ(a->ArcToCollision(bin, cell), alone.ArcToCollision(bin, cell));
    }
  }
  CollisionTableOptions wider = o;
  wider.safety_margin_m = 0.03;
  EXPECT_NE(SharedCollisionTable(wider, Octagon()).get(), a.get());
  core::Polygon2 moved = Octagon();
  moved[0].x() += 1e-12;  // exact keys: any change is another polygon
  EXPECT_NE(SharedCollisionTable(o, moved).get(), a.get());
}

}  // namespace
}  // namespace pavilion::nav
