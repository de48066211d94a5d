#include "nav/mission/command_queue.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace pavilion::nav {
namespace {

std::vector<QueuedNode> ThreeNodes() {
  return {{"via_a", {2.0, 0.0}}, {"via_b", {6.0, 0.0}}, {"goal", {10.0, 0.0}}};
}

// Via nodes are passed inside their 2 m disk (§6.3.3), in order, never skipped.
TEST(CommandQueueTest, ViaNodesPassInsideTheirDisk) {
  CommandQueue q{CommandQueueOptions{}};
  q.Load(ThreeNodes(), {10.0, 0.0, 0.0});
  q.Update({-0.5, 0.0, 0.0});
  EXPECT_EQ(q.current().id, "via_a");  // 2.5 m away: outside the disk
  q.Update({0.1, 0.0, 0.0});
  EXPECT_EQ(q.current().id, "via_b");  // 1.9 m from via_a: reached
  EXPECT_FALSE(q.at_goal_node());
  q.Update({4.05, 0.0, 0.0});
  EXPECT_EQ(q.current().id, "goal");
  EXPECT_TRUE(q.at_goal_node());
  EXPECT_EQ(q.remaining().size(), 1u);
}

// With the map's walls, a via node in front of a door counts as passed only
// once the room's station behind it is in sight: the robot 1.9 m east of the
// door's via node, in the hallway, still works towards the via node.
TEST(CommandQueueTest, ViaNodePassesOnlyWhenItsSuccessorIsInSight) {
  CommandQueue q{CommandQueueOptions{}};
  // The room's wall along y = 1 with a door between x = -0.5 and 0.5.
  q.SetWalls({{{-10.0, 1.0}, {-0.5, 1.0}}, {{0.5, 1.0}, {10.0, 1.0}}});
  q.Load({{"via_door", {0.0, 0.5}}, {"station", {0.5, 4.0}}}, {0.5, 4.0, 0.0});
  q.Update({1.9, 0.3, 0.0});
  EXPECT_EQ(q.current().id, "via_door");  // in the disk, the station behind the wall
  q.Update({0.1, 0.4, 0.0});
  EXPECT_EQ(q.current().id, "station");  // in front of the door: in sight
  // Without walls the disk alone passes it (the thesis' rule).
  CommandQueue open{CommandQueueOptions{}};
  open.Load({{"via_door", {0.0, 0.5}}, {"station", {0.5, 4.0}}}, {0.5, 4.0, 0.0});
  open.Update({1.9, 0.3, 0.0});
  EXPECT_EQ(open.current().id, "station");
}

// With a clearance, the robot must see the next node with room for its body:
// from beside the door the centre line passes the opening but one of its
// parallels 0.3 m aside hits the wall (a square robot would enter askew and
// jam); from in front of the door all three pass.
TEST(CommandQueueTest, SightNeedsRoomForTheBody) {
  CommandQueue q{CommandQueueOptions{}};
  // A 0.9 m door between x = -0.45 and 0.45 in a wall along y = 1.
  q.SetWalls({{{-10.0, 1.0}, {-0.45, 1.0}}, {{0.45, 1.0}, {10.0, 1.0}}}, 0.3);
  q.Load({{"via_door", {0.0, 0.0}}, {"station", {0.0, 4.0}}}, {0.0, 4.0, 0.0});
  q.Update({-0.4, 0.2, 0.0});  // the centre line crosses y = 1 at x = -0.33: in the door
  EXPECT_EQ(q.current().id, "via_door");
  q.Update({0.02, 0.1, 0.0});
  EXPECT_EQ(q.current().id, "station");
}

// The goal node is never passed by its disk: it needs the full pose.
TEST(CommandQueueTest, GoalNeedsTheFullPose) {
  CommandQueue q{CommandQueueOptions{}};
  q.Load(ThreeNodes(), {10.0, 0.0, 1.0});
  q.Update({5.0, 0.0, 1.0});  // inside via_b's disk, never near via_a: both passed
  EXPECT_TRUE(q.at_goal_node());
  q.Update({9.0, 0.0, 1.0});
  EXPECT_TRUE(q.at_goal_node());
  EXPECT_FALSE(q.arrived());
  q.Update({10.01, 0.0, 0.0});  // in position, heading 1 rad off
  EXPECT_FALSE(q.arrived());
  q.Update({10.01, 0.0, 0.98});
  EXPECT_TRUE(q.arrived());
  EXPECT_FALSE(q.empty());
}

// Localization pauses within 10 cm of the final goal and resumes only when the
// robot is pushed well away from it (hysteresis), never near a via node.
TEST(CommandQueueTest, LocalizationPausesNearTheGoalOnly) {
  CommandQueue q{CommandQueueOptions{}};
  q.Load({{"via", {1.0, 0.0}}, {"goal", {1.0, 0.0}}}, {1.0, 0.05, 0.0});
  q.Update({1.0, 0.0, 0.0});  // on the via node: passes it, now 5 cm from the goal
  EXPECT_TRUE(q.at_goal_node());
  EXPECT_TRUE(q.localization_paused());
  q.Update({1.0, 0.25, 0.0});  // 20 cm off: still paused
  EXPECT_TRUE(q.localization_paused());
  q.Update({1.0, 0.5, 0.0});  // 45 cm off: resumes
  EXPECT_FALSE(q.localization_paused());
  q.Clear();
  EXPECT_TRUE(q.empty());
  EXPECT_FALSE(q.localization_paused());
}

// A plan of the goal alone (the robot starts next to it) works; an empty plan is refused.
TEST(CommandQueueTest, SingleNodePlanAndEmptyPlan) {
  CommandQueue q{CommandQueueOptions{}};
  q.Load({{"goal", {0.0, 0.0}}}, {0.5, 0.5, 0.0});
  EXPECT_TRUE(q.at_goal_node());
  EXPECT_DOUBLE_EQ(q.current().position_m.x(), 0.5);  // the pose replaces the node's position
  EXPECT_THROW(q.Load({}, {}), std::invalid_argument);
}

// Options are validated naming the field.
TEST(CommandQueueTest, ValidatesOptions) {
  CommandQueueOptions o;
  o.via_reached_radius_m = 0.0;
  try {
    o.Validate();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("via_reached_radius_m"), std::string::npos);
  }
}

}  // namespace
}  // namespace pavilion::nav
