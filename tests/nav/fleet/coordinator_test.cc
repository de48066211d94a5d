// Multi-robot planning (thesis §6.3.5): plan weights falling along the plan,
// their superposition on the board, the planner's choice on a small graph
// (two robots take disjoint nodes where a disjoint way exists), station
// reservations and the goal proposal among free stations, and the bytes.
#include "nav/fleet/coordinator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/random/random_stream.h"
#include "nav/mission/mission_sequence.h"
#include "nav/planning/graph_planner.h"
#include "nav/planning/topology_graph.h"

namespace pavilion::nav {
namespace {

// A ladder: start s, goal g, two parallel ways s-a1-a2-g (upper) and
// s-b1-b2-g (lower), the upper 0.1 m shorter so that a lone robot takes it.
struct Ladder {
  TopologyGraph graph;
  int s, a1, a2, b1, b2, g;
  Ladder() {
    s = graph.AddNode("s", {0, 0});
    a1 = graph.AddNode("a1", {1, 1});
    a2 = graph.AddNode("a2", {2, 1});
    b1 = graph.AddNode("b1", {1, -1});
    b2 = graph.AddNode("b2", {2, -1});
    g = graph.AddNode("g", {3, 0}, /*station=*/true);
    const auto both = [&](int u, int v, double w) {
      graph.AddArc(u, v, w);
      graph.AddArc(v, u, w);
    };
    both(s, a1, 1.4);
    both(a1, a2, 1.0);
    both(a2, g, 1.4);
    both(s, b1, 1.45);
    both(b1, b2, 1.0);
    both(b2, g, 1.45);
  }
};

TEST(PlanWeights, FallWithTheDistanceAlongThePlan) {
  FleetOptions o;
  const std::vector<int> nodes{3, 4, 5};
  const std::vector<Eigen::Vector2d> positions{{1, 0}, {3, 0}, {6, 0}};
  const std::vector<PathWeight> w = PlanWeights({0, 0}, nodes, positions, o);
  ASSERT_EQ(w.size(), 3u);
  EXPECT_NEAR(w[0].weight, o.peak_weight_m * std::exp(-1.0 / o.falloff_m), 1e-12);
  EXPECT_NEAR(w[1].weight, o.peak_weight_m * std::exp(-3.0 / o.falloff_m), 1e-12);
  EXPECT_NEAR(w[2].weight, o.peak_weight_m * std::exp(-6.0 / o.falloff_m), 1e-12);
  EXPECT_GT(w[0].weight, w[1].weight);
  EXPECT_EQ(w[2].node, 5);
  o.horizon_m = 4.0;  // the third node is 6 m along: not published
  EXPECT_EQ(PlanWeights({0, 0}, nodes, positions, o).size(), 2u);
}

TEST(FleetBoard, SuperposesTheOthersWeightsOnly) {
  FleetCoordinator c(3, {});
  c.Send(0, {{{1, 2.0}, {2, 1.0}}, std::nullopt, 0.0, -1, -1, {}});
  c.Send(1, {{{2, 0.5}}, std::nullopt, 0.0, 4, 5, {}});
  c.Send(2, {{{1, 3.0}}, std::nullopt, 0.0, -1, -1, {}});
  std::vector<double> costs(6, 0.0);
  c.board().AddOthersCosts(2, 100.0, &costs);  // nothing merged yet
  EXPECT_EQ(costs, std::vector<double>(6, 0.0));
  c.Merge();
  c.board().AddOthersCosts(2, 100.0, &costs);
  EXPECT_DOUBLE_EQ(costs[1], 2.0);  // robot 2's own 3.0 is left out
  EXPECT_DOUBLE_EQ(costs[2], 1.5);
  EXPECT_DOUBLE_EQ(costs[4], 100.0);  // reserved by robot 1
  EXPECT_DOUBLE_EQ(costs[5], 100.0);  // occupied by robot 1
  EXPECT_TRUE(c.board().StationTaken(4, 0));
  EXPECT_FALSE(c.board().StationTaken(4, 1));  // its own reservation
}

TEST(FleetCoordinator, TwoRobotsTakeDisjointWaysWhereOneExists) {
  Ladder l;
  FleetOptions o;
  FleetCoordinator c(2, o);
  // Robot 0 plans alone: the shorter, upper way.
  const std::optional<GraphPath> first = PlanGraphPath(l.graph, l.s, l.g);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->nodes, (std::vector<int>{l.s, l.a1, l.a2, l.g}));
  std::vector<Eigen::Vector2d> positions;
  for (int n : first->nodes) positions.push_back(l.graph.position(n));
  // Its goal is its own reservation, not a node on the way: publish the way.
  const std::vector<int> way(first->nodes.begin() + 1, first->nodes.end() - 1);
  const std::vector<Eigen::Vector2d> way_at(positions.begin() + 1, positions.end() - 1);
  c.Send(0, {PlanWeights(l.graph.position(l.s), way, way_at, o), std::nullopt, 0.0, -1, -1, {}});
  c.Merge();
  // Robot 1, on the superposed weights, goes the other way.
  std::vector<double> costs(l.graph.node_count(), 0.0);
  c.board().AddOthersCosts(1, o.occupied_station_cost_m, &costs);
  const std::optional<GraphPath> second = PlanGraphPath(l.graph, l.s, l.g, costs);
  ASSERT_TRUE(second);
  EXPECT_EQ(second->nodes, (std::vector<int>{l.s, l.b1, l.b2, l.g}));
  // Robot 0 itself still plans its own way: its weights do not count for it.
  std::vector<double> own(l.graph.node_count(), 0.0);
  c.board().AddOthersCosts(0, o.occupied_station_cost_m, &own);
  EXPECT_EQ(PlanGraphPath(l.graph, l.s, l.g, own)->nodes, first->nodes);
}

TEST(FleetCoordinator, AnotherRobotsWayIsTakenWhenNoOtherExists) {
  // A corridor s-m-g: the potential field cannot forbid the only way (§6.3.5:
  // no guarantee of collision freeness), it only makes it cost more.
  TopologyGraph g;
  const int s = g.AddNode("s", {0, 0});
  const int m = g.AddNode("m", {1, 0});
  const int t = g.AddNode("g", {2, 0});
  g.AddArc(s, m, 1.0);
  g.AddArc(m, t, 1.0);
  FleetCoordinator c(2, {});
  c.Send(0, {{{m, 5.0}}, std::nullopt, 0.0, -1, -1, {}});
  c.Merge();
  std::vector<double> costs(3, 0.0);
  c.board().AddOthersCosts(1, 200.0, &costs);
  const std::optional<GraphPath> p = PlanGraphPath(g, s, t, costs);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->nodes, (std::vector<int>{s, m, t}));
  EXPECT_DOUBLE_EQ(p->cost, 7.0);
}

