// The social-navigation figures (metrics.md "Navigation and fleet",
// docs/crowd.md): Hall's zones surface to surface between a robot's footprint
// and visitors' body discs, on visitors moved by hand; the crowd figures on a
// small crowd; and their metrics.json sections.
#include "scenarios/metrics/social_navigation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "core/random/random_stream.h"
#include "core/types/pose2.h"
#include "scenarios/metrics/run_metrics.h"
#include "sim/crowd/social_force.h"

namespace pavilion::scenarios {
namespace {

using sim::crowd::PersonState;

constexpr double kDt = 0.005;  // a 200 Hz physics step

// A 0.8 m x 0.6 m rectangle about the base origin, counter-clockwise.
std::vector<Eigen::Vector2d> Rectangle() {
  return {{-0.4, -0.3}, {0.4, -0.3}, {0.4, 0.3}, {-0.4, 0.3}};
}

PersonState Visitor(const Eigen::Vector2d& position_m, double radius_m = 0.2) {
  PersonState p;
  p.position_m = position_m;
  p.shape.radius_m = radius_m;
  p.present = true;
  return p;
}

// Half the length of the line y = y0 along which a disc of radius r is within
// gap g of the box |x| <= hx, |y| <= hy (y0 > hy): the stretch over the box
// plus the run out to where the corner is g + r away.
double HalfStretch(double g, double hx, double hy, double y0, double r) {
  const double reach = g + r;
  const double dy = y0 - hy;
  return reach > dy ? hx + std::sqrt(reach * reach - dy * dy) : 0.0;
}

// A visitor walking straight past a robot turned by 90 degrees at a lateral
// offset spends the hand-computed times in each zone (each zone edge crossed
// may shift by one tick), intrudes once into each zone, and passes at the
// offset's gap.
TEST(SocialNavigationTrackerTest, VisitorWalkingPastGivesHandComputedZoneTimes) {
  SocialNavigationTracker tracker(Rectangle());
  // Turned by 90 degrees the robot covers |x| <= 0.3, |y| <= 0.4 in the world.
  const core::Pose2 robot{2.0, 1.0, std::numbers::pi / 2};
  constexpr double kHx = 0.3, kHy = 0.4, kY0 = 0.75, kR = 0.2, kSpeed = 1.0;
  std::vector<PersonState> people = {Visitor({0, 0}, kR)};
  const int steps = static_cast<int>(12.0 / (kSpeed * kDt));
  for (int k = 0; k <= steps; ++k) {
    people[0].position_m = {robot.x_m - 6.0 + k * kSpeed * kDt, robot.y_m + kY0};
    tracker.Update(kDt, robot, people);
  }
  ASSERT_TRUE(tracker.active());
  const SocialNavigationFigures f = tracker.Figures();
  const auto stretch_s = [&](double g) { return 2.0 * HalfStretch(g, kHx, kHy, kY0, kR) / kSpeed; };
  const double intimate_s = stretch_s(kIntimateZoneM);
  const double personal_s = stretch_s(kPersonalZoneM) - intimate_s;
  const double social_s = stretch_s(kSocialZoneM) - stretch_s(kPersonalZoneM);
  EXPECT_NEAR(f.intimate_time_s, intimate_s, 2 * kDt);  // two edges
  EXPECT_NEAR(f.personal_time_s, personal_s, 4 * kDt);  // four edges
  EXPECT_NEAR(f.social_time_s, social_s, 4 * kDt);
  EXPECT_NEAR(f.closer_than_0_2_m_time_s, stretch_s(kDiscomfortGapM), 2 * kDt);
  EXPECT_NEAR(f.min_visitor_gap_m, kY0 - kHy - kR, 1e-9);  // 0.15 m over the flank
  EXPECT_EQ(f.intimate_intrusions, 1);
  EXPECT_EQ(f.personal_intrusions, 1);
  EXPECT_EQ(f.social_intrusions, 1);
}

// Only the closest visitor's zone counts in a tick: two visitors, one in the
// intimate zone and one in the social zone, give intimate time only.
TEST(SocialNavigationTrackerTest, ZoneTimesAreDisjoint) {
  SocialNavigationTracker tracker(Rectangle());
  const std::vector<PersonState> people = {Visitor({0.4 + 0.2 + 2.0, 0}),
                                           Visitor({0.4 + 0.2 + 0.3, 0})};
  for (int k = 0; k < 200; ++k) tracker.Update(kDt, core::Pose2{}, people);
  const SocialNavigationFigures f = tracker.Figures();
  EXPECT_NEAR(f.intimate_time_s, 1.0, 1e-9);
  EXPECT_EQ(f.personal_time_s, 0.0);
  EXPECT_EQ(f.social_time_s, 0.0);
  EXPECT_EQ(f.closer_than_0_2_m_time_s, 0.0);
  EXPECT_EQ(f.social_intrusions, 2);  // both appeared inside the social disc
  EXPECT_EQ(f.personal_intrusions, 1);
  EXPECT_EQ(f.intimate_intrusions, 1);
}

// A visitor who appears already in the personal zone intrudes once there (and
// into the social zone around it), however long they stay; after leaving the
// floor and coming back they intrude again.
TEST(SocialNavigationTrackerTest, AppearingInsideCountsOnce) {
  SocialNavigationTracker tracker(Rectangle());
  std::vector<PersonState> people = {Visitor({0.4 + 0.2 + 0.8, 0})};  // gap 0.8 m
  for (int k = 0; k < 100; ++k) tracker.Update(kDt, core::Pose2{}, people);
  EXPECT_EQ(tracker.Figures().personal_intrusions, 1);
  EXPECT_EQ(tracker.Figures().social_intrusions, 1);
  EXPECT_EQ(tracker.Figures().intimate_intrusions, 0);
  EXPECT_NEAR(tracker.Figures().personal_time_s, 0.5, 1e-9);
  people[0].present = false;
  for (int k = 0; k < 10; ++k) tracker.Update(kDt, core::Pose2{}, people);
  people[0].present = true;
  tracker.Update(kDt, core::Pose2{}, people);
  EXPECT_EQ(tracker.Figures().personal_intrusions, 2);
  EXPECT_EQ(tracker.Figures().social_intrusions, 2);
  EXPECT_NEAR(tracker.Figures().personal_time_s, 0.505, 1e-9);
}

// Parked people (present = false) are ignored even on top of the robot; with
// only them the tracker stays inactive.
TEST(SocialNavigationTrackerTest, ParkedPeopleAreIgnored) {
  SocialNavigationTracker tracker(Rectangle());
  std::vector<PersonState> people = {Visitor({0, 0}), Visitor({0.1, 0.1})};
  for (PersonState& p : people) p.present = false;
  for (int k = 0; k < 100; ++k) tracker.Update(kDt, core::Pose2{}, people);
  EXPECT_FALSE(tracker.active());
  const SocialNavigationFigures f = tracker.Figures();
  EXPECT_EQ(f.intimate_time_s, 0.0);
  EXPECT_EQ(f.closer_than_0_2_m_time_s, 0.0);
  EXPECT_EQ(f.intimate_intrusions + f.personal_intrusions + f.social_intrusions, 0);
  EXPECT_TRUE(std::isinf(f.min_visitor_gap_m));
}

// The smallest gap is exact also for visitors far outside the social zone
// (the cheap distance test skips only those that cannot be closer), and
// negative in contact.
TEST(SocialNavigationTrackerTest, MinimumGapIsExactFarAndInContact) {
  SocialNavigationTracker tracker(Rectangle());
  std::vector<PersonState> people = {Visitor({10.0, 0}), Visitor({0, -20.0})};
  tracker.Update(kDt, core::Pose2{}, people);
  EXPECT_NEAR(tracker.Figures().min_visitor_gap_m, 10.0 - 0.4 - 0.2, 1e-12);
  people[1].position_m = {0, -6.0};
  tracker.Update(kDt, core::Pose2{}, people);
  EXPECT_NEAR(tracker.Figures().min_visitor_gap_m, 6.0 - 0.3 - 0.2, 1e-12);
  EXPECT_EQ(tracker.Figures().social_time_s, 0.0);
  people[1].position_m = {0, -0.45};  // the disc reaches 0.05 m into the hull
  tracker.Update(kDt, core::Pose2{}, people);
  EXPECT_NEAR(tracker.Figures().min_visitor_gap_m, -0.05, 1e-12);
  EXPECT_NEAR(tracker.Figures().closer_than_0_2_m_time_s, kDt, 1e-12);
}

// A clockwise footprint is reversed; too few vertices, a concave outline and
// a bad step are rejected with the field named.
// Most visitors' zones are settled by bounds on the gap (the footprint's
// circumradius and inradius about the base origin) without the hull
// distance. On a long footprint whose origin sits near one end, where the
// bounds lie a metre apart, thirty visitors wandering from contact to 5 m
// give exactly the figures of every gap measured: zone times, intrusions,
// the discomfort time and the smallest gap.
TEST(SocialNavigationTrackerTest, BoundsSettleZonesExactlyAsMeasuredGapsDo) {
  const std::vector<Eigen::Vector2d> hull = {
      {-0.1, -0.3}, {0.9, -0.3}, {1.1, 0.0}, {0.9, 0.3}, {-0.1, 0.3}};
  SocialNavigationTracker tracker(hull);
  core::RandomStream random(11, 0);
  std::vector<PersonState> people;
  for (int i = 0; i < 30; ++i) {
    const double a = random.Uniform(0.0, 2.0 * std::numbers::pi);
    const double r = random.Uniform(0.0, 5.0);
    people.push_back(Visitor({r * std::cos(a), r * std::sin(a)}, random.Uniform(0.15, 0.25)));
  }
  // The rule, every gap measured.
  SocialNavigationFigures expected;
  std::vector<int> zone(people.size(), 3);  // 0 intimate .. 3 outside
  const auto zone_of = [](double gap) {
    return gap < kIntimateZoneM ? 0 : gap < kPersonalZoneM ? 1 : gap < kSocialZoneM ? 2 : 3;
  };
  for (int step = 0; step < 4000; ++step) {
    const core::Pose2 robot{0.1 * std::sin(0.001 * step), 0.0, 0.002 * step};
    for (PersonState& p : people) {
      p.position_m += Eigen::Vector2d(random.Normal(0.0, 0.02), random.Normal(0.0, 0.02));
      p.position_m = p.position_m.cwiseMax(-5.0).cwiseMin(5.0);
    }
    tracker.Update(kDt, robot, people);
    const core::PointTransform robot_from_world(robot.Inverse());
    double closest = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < people.size(); ++i) {
      Eigen::Vector2d normal, point;
      const double gap = sim::crowd::SignedDistanceToConvex(
                             hull, robot_from_world.Apply(people[i].position_m), &normal, &point) -
                         people[i].shape.radius_m;
      closest = std::min(closest, gap);
      expected.min_visitor_gap_m = std::min(expected.min_visitor_gap_m, gap);
      const int now = zone_of(gap);
      expected.intimate_intrusions += now <= 0 && zone[i] > 0;
      expected.personal_intrusions += now <= 1 && zone[i] > 1;
      expected.social_intrusions += now <= 2 && zone[i] > 2;
      zone[i] = now;
    }
    const int z = zone_of(closest);
    if (z == 0) expected.intimate_time_s += kDt;
    if (z == 1) expected.personal_time_s += kDt;
    if (z == 2) expected.social_time_s += kDt;
    if (closest < kDiscomfortGapM) expected.closer_than_0_2_m_time_s += kDt;
  }
  const SocialNavigationFigures f = tracker.Figures();
  EXPECT_EQ(f.min_visitor_gap_m, expected.min_visitor_gap_m);
  EXPECT_EQ(f.intimate_intrusions, expected.intimate_intrusions);
  EXPECT_EQ(f.personal_intrusions, expected.personal_intrusions);
  EXPECT_EQ(f.social_intrusions, expected.social_intrusions);
  EXPECT_EQ(f.intimate_time_s, expected.intimate_time_s);
  EXPECT_EQ(f.personal_time_s, expected.personal_time_s);
  EXPECT_EQ(f.social_time_s, expected.social_time_s);
  EXPECT_EQ(f.closer_than_0_2_m_time_s, expected.closer_than_0_2_m_time_s);
  // The walk crossed every zone edge many times.
  EXPECT_GT(expected.intimate_intrusions, 10);
  EXPECT_GT(expected.social_intrusions, 10);
  EXPECT_GT(expected.closer_than_0_2_m_time_s, 0.0);
}

TEST(SocialNavigationTrackerTest, ValidatesItsInput) {
  std::vector<Eigen::Vector2d> clockwise = Rectangle();
  std::reverse(clockwise.begin(), clockwise.end());
  SocialNavigationTracker tracker(clockwise);
  tracker.Update(kDt, core::Pose2{}, {Visitor({1.0, 0})});
  EXPECT_NEAR(tracker.Figures().min_visitor_gap_m, 1.0 - 0.4 - 0.2, 1e-12);
  const std::vector<Eigen::Vector2d> segment = {{0, 0}, {1, 0}};
  EXPECT_THROW(SocialNavigationTracker{segment}, std::invalid_argument);
  const std::vector<Eigen::Vector2d> notched = {{0, 0}, {2, 0}, {1, 0.2}, {2, 2}, {0, 2}};
  EXPECT_THROW(SocialNavigationTracker{notched}, std::invalid_argument);
  EXPECT_THROW(tracker.Update(-kDt, core::Pose2{}, {}), std::invalid_argument);
  EXPECT_THROW(tracker.Update(std::nan(""), core::Pose2{}, {}), std::invalid_argument);
}

// An empty 20 m x 10 m room with its four walls, and a 1.2 m wide corridor
// along y = 5 from x = 4 to x = 16.
sim::crowd::CrowdSite Corridor() {
  sim::crowd::CrowdSite site;
  site.floor_min_m = {0, 0};
  site.floor_max_m = {20, 10};
  site.walls = {{{0, 0}, {20, 0}, 0}, {{20, 0}, {20, 10}, 1},   {{20, 10}, {0, 10}, 2},
                {{0, 10}, {0, 0}, 3}, {{4, 4.4}, {16, 4.4}, 4}, {{4, 5.6}, {16, 5.6}, 5}};
  site.entrance = {{0.5, 4}, {2, 4}, {2, 6}, {0.5, 6}};
  site.exit = {{18.5, 4.5}, {19.5, 4.5}, {19.5, 5.5}, {18.5, 5.5}};
  site.attractions = {{"goal", core::Pose2{18.0, 5.0, 0.0}, 1.0}};
  return site;
}

sim::crowd::CrowdOptions OneWayVisit(int pool) {
  sim::crowd::CrowdOptions options;
  options.pool_size = pool;
  options.max_present = pool;
  options.visit.min_exhibits = options.visit.max_exhibits = 1;
  options.visit.group_fraction = 0.0;
  options.watch_spots = 0;
  return options;
}

// The crowd figures follow the crowd: the pool, time-averaged and largest
// number present, no robot in anyone's way, no pushes without robots.
TEST(CrowdTrackerTest, FollowsTheCrowd) {
  sim::crowd::Crowd crowd(Corridor(), OneWayVisit(4), 3);
  CrowdTracker tracker;
  sim::crowd::CrowdStepResult result;
  const int steps = static_cast<int>(2.0 / kDt);
  for (int k = 0; k < steps; ++k) {
    if (k == steps / 2) {
      ASSERT_EQ(crowd.SpawnGroup({2.5, 2.0}, 2), 2);
    }
    crowd.Step(kDt, {}, &result);
    tracker.Update(kDt, crowd);
  }
  const CrowdFigures f = tracker.Figures();
  EXPECT_EQ(f.pool, 4);
  EXPECT_EQ(f.max_present, 2);
  EXPECT_NEAR(f.mean_present, 1.0, 2 * kDt);  // two visitors for half the time
  EXPECT_EQ(f.arrivals, crowd.arrivals());
  EXPECT_EQ(f.departures, 0);
  EXPECT_GE(f.max_overlap_m, 0.0);
  EXPECT_EQ(f.visitor_blocked_by_robot_s, 0.0);
  EXPECT_EQ(f.pushes, 0);
}

// A robot filling a corridor blocks a visitor who wants through it: nothing
// counts while the visitor walks up (about 3 s from 3 m to 6.7 m), then the
// blocked person-seconds grow while they stand pressed against the robot's
// repulsion. Their speed there hovers about the 0.1 m/s blocked threshold, so
// at least half of the standing time is asked for, not all of it.
TEST(CrowdTrackerTest, CountsVisitorsBlockedByARobot) {
  sim::crowd::Crowd crowd(Corridor(), OneWayVisit(1), 5);
  ASSERT_EQ(crowd.SpawnGroup({3.0, 5.0}, 1), 1);
  std::vector<sim::crowd::CrowdRobot> robots(1);
  robots[0].pose = {8.0, 5.0, 0.0};
  robots[0].footprint_in_robot_m = {{-0.4, -0.55}, {0.4, -0.55}, {0.4, 0.55}, {-0.4, 0.55}};
  CrowdTracker tracker;
  sim::crowd::CrowdStepResult result;
  const auto run = [&](double duration_s) {
    for (int k = 0; k < static_cast<int>(duration_s / kDt); ++k) {
      result.contacts.clear();
      result.pushes.clear();
      crowd.Step(kDt, robots, &result);
      tracker.Update(kDt, crowd);
    }
  };
  run(3.0);
  EXPECT_EQ(tracker.Figures().visitor_blocked_by_robot_s, 0.0);
  run(3.0);  // slowing down in front of the robot
  const double standing_from_s = tracker.Figures().visitor_blocked_by_robot_s;
  constexpr double kStandingS = 14.0;
  run(kStandingS);
  ASSERT_LT(crowd.person(0).position_m.x(), 8.0);  // still on this side
  const double blocked_s = tracker.Figures().visitor_blocked_by_robot_s - standing_from_s;
  EXPECT_GT(blocked_s, 0.5 * kStandingS);
  EXPECT_LE(blocked_s, kStandingS + 1e-9);
}

// metrics.json holds the robot's `social` and the run's `crowd` sections only
// when they are set, keys in order, figures rounded to 4 places.
TEST(SocialNavigationJsonTest, SectionsOnlyWhenSet) {
  RunMetrics m;
  m.scenario = "crowd";
  RobotMetrics r;
  r.id = "r1";
  r.model = "robox";
  m.robots = {r};
  nlohmann::ordered_json j = MetricsToJson(m);
  EXPECT_FALSE(j["robots"]["r1"].contains("social"));
  EXPECT_FALSE(j.contains("crowd"));

  SocialNavigationFigures s;
  s.intimate_time_s = 1.234567;
  s.personal_time_s = 2.0;
  s.social_time_s = 3.0;
  s.intimate_intrusions = 1;
  s.personal_intrusions = 2;
  s.social_intrusions = 3;
  s.min_visitor_gap_m = -0.012345;
  s.closer_than_0_2_m_time_s = 0.5;
  m.robots[0].social = s;
  CrowdFigures c;
  c.pool = 100;
  c.arrivals = 40;
  c.departures = 10;
  c.mean_present = 29.87654;
  c.max_present = 35;
  c.max_overlap_m = 0.00123;
  c.visitor_blocked_by_robot_s = 12.5;
  c.pushes = 2;
  m.crowd = c;
  j = MetricsToJson(m);
  const nlohmann::ordered_json& social = j["robots"]["r1"]["social"];
  const std::vector<std::string> social_keys = {
      "intimate_time_s",     "personal_time_s",   "social_time_s",     "intimate_intrusions",
      "personal_intrusions", "social_intrusions", "min_visitor_gap_m", "closer_than_0_2_m_s"};
  std::vector<std::string> keys;
  for (const auto& [key, value] : social.items()) keys.push_back(key);
  EXPECT_EQ(keys, social_keys);
  EXPECT_DOUBLE_EQ(social["intimate_time_s"].get<double>(), 1.2346);
  EXPECT_DOUBLE_EQ(social["min_visitor_gap_m"].get<double>(), -0.0123);
  EXPECT_EQ(social["social_intrusions"], 3);
  const std::vector<std::string> crowd_keys = {
      "pool",        "arrivals",      "departures",     "mean_present",
      "max_present", "max_overlap_m", "max_overlap_by", "visitor_blocked_by_robot_s",
      "pushes",      "episodes"};
  keys.clear();
  for (const auto& [key, value] : j["crowd"].items()) keys.push_back(key);
  EXPECT_EQ(keys, crowd_keys);
  EXPECT_DOUBLE_EQ(j["crowd"]["mean_present"].get<double>(), 29.8765);
  EXPECT_EQ(j["crowd"]["max_present"], 35);
  EXPECT_EQ(j["crowd"]["pushes"], 2);
}

}  // namespace
}  // namespace pavilion::scenarios
