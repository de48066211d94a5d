// The station rings of the fleet (§6.3.5, NavigationControllerOptions::
// fleet_station_clear_m): a robot keeps out of a station another robot
// claims, a robot caught inside such a ring when the other arrives is not
// trapped but leaves, a robot heading for its own station waits outside while
// another robot is inside, and one passing through goes round it. One controller drives an ideal
// robot (belief = truth); the other robot is a fixed message on the coordinator's board.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/geometry/polygon.h"
#include "core/odometry/diff_drive.h"
#include "nav/fleet/coordinator.h"
#include "nav/mission/navigation_controller.h"
#include "tests/support/robox_octagon.h"

namespace pavilion::nav {
namespace {

constexpr double kStepS = 0.005;
constexpr int kStation = 1;  // node index of "s"
const Eigen::Vector2d kStationAt(4.0, 0.0);

// An empty floor: a -- s -- b on a line, s a station between the two ends.
core::RobotMap Line() {
  core::RobotMap map;
  map.name = "line";
  map.nodes.push_back({"a", {0.0, 0.0, 0.0}, true});
  map.nodes.push_back({"s", {kStationAt.x(), kStationAt.y(), 0.0}, true});
  map.nodes.push_back({"b", {8.0, 0.0, 0.0}, true});
  map.edges.push_back({"a", "s", 4.0});
  map.edges.push_back({"s", "b", 4.0});
  return map;
}

std::vector<Eigen::Vector2d> Square() {
  return {{-0.3, -0.3}, {0.3, -0.3}, {0.3, 0.3}, {-0.3, 0.3}};
}

using pavilion::testing::RoboxOctagon;

struct RingRun {
  NavigationFigures figures;
  core::Pose2 pose;
  double closest_to_station_m = std::numeric_limits<double>::infinity();
  double closest_while_other_there_m = std::numeric_limits<double>::infinity();
  double completed_at_s = -1.0;
};

// Robot 0 (the controller) starts at `start` with `goal`; robot 1 stands at
// `other` holding `other_station` (-1: none) until `other_leaves_s`, then is
// published far away. `other_first`: the other is first in robot order (it
// wins a claim both make in the same cycle).
RingRun Drive(const core::Pose2& start, const char* goal, const Eigen::Vector2d& other,
              int other_station, double other_leaves_s, double duration_s, bool other_first = false,
              const std::vector<Eigen::Vector2d>& hull = Square()) {
  const int self = other_first ? 1 : 0;
  const int them = 1 - self;
  NavigationControllerOptions options;
  options.step_s = kStepS;
  FleetCoordinator coordinator(2, FleetOptions{});
  coordinator.SetStations({"a", "s", "b"});
  NavigationController controller(Line(), hull, MissionSequence::List({goal}), options);
  controller.SetFleet({&coordinator, self});
  coordinator.Join(them, hull);
  RingRun run;
  run.pose = start;
  const double b = options.odometry.wheelbase_m;
  WheelSpeeds held;
  std::vector<NavigationEvent> events;
  for (std::int64_t tick = 0; tick * kStepS < duration_s; ++tick) {
    const double now_s = tick * kStepS;
    if (const std::optional<WheelSpeeds> w =
            controller.OnTick(ControlTick{tick, now_s, run.pose, run.pose, false})) {
      held = *w;
    }
    FleetMessage m;
    const bool there = now_s < other_leaves_s;
    m.pose = there ? core::Pose2{other.x(), other.y(), 0.0} : core::Pose2{-50.0, -50.0, 0.0};
    m.reserved_station = there ? other_station : -1;
    if (there && other_station >= 0) m.claims = {other_station};
    coordinator.Send(them, m);
    coordinator.Merge();
    const core::WheelTravel travel{
        held.left_radps * options.odometry.left_wheel_radius_m * kStepS,
        held.right_radps * options.odometry.right_wheel_radius_m * kStepS};
    run.pose = core::DiffDriveStep(run.pose, travel, b);
    run.closest_to_station_m =
        std::min(run.closest_to_station_m, (run.pose.translation() - kStationAt).norm());
    if (there) {
      run.closest_while_other_there_m =
          std::min(run.closest_while_other_there_m, (run.pose.translation() - kStationAt).norm());
    }
    controller.TakeEvents(&events);
    for (const NavigationEvent& e : events) {
      if (e.type == NavigationEvent::Type::kMissionCompleted && run.completed_at_s < 0.0) {
        run.completed_at_s = e.at_s;
      }
    }
    events.clear();
  }
  run.figures = *controller.navigation();
  return run;
}

TEST(NavigationControllerFleet, KeepsOutOfAStationAnotherRobotHolds) {
  // The other stands at its station's edge; the way a -> b crosses the node.
  const RingRun run = Drive({0.0, 0.0, 0.0}, "b", {4.0, 1.2}, kStation, 1e9, 60.0);
  EXPECT_EQ(run.figures.missions_completed, 1);  // around the ring
  // The ring's radius is the clear distance less the inradius; the hull's
  // corners reach a little further in than its sides (0.42 vs 0.3 m).
  EXPECT_GE(run.closest_to_station_m, 1.05 - 0.13);
}

TEST(NavigationControllerFleet, ARobotInsideTheRingWhenTheOtherComesLeaves) {
  // Robot 0 is on the node's doorstep, heading on to b, when robot 1 arrives
  // for the station: before the rule the ring closed around robot 0 for good.
  const RingRun run = Drive({4.3, 0.0, 0.0}, "b", {4.0, 1.2}, kStation, 1e9, 30.0);
  EXPECT_EQ(run.figures.missions_completed, 1);
  EXPECT_GT(run.completed_at_s, 0.0);
  EXPECT_LT(run.completed_at_s, 20.0);
}

TEST(NavigationControllerFleet, WaitsOutsideItsStationWhileAnotherRobotIsInside) {
  // Robot 1, holding nothing, stands within the clear radius of robot 0's
  // station until t = 25 s; robot 0 waits outside, then takes the station.
  const RingRun waiting = Drive({0.0, 0.0, 0.0}, "s", {4.5, 0.4}, -1, 1e9, 25.0);
  EXPECT_EQ(waiting.figures.missions_completed, 0);
  EXPECT_GE(waiting.closest_to_station_m, 1.05 - 0.13);
  const RingRun run = Drive({0.0, 0.0, 0.0}, "s", {4.5, 0.4}, -1, 25.0, 60.0);
  EXPECT_EQ(run.figures.missions_completed, 1);
  EXPECT_GT(run.completed_at_s, 25.0);
}

TEST(NavigationControllerFleet, APasserKeepsOutWhileAnotherRobotIsInsideTheStation) {
  // The way a -> b crosses s. Robot 0 claims s when its plan reaches it; robot
  // 1 stands inside s's ring without a claim (pushed there): robot 0 goes
  // round the ring. With robot 1 gone, it drives straight through the node.
  const RingRun around = Drive({0.0, 0.0, 0.0}, "b", {4.5, 0.4}, -1, 1e9, 60.0);
  EXPECT_EQ(around.figures.missions_completed, 1);
  EXPECT_GE(around.closest_to_station_m, 1.05 - 0.13);
  const RingRun through = Drive({0.0, 0.0, 0.0}, "b", {4.5, 0.4}, -1, 0.0, 60.0);
  EXPECT_EQ(through.figures.missions_completed, 1);
  EXPECT_LT(through.closest_to_station_m, 0.2);
}

// A robot that slipped a few centimetres past the ring of a station another
// robot holds (the claim came as it arrived, and it braked too late) is not
// "inside" the way a robot crossing the node is: the ring is drawn just outside
// its hull, a ratchet that lets it out and not in. Robot 0 starts 1.0 m from
// the node, 5 cm inside the 1.05 m ring, on its way through s to b, and
// claims s in the same cycle as the other robot, which comes first in robot
// order and holds it for 15 s (a passer): robot 0 (Robox's octagon) backs
// out, then drives on round the ring (with set-points that moved in steps it
// waited for the other to leave instead; either is right). Without the
// ratchet it drove straight over the node the other held.
TEST(NavigationControllerFleet, ARobotThatSlippedPastTheRingBacksOutUntilItIsFree) {
  const RingRun run = Drive({kStationAt.x() - 1.0, 0.0, 0.0}, "b", {4.0, 1.2}, kStation, 15.0, 60.0,
                            /*other_first=*/true, RoboxOctagon());
  // While the other holds it, the centre never gets nearer the node than it
  // started by more than the octagon's corners reach beyond its sides
  // (2.8 cm) and the window's slack.
  EXPECT_GE(run.closest_while_other_there_m, 1.0 - 0.04);
  EXPECT_EQ(run.figures.missions_completed, 1);
  EXPECT_GT(run.completed_at_s, 0.0);
}

// Passage claims follow the band, not only the plan's nodes
// (NavigationControllerOptions::fleet_claim_margin_m): the way a -> b passes
// 1.2 m from station t, which is on no plan of robot 0's. Robot 0 claims t
// ahead of passing it (before its centre is within the 1.05 m ring, so that a
// second passer would find it held) and gives it up once past.
TEST(NavigationControllerFleet, ClaimsAStationItsBandPassesNearAndReleasesItPast) {
  core::RobotMap map;
  map.name = "aside";
  map.nodes.push_back({"a", {0.0, 0.0, 0.0}, true});
  map.nodes.push_back({"b", {8.0, 0.0, 0.0}, true});
  map.nodes.push_back({"t", {4.0, 1.2, 0.0}, true});
  map.edges.push_back({"a", "b", 8.0});
  map.edges.push_back({"t", "b", 4.2});
  constexpr int kT = 2;
  const Eigen::Vector2d t_at(4.0, 1.2);
  NavigationControllerOptions options;
  options.step_s = kStepS;
  FleetCoordinator coordinator(1, FleetOptions{});
  coordinator.SetStations({"a", "b", "t"});
  NavigationController controller(map, Square(), MissionSequence::List({"b"}), options);
  controller.SetFleet({&coordinator, 0});
  core::Pose2 pose{0.0, 0.0, 0.0};
  WheelSpeeds held;
  double first_claim_m = -1.0;  // robot 0's distance to t when it first claims t
  double closest_m = std::numeric_limits<double>::infinity();
  for (std::int64_t tick = 0; tick * kStepS < 40.0; ++tick) {
    const double now_s = tick * kStepS;
    if (const std::optional<WheelSpeeds> w =
            controller.OnTick(ControlTick{tick, now_s, pose, pose, false})) {
      held = *w;
    }
    coordinator.Merge();
    const std::vector<int>& claims = coordinator.board().message(0).claims;
    const double d_m = (pose.translation() - t_at).norm();
    closest_m = std::min(closest_m, d_m);
    if (first_claim_m < 0.0 && std::count(claims.begin(), claims.end(), kT) > 0) {
      first_claim_m = d_m;
    }
    const core::WheelTravel travel{
        held.left_radps * options.odometry.left_wheel_radius_m * kStepS,
        held.right_radps * options.odometry.right_wheel_radius_m * kStepS};
    pose = core::DiffDriveStep(pose, travel, options.odometry.wheelbase_m);
  }
  EXPECT_EQ(controller.navigation()->missions_completed, 1);
  EXPECT_LT(closest_m, 1.4);  // the way does pass near t (1.2 m from the line a-b)
  ASSERT_GT(first_claim_m, 0.0) << "t was never claimed";
  EXPECT_GT(first_claim_m, 1.5);  // ahead, not on entering the ring
  const std::vector<int>& last = coordinator.board().message(0).claims;
  EXPECT_EQ(std::count(last.begin(), last.end(), kT), 0);  // released past it
}

// Goal coordination's revisit (NavigationControllerOptions::station_wait_s):
// robot 0 tours a, s, b and c; robots 1 and 2 hold s and b for good (they
// stand far away). Robot 0 visits a and c, finds the rest of its round taken,
// waits station_wait_s and then revisits a free station it visited before
// (not the one it stands at): the revisit is the mission after the two free
// ones, started once the wait is over.
TEST(NavigationControllerFleet, RevisitsAVisitedStationAfterWaitingForTakenOnes) {
  core::RobotMap map;
  map.name = "line4";
  for (int k = 0; k < 4; ++k) {
    const char* id[] = {"a", "s", "b", "c"};
    map.nodes.push_back({id[k], {4.0 * k, 0.0, 0.0}, true});
  }
  map.edges.push_back({"a", "s", 4.0});
  map.edges.push_back({"s", "b", 4.0});
  map.edges.push_back({"b", "c", 4.0});
  NavigationControllerOptions options;
  options.step_s = kStepS;
  FleetCoordinator coordinator(3, FleetOptions{});
  coordinator.SetStations({"a", "s", "b", "c"});
  NavigationController controller(
      map, Square(), MissionSequence::Tour({"a", "s", "b", "c"}, 4, true, core::RandomStream(5, 1)),
      options);
  controller.SetFleet({&coordinator, 0});
  coordinator.Join(1, Square());
  coordinator.Join(2, Square());
  core::Pose2 pose{0.0, 0.0, 0.0};
  WheelSpeeds held;
  std::vector<NavigationEvent> events, started;
  double second_completed_s = -1.0;
  int completed = 0;
  for (std::int64_t tick = 0; tick * kStepS < 120.0 && started.size() < 3; ++tick) {
    const double now_s = tick * kStepS;
    if (const std::optional<WheelSpeeds> w =
            controller.OnTick(ControlTick{tick, now_s, pose, pose, false})) {
      held = *w;
    }
    for (int r = 1; r <= 2; ++r) {
      FleetMessage m;
      m.pose = core::Pose2{-50.0, -50.0 * r, 0.0};
      m.occupied_station = r;  // s (1), then b (2)
      coordinator.Send(r, m);
    }
    coordinator.Merge();
    const core::WheelTravel travel{
        held.left_radps * options.odometry.left_wheel_radius_m * kStepS,
        held.right_radps * options.odometry.right_wheel_radius_m * kStepS};
    pose = core::DiffDriveStep(pose, travel, options.odometry.wheelbase_m);
    controller.TakeEvents(&events);
    for (const NavigationEvent& e : events) {
      if (e.type == NavigationEvent::Type::kMissionStarted) started.push_back(e);
      if (e.type == NavigationEvent::Type::kMissionCompleted && ++completed == 2) {
        second_completed_s = e.at_s;
      }
    }
    events.clear();
  }
  ASSERT_EQ(started.size(), 3u);
  ASSERT_GT(second_completed_s, 0.0);
  const std::set<std::string> free{started[0].goal, started[1].goal};
  EXPECT_EQ(free, (std::set<std::string>{"a", "c"}));
  // The revisit: the station visited first (the robot stands at the second).
  EXPECT_EQ(started[2].goal, started[0].goal);
  EXPECT_NEAR(started[2].at_s - second_completed_s, options.station_wait_s, 0.2);
  EXPECT_EQ(controller.navigation()->station_revisits, 1);
}

// What a robot believes, against the truth (offsets in the world frame).
struct Beliefs {
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();  // its belief's
  double position_sigma_m = 0.0;
  // While lost: where it was last localized, carried on, is the truth
  // shifted by this; none: never localized.
  std::optional<Eigen::Vector2d> carried_on_offset = std::nullopt;
  bool lone_hypothesis = false;  // while lost: its belief is its one hypothesis
};

// Runs `controller` (a Robox octagon starting at the origin, believing as
// `beliefs` say) for duration_s, `publish` called before every tick; returns
// the closest its hull came to the hull of a robot standing at `other`.
double ClosestApproach(NavigationController& controller, const NavigationControllerOptions& options,
                       const core::Pose2& other, bool lost, double duration_s,
                       const std::function<void()>& publish, core::Pose2* end = nullptr,
                       std::vector<core::Pose2>* trail = nullptr, const Beliefs& beliefs = {}) {
  const Eigen::Vector2d& belief_offset = beliefs.offset;
  std::vector<Eigen::Vector2d> other_hull;
  for (const Eigen::Vector2d& c : RoboxOctagon()) other_hull.push_back(other * c);
  core::Pose2 pose;
  WheelSpeeds held;
  double closest_m = std::numeric_limits<double>::infinity();
  for (std::int64_t tick = 0; tick * kStepS < duration_s; ++tick) {
    publish();
    ControlTick control{tick, tick * kStepS, pose, pose, lost};
    control.belief =
        core::Pose2{pose.x_m + belief_offset.x(), pose.y_m + belief_offset.y(), pose.theta_rad};
    control.position_sigma_m = beliefs.position_sigma_m;
    if (lost && beliefs.carried_on_offset) {
      const Eigen::Vector2d& c = *beliefs.carried_on_offset;
      control.last_localized = core::Pose2{pose.x_m + c.x(), pose.y_m + c.y(), pose.theta_rad};
      control.lone_hypothesis = beliefs.lone_hypothesis;
    }
    if (const std::optional<WheelSpeeds> w = controller.OnTick(control)) held = *w;
    const core::WheelTravel travel{
        held.left_radps * options.odometry.left_wheel_radius_m * kStepS,
        held.right_radps * options.odometry.right_wheel_radius_m * kStepS};
    pose = core::DiffDriveStep(pose, travel, options.odometry.wheelbase_m);
    std::vector<Eigen::Vector2d> own;
    for (const Eigen::Vector2d& c : RoboxOctagon()) own.push_back(pose * c);
    closest_m = std::min(closest_m, core::ConvexPolygonGap(own, other_hull));
    if (trail != nullptr) trail->push_back(pose);
  }
  if (end != nullptr) *end = pose;
  return closest_m;
}

// The message of a robot that publishes `pose`, declared lost or not.
FleetMessage Published(const core::Pose2& pose, bool lost) {
  FleetMessage m;
  m.pose = pose;
  m.lost = lost;
  return m;
}

// A robot lost on an empty floor (nothing in its scans: another Robox's
// recessed body can be all but invisible) explores straight ahead, where
// another robot stands 1.5 m off. In the fleet it places the other's
// published hull by its belief, grown by lost_hull_margin_m, and keeps off
// it; alone, it drives into it. `beliefs`: what it believes (its belief, where
// it was last localized carried on, a lone hypothesis).
double ClosestWhileExploring(bool fleet, const Beliefs& beliefs = {}) {
  NavigationControllerOptions options;
  options.step_s = kStepS;
  options.explore_when_lost = true;
  FleetCoordinator coordinator(2, FleetOptions{});
  coordinator.SetStations({"a", "s", "b"});
  NavigationController controller(Line(), RoboxOctagon(), MissionSequence::List({"b"}), options);
  if (fleet) {
    controller.SetFleet({&coordinator, 0});
    coordinator.Join(1, RoboxOctagon());
  }
  const core::Pose2 other{1.5, 0.0, 0.0};
  return ClosestApproach(
      controller, options, other, true, 15.0,
      [&] {
        if (!fleet) return;
        coordinator.Send(1, Published(other, false));
        coordinator.Merge();
      },
      nullptr, nullptr, beliefs);
}

TEST(NavigationControllerFleet, ALostRobotKeepsOffTheOthersPublishedHulls) {
  EXPECT_GT(ClosestWhileExploring(true), 0.2);
  EXPECT_LT(ClosestWhileExploring(false), 0.01);
}

// The same robot, its belief 1 m to the side (a look-alike hypothesis): by
// its belief it places the other's hull beside its way and drives into the
// other; by where it was last localized, carried on, it keeps off.
TEST(NavigationControllerFleet, ALostRobotPlacesTheOthersWhereItWasLastLocalized) {
  const Eigen::Vector2d aside(0.0, 1.0);
  EXPECT_GT(
      ClosestWhileExploring(true, {.offset = aside, .carried_on_offset = Eigen::Vector2d::Zero()}),
      0.2);
  EXPECT_LT(ClosestWhileExploring(true, {.offset = aside}), 0.01);
}

// Kidnapped 1 m aside and not localized again, its one hypothesis right: by
// where it was last localized, carried on, it places the other's hull beside
// its way; by its hypothesis as well, it keeps off.
TEST(NavigationControllerFleet, ALostRobotPlacesTheOthersByItsLoneHypothesisToo) {
  const Eigen::Vector2d aside(0.0, 1.0);
  EXPECT_GT(ClosestWhileExploring(true, {.carried_on_offset = aside, .lone_hypothesis = true}),
            0.2);
  EXPECT_LT(ClosestWhileExploring(true, {.carried_on_offset = aside}), 0.01);
}

// A robot (the controller, with `options`) drives from the origin to b,
// another Robox standing at `other` and publishing `published` (its pose,
// declared lost or not, its sigma). Returns the closest the two hulls came;
// `end`: where the driver ended.
double ClosestBesideAPublishedRobot(const core::Pose2& other, const FleetMessage& published,
                                    double duration_s, core::Pose2* end,
                                    NavigationControllerOptions options = {},
                                    const Beliefs& belief = {}) {
  options.step_s = kStepS;
  FleetCoordinator coordinator(2, FleetOptions{});
  coordinator.SetStations({"a", "s", "b"});
  NavigationController controller(Line(), RoboxOctagon(), MissionSequence::List({"b"}), options);
  controller.SetFleet({&coordinator, 0});
  coordinator.Join(1, RoboxOctagon());
  return ClosestApproach(
      controller, options, other, false, duration_s,
      [&] {
        coordinator.Send(1, published);
        coordinator.Merge();
      },
      end, nullptr, belief);
}

// A robot drives from a to b past another that declared itself lost: it
// stands 0.45 m beside the way, but its belief, published, is 0.3 m further
// off (a false loss's hypothesis, expo_tours seed 1). Drawn grown by
// lost_hull_margin_m, the hull keeps the passer off the true one; taken at
// its word (not lost), the passer brushes past where the other truly stands.
double ClosestPassingALostRobot(bool declared_lost) {
  core::Pose2 end;
  const double closest_m = ClosestBesideAPublishedRobot(
      {2.0, 0.45, 0.0}, Published({2.0, 0.75, 0.0}, declared_lost), 12.0, &end);
  EXPECT_GT(end.x_m, 4.0) << "the passer got past";
  return closest_m;
}

// The same passer beside a robot not localized whose pose carried on is a
// phantom 3 m off the way and whose one hypothesis is right: it keeps off
// the hull drawn at the hypothesis; without it, it brushes past.
double ClosestPassingARobotWithALoneHypothesis(bool sends_hypothesis) {
  FleetMessage m = Published({2.0, 3.45, 0.0}, true);
  if (sends_hypothesis) m.also_at = core::Pose2{2.0, 0.45, 0.0};
  core::Pose2 end;
  const double closest_m = ClosestBesideAPublishedRobot({2.0, 0.45, 0.0}, m, 12.0, &end);
  EXPECT_GT(end.x_m, 4.0) << "the passer got past";
  return closest_m;
}

TEST(NavigationControllerFleet, KeepsOffARobotWhereItsLoneHypothesisPutsIt) {
  EXPECT_GT(ClosestPassingARobotWithALoneHypothesis(true), 0.05);
  EXPECT_LT(ClosestPassingARobotWithALoneHypothesis(false), 0.01);
}

TEST(NavigationControllerFleet, KeepsFurtherFromARobotThatDeclaredItselfLost) {
  EXPECT_GT(ClosestPassingALostRobot(true), 0.05);
  EXPECT_LT(ClosestPassingALostRobot(false), 0.01);
}

// A robot not localized publishes, for the others to draw its hull at, where
// it was last localized carried on by odometry — not its belief, which
// follows global localization's hypotheses — and says it is lost; localized,
// its belief.
TEST(NavigationControllerFleet, ALostRobotPublishesWhereItWasLastLocalizedCarriedOn) {
  NavigationControllerOptions options;
  options.step_s = kStepS;
  FleetCoordinator coordinator(2, FleetOptions{});
  coordinator.SetStations({"a", "s", "b"});
  NavigationController controller(Line(), RoboxOctagon(), MissionSequence::List({"b"}), options);
  controller.SetFleet({&coordinator, 0});
  const auto published = [&](const ControlTick& tick) {
    controller.OnTick(tick);
    coordinator.Merge();
    return coordinator.board().message(0);
  };
  ControlTick lost{0, 0.0, core::Pose2{6.0, 3.0, 1.0}, core::Pose2{}, true};
  lost.last_localized = core::Pose2{1.0, 0.2, 0.1};
  const FleetMessage carried = published(lost);
  ASSERT_TRUE(carried.pose);
  EXPECT_TRUE(carried.lost);
  EXPECT_DOUBLE_EQ(carried.pose->x_m, 1.0);
  EXPECT_DOUBLE_EQ(carried.pose->y_m, 0.2);
  EXPECT_DOUBLE_EQ(carried.pose->theta_rad, 0.1);
  EXPECT_FALSE(carried.also_at);
  // With one hypothesis (its belief), it sends that as well.
  lost.lone_hypothesis = true;
  lost.tick = 500;
  lost.now_s = 2.5;
  const FleetMessage both = published(lost);
  ASSERT_TRUE(both.also_at);
  EXPECT_DOUBLE_EQ(both.also_at->x_m, 6.0);
  EXPECT_DOUBLE_EQ(both.pose->x_m, 1.0);
  lost.lone_hypothesis = false;
  // Never localized (no such pose): its belief.
  lost.tick = 1000;
  lost.now_s = 5.0;
  lost.last_localized.reset();
  const FleetMessage believed = published(lost);
  ASSERT_TRUE(believed.pose);
  EXPECT_DOUBLE_EQ(believed.pose->x_m, 6.0);
  const ControlTick localized{2000, 10.0, core::Pose2{0.5, 0.0, 0.0}, core::Pose2{}, false};
  const FleetMessage fine = published(localized);
  ASSERT_TRUE(fine.pose);
  EXPECT_FALSE(fine.lost);
  EXPECT_DOUBLE_EQ(fine.pose->x_m, 0.5);
}

// A robot lost on an empty floor explores straight ahead, over the station
// another robot (standing 1.2 m beside it) holds. With the fleet it keeps
// out of the station's ring placed by its belief; alone it drives over the
// node. Returns how near its centre came to the node.
double ClosestToAStationWhileExploring(bool fleet) {
  NavigationControllerOptions options;
  options.step_s = kStepS;
  options.explore_when_lost = true;
  FleetCoordinator coordinator(2, FleetOptions{});
  coordinator.SetStations({"a", "s", "b"});
  NavigationController controller(Line(), RoboxOctagon(), MissionSequence::List({"b"}), options);
  if (fleet) {
    controller.SetFleet({&coordinator, 0});
    coordinator.Join(1, RoboxOctagon());
  }
  const core::Pose2 other{kStationAt.x(), 1.2, 0.0};
  core::Pose2 end;
  std::vector<core::Pose2> trail;
  ClosestApproach(
      controller, options, other, true, 30.0,
      [&] {
        if (!fleet) return;
        FleetMessage m;
        m.pose = other;
        m.reserved_station = kStation;
        m.claims = {kStation};
        coordinator.Send(1, m);
        coordinator.Merge();
      },
      &end, &trail);
  EXPECT_GT(end.x_m, 2.0) << "it explored";
  double closest_m = std::numeric_limits<double>::infinity();
  for (const core::Pose2& p : trail) {
    closest_m = std::min(closest_m, (p.translation() - kStationAt).norm());
  }
  return closest_m;
}

TEST(NavigationControllerFleet, ALostRobotKeepsOutOfAStationAnotherRobotHolds) {
  EXPECT_GE(ClosestToAStationWhileExploring(true), 1.0);
  EXPECT_LT(ClosestToAStationWhileExploring(false), 0.5);
}

// A robot declared lost stands 0.75 m behind another (hulls 7 cm apart) and
// publishes a belief `published_x` along the line. Grown by
// lost_hull_margin_m, its hull reaches into the other, which is sent to b
// ahead: drawn whole, it would hold that robot where it stands (expo_tours
// seed 4, 2,596 s: 17 minutes). The growth stops short of the other's hull
// (a ratchet: it may move away, not closer), and where the published hull
// itself reaches into it the points within its margin are left out. Returns
// how far it got along the line in 15 s.
double DistanceDrivenFromUnderALostHull(double published_x) {
  core::Pose2 end;
  const double closest_m = ClosestBesideAPublishedRobot(
      {-0.75, 0.0, 0.0}, Published({published_x, 0.0, 0.0}, true), 15.0, &end);
  EXPECT_GT(closest_m, 0.065) << "it never backed towards the lost robot";
  return end.x_m;
}

TEST(NavigationControllerFleet, DrivesAwayFromALostRobotWhoseGrownHullReachesIntoIt) {
  EXPECT_GT(DistanceDrivenFromUnderALostHull(-0.75), 4.0);  // the growth ratchets
  EXPECT_GT(DistanceDrivenFromUnderALostHull(-0.55), 4.0);  // the hull itself reaches in
}

// Two localized robots that touched (a belief a few centimetres off, thesis
// §6.3.5.1: the recessed bodies hide each other's true size from the lasers)
// stand face to face, the other robot's published hull `published_x` ahead
// on the way to b, touching this robot's or 1 cm into it. Grown by
// fleet_hull_margin_m and drawn whole, it held both robots where they stood
// for 470 s (expo_day seed 3, 4,430 s: robox_01 and robox_08). The growth
// stops short of this robot's hull, and the points of a hull that itself
// reaches in are left out within the margin, as for a lost robot: it backs
// off and goes round. Returns how far along the line it got in 30 s.
double DistanceDrivenFromATouchingRobot(double published_x) {
  core::Pose2 end;
  const double closest_m = ClosestBesideAPublishedRobot(
      {0.69, 0.0, 0.0}, Published({published_x, 0.0, 0.0}, false), 30.0, &end);
  EXPECT_GT(closest_m, 0.005) << "it never pressed towards the other robot, published at "
                              << published_x;
  return end.x_m;
}

TEST(NavigationControllerFleet, DrivesAwayFromALocalizedRobotItTouches) {
  EXPECT_GT(DistanceDrivenFromATouchingRobot(0.68), 4.0);  // the growth ratchets
  EXPECT_GT(DistanceDrivenFromATouchingRobot(0.67), 4.0);  // the hull itself reaches in
}

// A localized robot drives to its goal b, 0.8 m short of which another robot
// stands (its station ring off, so that nothing but its hull stops this one
// short). A visitor's bump left this robot 12 cm ahead of its belief
// (expo_day seed 1, 24,689.5 s: robox_03, 8-13 cm off along its way with no
// wall across it to fix that; it drove into robox_04). Placed by that belief
// and grown by fleet_hull_margin_m alone, the other's hull lets it stop at
// its goal, 4 cm into the other; grown by two sigmas of its belief (7 cm, as
// its covariance says after the bump) it stops short, clear of the other. The
// other's published sigma counts alike (here its belief is the truth).
// Returns the closest the two hulls came.
double ClosestAtAGoalWithAnUncertainBelief(double position_sigma_m, double other_sigma_m = 0.003) {
  NavigationControllerOptions options;
  options.fleet_station_clear_m = 0.0;
  FleetMessage other = Published({8.8, 0.0, 0.0}, false);
  other.outline_sigma_m = other_sigma_m;
  core::Pose2 end;
  const double closest_m = ClosestBesideAPublishedRobot(
      *other.pose, other, 30.0, &end, options, {Eigen::Vector2d(-0.12, 0.0), position_sigma_m});
  EXPECT_GT(end.x_m, 7.5) << "it drove to its goal";
  return closest_m;
}

TEST(NavigationControllerFleet, KeepsClearOfAnotherRobotByItsOwnBeliefsUncertainty) {
  EXPECT_GT(ClosestAtAGoalWithAnUncertainBelief(0.07), 0.03);
  EXPECT_GT(ClosestAtAGoalWithAnUncertainBelief(0.002, 0.07), 0.03);
  EXPECT_LT(ClosestAtAGoalWithAnUncertainBelief(0.002), 0.001);
}

}  // namespace
}  // namespace pavilion::nav
