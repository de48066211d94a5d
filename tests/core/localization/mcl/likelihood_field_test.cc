// The likelihood field of a map's geometry (Probabilistic Robotics §6.4):
// distances to segments, multi-segment members, points, discs, beacons and
// clipped lines, and the cap.
#include "core/localization/mcl/likelihood_field.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace pavilion::core {
namespace {

using Vec2 = Eigen::Vector2d;

Point2Uncertain At(double x, double y) { return {Vec2(x, y), Eigen::Matrix2d::Identity() * 1e-6}; }

// Segment (1,1)-(5,1); a multi-segment line y = 3 with a gap x in (2, 3); an
// edge point (8,2); a column at (8,5) of radius 0.5; a beacon (1,6); an
// infinite line y = 4.5. Bounds of the finite part: x in [1, 8.5], y in [1, 6].
RobotMap TestMap() {
  RobotMap map;
  MapSegment s;
  s.id = "wall";
  s.first_endpoint = At(1, 1);
  s.second_endpoint = At(5, 1);
  map.segments.push_back(s);
  MapMultiSegmentLine m;
  m.id = "doors";
  m.segments = {{At(1, 3), At(2, 3)}, {At(3, 3), At(5, 3)}};
  map.multi_segment_lines.push_back(m);
  map.points.push_back({"edge", At(8, 2), 0.0});
  map.points.push_back({"column", At(8, 5), 0.5});
  map.beacons.push_back({"beacon", At(1, 6)});
  MapLine line;
  line.id = "rail";
  line.line.alpha_rad = 0.5 * std::numbers::pi;
  line.line.r_m = 4.5;
  map.lines.push_back(line);
  return map;
}

// Hand-computed distances hold within the raster's bound (resolution/sqrt(2)
// for the transform plus as much for reading the cell that holds the point).
TEST(LikelihoodFieldTest, DistancesMatchHandComputedValues) {
  struct Case {
    Vec2 point;
    double distance_m;
    const char* what;
  };
  const Case cases[] = {
      {{3.0, 1.5}, 0.5, "beside the segment"},
      {{6.0, 1.0}, 1.0, "beyond the segment's end"},
      {{2.5, 3.0}, 0.5, "in the middle of the multi-segment line's gap"},
      {{2.5, 3.2}, std::sqrt(0.25 + 0.04), "off the gap"},
      {{8.0, 2.7}, 0.7, "above the edge point"},
      {{8.0, 5.0}, 0.0, "inside the column"},
      {{8.0, 5.8}, 0.3, "outside the column"},
      {{4.0, 4.8}, 0.3, "above the infinite line"},
      {{0.2, 4.5}, 0.8, "beyond the end of the clipped line"},
      {{1.4, 6.3}, 0.5, "near the beacon"},
  };
  for (const double resolution_m : {0.01, 0.05}) {
    LikelihoodFieldOptions options;
    options.resolution_m = resolution_m;
    const LikelihoodField field(TestMap(), options);
    const double tolerance_m = std::sqrt(2.0) * resolution_m;
    for (const Case& c : cases) {
      EXPECT_NEAR(field.DistanceM(c.point), c.distance_m, tolerance_m)
          << c.what << " at resolution " << resolution_m;
    }
  }
}

// Distances stop at max_distance_m, and off the grid the field is max_distance_m.
TEST(LikelihoodFieldTest, CapsAtMaxDistance) {
  LikelihoodFieldOptions options;
  options.resolution_m = 0.01;
  options.max_distance_m = 0.4;
  const LikelihoodField field(TestMap(), options);
  EXPECT_NEAR(field.DistanceM({3.0, 1.2}), 0.2, 0.015);
  EXPECT_DOUBLE_EQ(field.DistanceM({6.0, 1.0}), 0.4);
  EXPECT_DOUBLE_EQ(field.DistanceM({100.0, 100.0}), 0.4);
  EXPECT_EQ(field.CellIndex({100.0, 100.0}), -1);
}

// A map of infinite lines only has no finite extent: the field is empty.
TEST(LikelihoodFieldTest, LinesAloneGiveAnEmptyField) {
  RobotMap map = TestMap();
  map.segments.clear();
  map.multi_segment_lines.clear();
  map.points.clear();
  map.beacons.clear();
  const LikelihoodField field(map);
  EXPECT_EQ(field.cell_count(), 0);
  EXPECT_DOUBLE_EQ(field.DistanceM({4.0, 4.5}), field.max_distance_m());
}

// The geometry collected from the map: members, clipped line and discs.
TEST(LikelihoodFieldTest, CollectsTheFiniteGeometry) {
  const MapGeometry g = CollectMapGeometry(TestMap());
  ASSERT_EQ(g.segments.size(), 4u);  // segment, two members, the clipped line
  EXPECT_NEAR(g.segments[3].first.y(), 4.5, 1e-12);
  EXPECT_NEAR(std::min(g.segments[3].first.x(), g.segments[3].second.x()), 1.0, 1e-12);
  EXPECT_NEAR(std::max(g.segments[3].first.x(), g.segments[3].second.x()), 8.5, 1e-12);
  EXPECT_EQ(g.discs.size(), 3u);
  EXPECT_NEAR(g.bounds.hi.x(), 8.5, 1e-12);
  EXPECT_NEAR(g.bounds.hi.y(), 6.0, 1e-12);
}

// Every field is validated and named in the error.
TEST(LikelihoodFieldTest, ValidatesOptions) {
  const auto expect_field = [](LikelihoodFieldOptions o, const std::string& field) {
    try {
      o.Validate();
      ADD_FAILURE() << field << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  LikelihoodFieldOptions o;
  o.resolution_m = 0.0;
  expect_field(o, "resolution_m");
  o = {};
  o.margin_m = -1.0;
  expect_field(o, "margin_m");
  o = {};
  o.max_distance_m = 0.0;
  expect_field(o, "max_distance_m");
}

}  // namespace
}  // namespace pavilion::core