TEST(GoalCoordination, ProposesOnlyFreeStationsAndWaitsWhenAllAreTaken) {
  const std::vector<std::string> among{"st1", "st2", "st3"};
  MissionSequence tour = MissionSequence::Tour(among, 3, false, core::RandomStream(7, 1));
  std::set<std::string> taken{"st1", "st2"};
  const auto is_taken = [&](const std::string& id) { return taken.contains(id); };
  MissionSequence::Proposal p = tour.NextFree(is_taken);
  ASSERT_TRUE(p.goal);
  EXPECT_EQ(*p.goal, "st3");    // the only free one
  p = tour.NextFree(is_taken);  // st1 and st2 remain, both taken
  EXPECT_TRUE(p.wait);
  EXPECT_FALSE(p.goal);
  taken.clear();
  std::set<std::string> rest;
  for (int k = 0; k < 2; ++k) {
    p = tour.NextFree(is_taken);
    ASSERT_TRUE(p.goal);
    rest.insert(*p.goal);
  }
  EXPECT_EQ(rest, (std::set<std::string>{"st1", "st2"}));  // each once per round
  p = tour.NextFree(is_taken);
  EXPECT_FALSE(p.goal);  // one round, not repeated: done
  EXPECT_FALSE(p.wait);
}

// Robots standing each at a station another still has to visit wait for
// good unless one proposes a station it already visited: a revisit is a free
// station of the candidates, neither still ahead in the round nor the one the
// robot just left, and the round keeps its remaining stations.
TEST(GoalCoordination, AfterWaitingARevisitBreaksTheCircle) {
  const std::vector<std::string> among{"st1", "st2", "st3", "st4", "st5"};
  MissionSequence tour = MissionSequence::Tour(among, 5, true, core::RandomStream(3, 1));
  std::set<std::string> taken;
  const auto is_taken = [&](const std::string& id) { return taken.contains(id); };
  std::vector<std::string> visited;
  for (int k = 0; k < 3; ++k) visited.push_back(*tour.NextFree(is_taken).goal);
  std::set<std::string> ahead(among.begin(), among.end());
  for (const std::string& v : visited) ahead.erase(v);
  ASSERT_EQ(ahead.size(), 2u);
  taken = ahead;  // both stations still ahead are another robot's
  EXPECT_TRUE(tour.NextFree(is_taken).wait);
  EXPECT_TRUE(tour.NextFree(is_taken, false).wait);
  taken.insert(visited[0]);  // and one visited station as well
  // Only visited[1] is free, visited, and not the station just left (visited[2]).
  MissionSequence copy = tour;
  const MissionSequence::Proposal p = copy.NextFree(is_taken, true);
  ASSERT_TRUE(p.goal);
  EXPECT_TRUE(p.revisit);
  EXPECT_EQ(*p.goal, visited[1]);
  // No free candidate at all: the robot waits even with revisit.
  taken.insert(visited[1]);
  EXPECT_TRUE(tour.NextFree(is_taken, true).wait);
  // The round's remaining stations stay: freed, they are the next proposals.
  taken.clear();
  std::set<std::string> rest;
  for (int k = 0; k < 2; ++k) {
    const MissionSequence::Proposal p = tour.NextFree(is_taken, true);
    ASSERT_TRUE(p.goal);
    EXPECT_FALSE(p.revisit);
    rest.insert(*p.goal);
  }
  EXPECT_EQ(rest, ahead);
}

