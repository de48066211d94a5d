// The robot map's picture (scenarios/maps/map_render.h) in the thesis' style:
// its legend names exactly the kinds of item the map holds; vertical edges
// are crosses, columns circles; a scale bar and the legend are drawn.
#include "scenarios/maps/map_render.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace pavilion::scenarios {
namespace {

std::vector<std::string> Labels(const std::vector<LegendEntry>& legend) {
  std::vector<std::string> labels;
  for (const LegendEntry& e : legend) labels.push_back(e.label);
  return labels;
}

core::MapPoint Point(const std::string& id, const Eigen::Vector2d& p, double radius_m) {
  core::MapPoint point;
  point.id = id;
  point.point.position_m = p;
  point.radius_m = radius_m;
  return point;
}

// A wall along y = 0 seen from above (alpha = -90 deg, r = 0).
core::MapSegment Wall() {
  core::MapSegment s;
  s.id = "wall";
  s.line.alpha_rad = -0.5 * 3.14159265358979323846;
  s.first_endpoint.position_m = {0.0, 0.0};
  s.second_endpoint.position_m = {4.0, 0.0};
  return s;
}

// The legend grows with the map, one row per kind present, features first:
// an empty map has none; points of radius 0 are vertical edges, others columns.
TEST(MapLegendTest, NamesExactlyTheKindsTheMapHolds) {
  core::RobotMap map;
  EXPECT_TRUE(MapLegend(map).empty());
  map.points.push_back(Point("edge_001", {1, 1}, 0.0));
  EXPECT_EQ(Labels(MapLegend(map)), std::vector<std::string>{"vertical edge"});
  map.segments.push_back(Wall());
  map.points.push_back(Point("edge_002", {2, 1}, 0.0));
  EXPECT_EQ(Labels(MapLegend(map)), (std::vector<std::string>{"map line", "vertical edge"}));
  map.points.push_back(Point("column", {3, 2}, 0.2));
  map.nodes.push_back({"via_1", core::Pose2(1.0, 2.0, 0.0), false});
  map.nodes.push_back({"via_2", core::Pose2(2.0, 2.0, 0.0), false});
  map.edges.push_back({"via_1", "via_2", 1.0});
  map.ghost_points.push_back({"ghost_1", {0.5, 0.5}});
  EXPECT_EQ(Labels(MapLegend(map)),
            (std::vector<std::string>{"map line", "vertical edge", "column", "via node",
                                      "graph edge", "ghost point"}));
  map.points.erase(map.points.begin(), map.points.begin() + 2);  // the edges
  map.nodes.push_back({"desk", core::Pose2(3.0, 3.0, 0.0), true});
  map.beacons.push_back({"beacon_1", {}, 0.0});
  EXPECT_EQ(Labels(MapLegend(map)),
            (std::vector<std::string>{"map line", "column", "beacon", "station", "via node",
                                      "graph edge", "ghost point"}));
}

bool IsBlack(const core::RgbImage& image, int x, int y) {
  const std::size_t i = (static_cast<std::size_t>(y) * image.width + x) * 3;
  return image.pixels[i] == 0 && image.pixels[i + 1] == 0 && image.pixels[i + 2] == 0;
}

// A lone vertical edge is drawn as an upright black cross: its arms are ink,
// its diagonals not; the picture also carries a scale bar and a legend (black
// text and bar in two corners, a 400 px picture of 2 m: 200 px per m).
TEST(MapRenderTest, VerticalEdgeIsACross) {
  core::RobotMap map;
  map.points.push_back(Point("edge_001", {1, 1}, 0.0));
  MapRenderOptions options;
  options.width_px = 400;
  const core::RgbImage image = RenderRobotMap(map, nullptr, options);
  ASSERT_EQ(image.width, 400);
  ASSERT_EQ(image.height, 400);
  // The point at the picture's centre, pixel corner (200, 200).
  for (const int d : {-3, -2, 2, 3}) {
    EXPECT_TRUE(IsBlack(image, 200 + d, 200)) << d;
    EXPECT_TRUE(IsBlack(image, 200, 200 + d)) << d;
    EXPECT_FALSE(IsBlack(image, 200 + d, 200 + d)) << d;
    EXPECT_FALSE(IsBlack(image, 200 + d, 200 - d)) << d;
  }
  EXPECT_FALSE(IsBlack(image, 206, 200));  // arms 4 px long
  int top_right = 0, bottom_left = 0;
  for (int y = 0; y < 60; ++y) {
    for (int x = 0; x < 200; ++x) {
      top_right += IsBlack(image, 399 - x, y);
      bottom_left += IsBlack(image, x, 399 - y);
    }
  }
  EXPECT_GT(top_right, 40);    // the legend's cross and "vertical edge"
  EXPECT_GT(bottom_left, 80);  // "50 cm" over its 100 px bar
}

}  // namespace
}  // namespace pavilion::scenarios
