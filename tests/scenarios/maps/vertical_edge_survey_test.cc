// The vertical edges a camera sees (issue 19), surveyed from a world built
// here: a room's inside and outside corners, the corners where a wall runs
// into another, a wall's free end, a tall box's corners, a door's leaf as
// surveyed; no edge on a low box, a column or a flat face.
#include "scenarios/maps/vertical_edge_survey.h"

#include <gtest/gtest.h>

#include <numbers>
#include <stdexcept>
#include <vector>

#include "sim/world/world.h"

namespace pavilion::scenarios {
namespace {

using Vec2 = Eigen::Vector2d;

sim::WorldDescription Room() {
  sim::WorldDescription d;
  d.name = "survey";
  d.materials["grey"] = sim::Material{};
  d.floor.min_m = {-1, -1};
  d.floor.max_m = {11, 9};
  d.floor.material = "grey";
  // A closed 10 x 8 m room, walls 0.2 m thick centred on the outline.
  sim::Wall outer;
  outer.id = "outer";
  outer.points_m = {{0, 0}, {10, 0}, {10, 8}, {0, 8}};
  outer.closed = true;
  outer.material = "grey";
  d.walls.push_back(outer);
  // A partition from the south wall up to y = 4 (free end there).
  sim::Wall partition;
  partition.id = "partition";
  partition.points_m = {{5, 0}, {5, 4}};
  partition.material = "grey";
  d.walls.push_back(partition);
  sim::Box tall;
  tall.id = "cabinet";
  tall.pose = {2.5, 5.5, 0.0};
  tall.size_m = {1.0, 0.6, 1.8};
  tall.material = "grey";
  d.boxes.push_back(tall);
  sim::Box low = tall;
  low.id = "bench";
  low.pose = {7.5, 5.5, 0.0};
  low.size_m = {1.0, 0.6, 0.45};
  d.boxes.push_back(low);
  sim::Cylinder column;
  column.id = "column";
  column.position_m = {7.5, 2.0};
  column.radius_m = 0.2;
  column.height_m = 2.5;
  column.material = "grey";
  d.cylinders.push_back(column);
  sim::Door door;
  door.id = "door";
  door.hinge_m = {2.0, 2.0};
  door.width_m = 0.9;
  door.material = "grey";
  d.doors.push_back(door);
  return d;
}

bool Has(const std::vector<SurveyedEdge>& edges, const Vec2& p, const std::string& element) {
  for (const SurveyedEdge& e : edges) {
    if ((e.position_m - p).norm() < 1e-6 && e.element == element) return true;
  }
  return false;
}

VerticalEdgeSurveyOptions FramesOnly() {
  VerticalEdgeSurveyOptions o;
  o.doors = false;
  return o;
}

TEST(VerticalEdgeSurveyTest, FindsTheCornersACameraSees) {
  const sim::World world(Room(), {});
  const std::vector<SurveyedEdge> edges = SurveyVerticalEdges(world, FramesOnly());
  // The room's four inside corners (wall faces 0.1 m inside the outline).
  EXPECT_TRUE(Has(edges, {0.1, 0.1}, "outer"));
  EXPECT_TRUE(Has(edges, {9.9, 0.1}, "outer"));
  EXPECT_TRUE(Has(edges, {9.9, 7.9}, "outer"));
  EXPECT_TRUE(Has(edges, {0.1, 7.9}, "outer"));
  // Where the partition meets the south wall's face: two concave corners,
  // vertices of neither wall's outline; its free end: two convex corners.
  int junction = 0;
  for (const SurveyedEdge& e : edges) {
    if ((e.position_m - Vec2(4.9, 0.1)).norm() < 1e-6 ||
        (e.position_m - Vec2(5.1, 0.1)).norm() < 1e-6) {
      ++junction;
    }
  }
  EXPECT_EQ(junction, 2);
  EXPECT_TRUE(Has(edges, {4.9, 4.0}, "partition"));
  EXPECT_TRUE(Has(edges, {5.1, 4.0}, "partition"));
  // The tall cabinet's four corners.
  for (const Vec2& c : {Vec2(2.0, 5.2), Vec2(3.0, 5.2), Vec2(3.0, 5.8), Vec2(2.0, 5.8)}) {
    EXPECT_TRUE(Has(edges, c, "cabinet")) << c.transpose();
  }
  // The building's four outside corners (seen from outside: the map
  // derivation keeps only edges its robots' free space sees).
  EXPECT_TRUE(Has(edges, {-0.1, -0.1}, "outer"));
  EXPECT_TRUE(Has(edges, {10.1, 8.1}, "outer"));
  EXPECT_EQ(edges.size(), 4u + 4u + 2u + 2u + 4u);
  for (const SurveyedEdge& e : edges) {
    EXPECT_NE(e.element, "bench");   // below the band
    EXPECT_NE(e.element, "door");    // doors left out
    EXPECT_NE(e.element, "column");  // a silhouette, not a fixed edge
    EXPECT_NEAR(e.outward.norm(), 1.0, 1e-12);
  }
}

// A door's leaf as the surveyor found it (closed here: from its hinge at
// (2, 2) along +x, 0.9 m by 4 cm): its four corners.
TEST(VerticalEdgeSurveyTest, DoorLeavesAsSurveyed) {
  const sim::World world(Room(), {});
  const std::vector<SurveyedEdge> edges = SurveyVerticalEdges(world, {});
  int leaf = 0;
  for (const SurveyedEdge& e : edges) leaf += e.element == "door" ? 1 : 0;
  EXPECT_EQ(leaf, 4);
  EXPECT_EQ(edges.size(), SurveyVerticalEdges(world, FramesOnly()).size() + 4);
}

TEST(VerticalEdgeSurveyTest, OutwardPointsIntoFreeSpace) {
  const sim::World world(Room(), {});
  for (const SurveyedEdge& e : SurveyVerticalEdges(world, {})) {
    if ((e.position_m - Vec2(0.1, 0.1)).norm() < 1e-6) {  // the room's corner: into the room
      EXPECT_NEAR(e.outward.x(), std::sqrt(0.5), 0.05);
      EXPECT_NEAR(e.outward.y(), std::sqrt(0.5), 0.05);
    }
    if ((e.position_m - Vec2(3.0, 5.8)).norm() < 1e-6) {  // the cabinet's: away from it
      EXPECT_GT(e.outward.x(), 0.5);
      EXPECT_GT(e.outward.y(), 0.5);
    }
  }
}

TEST(VerticalEdgeSurveyTest, RejectsBadOptions) {
  const sim::World world(Room(), {});
  VerticalEdgeSurveyOptions o;
  o.low_m = 1.5;  // above high_m
  EXPECT_THROW(SurveyVerticalEdges(world, o), std::invalid_argument);
  o = {};
  o.min_turn_rad = 0.0;
  EXPECT_THROW(SurveyVerticalEdges(world, o), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::scenarios