TEST(GoalCoordination, TwoRobotsNeverReserveTheSameStation) {
  // Robots choose one after the other within a tick from the same board; the
  // second sees the first's reservation only after the merge, so they choose
  // in turn: each reservation is published before the next robot chooses.
  const std::vector<std::string> among{"st1", "st2", "st3", "st4"};
  FleetCoordinator c(4, {});
  std::set<std::string> chosen;
  for (int r = 0; r < 4; ++r) {
    MissionSequence tour = MissionSequence::Tour(among, 4, true, core::RandomStream(1, 1));
    const auto taken = [&](const std::string& id) {
      return c.board().StationTaken(std::stoi(id.substr(2)), r);
    };
    const MissionSequence::Proposal p = tour.NextFree(taken);
    ASSERT_TRUE(p.goal) << r;
    EXPECT_TRUE(chosen.insert(*p.goal).second) << *p.goal;
    c.Send(r, {{}, std::nullopt, 0.0, std::stoi(p.goal->substr(2)), -1, {}});
    c.Merge();
  }
}

// A lost robot's pose does not explain the markers others see (it may be
// decimetres off), robots without a pose neither; the lost flag travels in
// the pose's flag byte and a change of it alone is forwarded.
TEST(FleetBoard, ALostRobotsPoseIsNotTrusted) {
  FleetCoordinator c(3, {});
  FleetMessage m;
  m.pose = core::Pose2{1.0, 2.0, 0.0};
  c.Send(0, m);
  m.pose = core::Pose2{5.0, 6.0, 0.0};
  m.lost = true;
  const std::int64_t lost_bytes = EncodedBytes(m);
  c.Send(1, m);
  c.Send(2, FleetMessage{});
  c.Merge();
  m.lost = false;
  EXPECT_EQ(EncodedBytes(m), lost_bytes);
  const std::vector<Eigen::Vector2d> seen_by_2 = c.board().TrustedPositions(2);
  ASSERT_EQ(seen_by_2.size(), 1u);
  EXPECT_EQ(seen_by_2[0], Eigen::Vector2d(1.0, 2.0));
  EXPECT_TRUE(c.board().TrustedPositions(0).empty());
  // Relocalized at the same pose: the message changed and is forwarded.
  c.Send(1, m);
  c.Merge();
  EXPECT_EQ(c.board().TrustedPositions(2).size(), 2u);
  EXPECT_FALSE(c.board().message(1).lost);
}

