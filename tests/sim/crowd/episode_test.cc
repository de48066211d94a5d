// Visitors near robots in the episodes of thesis §6.5 (curious, crowding,
// blocking, following, pushing): they keep a standing gap to their robot and
// do not lean on it; only pushers touch it on purpose (docs/crowd.md).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "sim/crowd/crowd.h"
#include "sim/crowd/episode_spot.h"
#include "sim/crowd/floor_field.h"
#include "sim/crowd/robot_avoidance.h"
#include "tests/sim/crowd/crowd_test_site.h"

namespace pavilion::sim::crowd {
namespace {

constexpr double kDt = 0.005;

using testing::EmptyRoom;
using testing::Octagon;

// Everyone behaves so, in episodes that outlast the test.
CrowdOptions Behaving(Behaviour behaviour, int people) {
  CrowdOptions options;
  options.pool_size = people;
  options.max_present = people;
  options.visit.min_exhibits = options.visit.max_exhibits = 0;
  options.visit.group_fraction = 0.0;
  options.watch_spots = 0;
  BehaviourOptions& b = options.behaviours;
  b.curious = behaviour == Behaviour::kCurious ? 1.0 : 0.0;
  b.crowding = behaviour == Behaviour::kCrowding ? 1.0 : 0.0;
  b.blocking = behaviour == Behaviour::kBlocking ? 1.0 : 0.0;
  b.following = behaviour == Behaviour::kFollowing ? 1.0 : 0.0;
  b.pushing = behaviour == Behaviour::kPushing ? 1.0 : 0.0;
  b.episode_mean_s = 600.0;
  return options;
}

CrowdRobot StandingRobot(const core::Pose2& pose) {
  CrowdRobot robot;
  robot.pose = pose;
  robot.footprint_in_robot_m = Octagon();
  return robot;
}

// Person i's gap to the robot's hull (surface to surface), m.
double Gap(const Crowd& crowd, int i, const CrowdRobot& robot) {
  std::vector<Eigen::Vector2d> hull;
  for (const Eigen::Vector2d& v : robot.footprint_in_robot_m) hull.push_back(robot.pose * v);
  Eigen::Vector2d n, c;
  return SignedDistanceToConvex(hull, crowd.person(i).position_m, &n, &c) -
         crowd.person(i).shape.radius_m;
}

// What the crowd did to the robot over a stretch of a run.
struct Pressing {
  double contact_impulse_ns = 0.0;  // Σ |contact force| dt
  double max_contact_n = 0.0;       // the largest summed contact force in a step
  Eigen::Vector2d last_net_n{0, 0};
  std::vector<RobotPush> pushes;
};

Pressing RunFor(Crowd* crowd, const std::vector<CrowdRobot>& robots, double seconds) {
  Pressing p;
  CrowdStepResult result;
  for (int step = 0; step < static_cast<int>(seconds / kDt); ++step) {
    result.contacts.clear();
    result.pushes.clear();
    crowd->Step(kDt, robots, &result);
    Eigen::Vector2d net = Eigen::Vector2d::Zero();
    for (const RobotContactForce& f : result.contacts) {
      net += f.force_n;
      p.contact_impulse_ns += f.force_n.norm() * kDt;
    }
    p.max_contact_n = std::max(p.max_contact_n, net.norm());
    p.last_net_n = net;
    for (const RobotPush& push : result.pushes) p.pushes.push_back(push);
  }
  return p;
}

// A curious visitor who notices a standing Robox from behind walks round it
// and stands in front at a gap, touching it never. (Before, the robot it was
// curious about did not repel it and it walked straight at the place in
// front, through the robot: it leaned on the robot's back with its whole
// driving force, about 200 N, for the length of the episode.)
TEST(EpisodeTest, CuriousVisitorStandsInFrontAtAGap) {
  for (int seed = 1; seed <= 10; ++seed) {
    Crowd crowd(EmptyRoom(), Behaving(Behaviour::kCurious, 1), seed);
    ASSERT_EQ(crowd.SpawnGroup({8.0, 5.0 + 0.02 * seed}, 1), 1);
    const std::vector<CrowdRobot> robots = {StandingRobot({10.0, 5.0, 0.0})};
    const Pressing approach = RunFor(&crowd, robots, 20.0);
    const Pressing standing = RunFor(&crowd, robots, 10.0);
    EXPECT_EQ(crowd.activity(0), Activity::kEpisode) << "seed " << seed;
    EXPECT_LT(approach.contact_impulse_ns, 5.0) << "seed " << seed;
    EXPECT_EQ(standing.contact_impulse_ns, 0.0) << "seed " << seed;
    const double gap = Gap(crowd, 0, robots[0]);
    EXPECT_GT(gap, 0.45) << "seed " << seed;
    EXPECT_LT(gap, 1.0) << "seed " << seed;
    EXPECT_GT(crowd.person(0).position_m.x(), 10.6) << "seed " << seed;  // in front
    EXPECT_LT(crowd.person(0).velocity_mps.norm(), 0.1) << "seed " << seed;
    // Standing at its robot on purpose, it is not blocked by it.
    EXPECT_FALSE(crowd.blocked_by_robot(0)) << "seed " << seed;
  }
}

// Three visitors crowding round a standing robot they came upon from behind
// form their U at a gap: the crowd exerts no force on the robot. (Before, a
// U of three pressed a Robox with 250-630 N.)
TEST(EpisodeTest, CrowdingUExertsNoForceOnTheRobot) {
  for (int seed = 1; seed <= 10; ++seed) {
    Crowd crowd(EmptyRoom(), Behaving(Behaviour::kCrowding, 3), seed);
    ASSERT_EQ(crowd.SpawnGroup({8.3, 5.0}, 3), 3);
    const std::vector<CrowdRobot> robots = {StandingRobot({10.0, 5.0, 0.0})};
    const Pressing approach = RunFor(&crowd, robots, 20.0);
    const Pressing standing = RunFor(&crowd, robots, 10.0);
    EXPECT_LT(approach.max_contact_n, 300.0) << "seed " << seed;
    EXPECT_EQ(standing.contact_impulse_ns, 0.0) << "seed " << seed;
    EXPECT_EQ(standing.last_net_n.norm(), 0.0) << "seed " << seed;
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(crowd.activity(i), Activity::kEpisode) << "seed " << seed;
      EXPECT_GT(Gap(crowd, i, robots[0]), 0.3) << "seed " << seed << " person " << i;
    }
  }
}

// A robot standing with its front 0.4 m from a wall: the place in front of
// it lies in the wall. The curious visitor stands beside the robot instead,
// on the floor, and does not press into the robot or the wall.
TEST(EpisodeTest, CuriousPlaceInAWallMovesToFreeFloor) {
  for (int seed = 1; seed <= 10; ++seed) {
    Crowd crowd(EmptyRoom(), Behaving(Behaviour::kCurious, 1), seed);
    ASSERT_EQ(crowd.SpawnGroup({10.0 + 0.05 * seed, 7.0}, 1), 1);
    const std::vector<CrowdRobot> robots = {
        StandingRobot({10.0, 9.25, std::numbers::pi / 2})};  // facing the wall at y = 10
    RunFor(&crowd, robots, 20.0);
    const Pressing standing = RunFor(&crowd, robots, 10.0);
    EXPECT_EQ(standing.contact_impulse_ns, 0.0) << "seed " << seed;
    const Eigen::Vector2d& p = crowd.person(0).position_m;
    EXPECT_LT(p.y(), 10.0 - crowd.person(0).shape.radius_m) << "seed " << seed;
    EXPECT_GT(Gap(crowd, 0, robots[0]), 0.3) << "seed " << seed;
    EXPECT_LT(crowd.person(0).velocity_mps.norm(), 0.1) << "seed " << seed;
  }
}

// A pusher still walks up and pushes: 200 N for 0.5 s, or a kick at the
// 300 N limit for 0.1 s, on the robot's hull.
TEST(EpisodeTest, PusherStillPushes) {
  int pushes = 0, kicks = 0;
  for (int seed = 1; seed <= 10; ++seed) {
    Crowd crowd(EmptyRoom(), Behaving(Behaviour::kPushing, 1), seed);
    ASSERT_EQ(crowd.SpawnGroup({8.0, 5.3}, 1), 1);
    const std::vector<CrowdRobot> robots = {StandingRobot({10.0, 5.0, 0.0})};
    const Pressing run = RunFor(&crowd, robots, 10.0);
    EXPECT_EQ(crowd.pushes(), 1) << "seed " << seed;
    ASSERT_FALSE(run.pushes.empty()) << "seed " << seed;
    const bool kick = run.pushes.front().kick;
    (kick ? kicks : pushes) += 1;
    const double seconds = static_cast<double>(run.pushes.size()) * kDt;
    EXPECT_NEAR(seconds, kick ? 0.1 : 0.5, 0.06) << "seed " << seed;
    for (const RobotPush& p : run.pushes) {
      EXPECT_NEAR(p.force_n.norm(), kick ? 300.0 : 200.0, 1e-9);
      EXPECT_GT(p.force_n.x(), 0.0);  // towards the robot, from behind-left
    }
  }
  EXPECT_GT(pushes, 0);
  EXPECT_GT(kicks, 0);
}

// Someone touching a robot does not keep walking into it: the component of
// the wish into the robot goes, the rest stays; a robot not touched leaves
// the wish alone.
TEST(EpisodeTest, TouchingARobotRemovesTheWishIntoIt) {
  RobotObstacle robot;
  for (const Eigen::Vector2d& v : Octagon()) robot.hull_m.push_back(v);
  const std::vector<RobotObstacle> robots = {robot};
  const double radius = 0.22;
  const Eigen::Vector2d wish(-1.0, 0.5);  // into the robot and along it
  const Eigen::Vector2d touching = NotIntoRobots({0.34 + radius + 0.01, 0.0}, radius, wish, robots);
  EXPECT_NEAR(touching.x(), 0.0, 1e-12);
  EXPECT_NEAR(touching.y(), 0.5, 1e-12);
  const Eigen::Vector2d away = NotIntoRobots({0.34 + radius + 0.01, 0.0}, radius, -wish, robots);
  EXPECT_EQ(away, -wish);
  const Eigen::Vector2d apart = NotIntoRobots({0.34 + radius + 0.3, 0.0}, radius, wish, robots);
  EXPECT_EQ(apart, wish);
}

// Free-floor queries of the episode places: a place in a wall or its
// clearance, one on a robot and one behind a wall are refused; SpotAround
// turns round the robot to the first that is not.
TEST(EpisodeTest, StandingPlacesAreFreeReachableFloor) {
  // A 10 m x 10 m room split at x = 5 by a wall with a door at y in [8, 9].
  std::vector<ObstacleSegment> segments = {{{0, 0}, {10, 0}},   {{10, 0}, {10, 10}},
                                           {{10, 10}, {0, 10}}, {{0, 10}, {0, 0}},
                                           {{5, 0}, {5, 8}},    {{5, 9}, {5, 10}}};
  const WalkableGrid grid({0, 0}, {10, 10}, segments, {}, {0.2, 0.3});
  const DistanceField exit = DistanceField::ToDisc(grid, {9, 1}, 0.5);
  RobotObstacle robot;
  for (const Eigen::Vector2d& v : Octagon()) robot.hull_m.push_back(v + Eigen::Vector2d(3, 5));
  const std::vector<RobotObstacle> robots = {robot};
  const StandingFloor floor{&grid, &exit, robots};
  EXPECT_TRUE(CanStand(floor, {2, 2}, 0.22));
  EXPECT_FALSE(CanStand(floor, {5.1, 2}, 0.22));  // the wall's clearance
  EXPECT_FALSE(CanStand(floor, {3, 5}, 0.22));    // on the robot
  EXPECT_FALSE(CanStand(floor, {3.5, 5}, 0.22));  // its body would touch it
  EXPECT_FALSE(CanStand(floor, {12, 5}, 0.22));   // off the floor
  EXPECT_TRUE(ClearWalk(grid, {2, 2}, {4, 3}));
  EXPECT_FALSE(ClearWalk(grid, {4, 3}, {6, 3}));     // through the wall
  EXPECT_TRUE(ClearWalk(grid, {4, 8.5}, {6, 8.5}));  // through the door
  // In front of the robot (facing +x) 1.6 m out lies in the wall: the place
  // turns 15 deg at a time, + first, to free floor on the person's side.
  const std::optional<Eigen::Vector2d> spot =
      SpotAround(floor, {3, 5}, 1.6, 0.0, std::numbers::pi / 12, 6, {2, 5}, 0.22);
  ASSERT_TRUE(spot.has_value());
  EXPECT_LT(spot->x(), 5.0 - 0.3);
  EXPECT_TRUE(CanStand(floor, *spot, 0.22));
  // Against the wall with no turn allowed: none, the visitor waits.
  EXPECT_FALSE(SpotAround(floor, {4, 5}, 1.0, 0.0, std::numbers::pi / 12, 0, {3, 5}, 0.22));
}

}  // namespace
}  // namespace pavilion::sim::crowd