// Station passage claims: one robot at a time, first come first served, a
// same-cycle tie to the first in robot order, the occupied station always.
TEST(StationClaims, AStationIsOneRobotsAtATime) {
  FleetCoordinator c(3, {});
  const std::vector<int> none;
  // Nobody claims yet: robot 1 gets what it wants.
  EXPECT_EQ(c.board().ResolveClaims(1, std::vector<int>{2, 5}, none, -1), (std::vector<int>{2, 5}));
  FleetMessage m;
  m.claims = {5};
  c.Send(2, m);
  c.Merge();
  EXPECT_TRUE(c.board().ClaimedByOther(5, 1));
  EXPECT_FALSE(c.board().ClaimedByOther(5, 2));
  // Robot 2 holds 5 on the board: a new claim by robot 1 is not made...
  EXPECT_EQ(c.board().ResolveClaims(1, std::vector<int>{2, 5}, none, -1), (std::vector<int>{2}));
  // ...but one robot 1 made in the same cycle (it held 5 too) is kept, as
  // robot 1 comes first; robot 0's would also be, robot 2 yields.
  EXPECT_EQ(c.board().ResolveClaims(1, std::vector<int>{2, 5}, std::vector<int>{5}, -1),
            (std::vector<int>{2, 5}));
  m.claims = {5};
  c.Send(1, m);
  c.Merge();
  EXPECT_EQ(c.board().ResolveClaims(2, std::vector<int>{5}, std::vector<int>{5}, -1), none);
  // The station a robot stands at is kept, claimed by another or not wanted.
  EXPECT_EQ(c.board().ResolveClaims(2, std::vector<int>{1}, none, 5), (std::vector<int>{1, 5}));
}

TEST(FleetCoordinator, CountsTheBytesOfTheCompactEncoding) {
  FleetMessage m{{{1, 2.0}, {2, 1.0}}, core::Pose2{1, 2, 0.5}, 0.2, 3, -1, {3, 7}};
  // 2 robot + 2 count + 2 x (2 + 4) + 1 flag + 24 pose, speed, turn rate and
  // outline sigma + 2 x 2 stations + 2 count + 2 x 2 claims.
  EXPECT_EQ(EncodedBytes(m), 2 + 2 + 12 + 1 + 24 + 4 + 2 + 4);
  FleetCoordinator c(3, {});
  c.Send(0, m);
  c.Merge();
  EXPECT_EQ(c.bytes_up(0), EncodedBytes(m));
  EXPECT_EQ(c.bytes_down(1), EncodedBytes(m));
  EXPECT_EQ(c.bytes_down(0), 0);
  c.Send(0, m);  // unchanged: sent up, not forwarded
  c.Merge();
  EXPECT_EQ(c.bytes_up(0), 2 * EncodedBytes(m));
  EXPECT_EQ(c.bytes_down(1), EncodedBytes(m));
  EXPECT_EQ(c.messages(0), 2);
  // A second pose (a lone hypothesis' while not localized): 12 bytes more,
  // and a message that changed.
  m.also_at = core::Pose2{4, 5, -1.0};
  EXPECT_EQ(EncodedBytes(m), 2 + 2 + 12 + 1 + 24 + 12 + 4 + 2 + 4);
  c.Send(0, m);
  c.Merge();
  EXPECT_EQ(c.bytes_down(1), 2 * EncodedBytes(m) - 12);
}

TEST(FleetOptions, RejectsValuesOutOfRange) {
  FleetOptions o;
  o.falloff_m = 0.0;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o = FleetOptions{};
  o.claim_radius_m = 0.0;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o = FleetOptions{};
  o.claim_ahead_m = -1.0;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  EXPECT_THROW(FleetCoordinator(0, {}), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::nav
