// Making way at a rest node (NavigationControllerOptions::rest_among): a
// robot of a fleet with more robots than stations that finds every station
// taken drives to the nearest free rest node and waits there, its station
// free for another robot. One controller drives an ideal robot (belief =
// truth); the other robots are fixed messages on the coordinator's board.
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "core/odometry/diff_drive.h"
#include "nav/fleet/coordinator.h"
#include "nav/mission/navigation_controller.h"

namespace pavilion::nav {
namespace {

constexpr double kStepS = 0.005;
// Node indices of the map below.
constexpr int kA = 1, kB = 2, kDock1 = 3, kDock2 = 4;

// An empty floor: the robot starts at via node v; stations a and b of the
// tour; two docks beyond a, dock_2 the nearer.
core::RobotMap Floor() {
  core::RobotMap map;
  map.name = "floor";
  map.nodes.push_back({"v", {0.0, 0.0, 0.0}, false});
  map.nodes.push_back({"a", {4.0, 0.0, 0.0}, true});
  map.nodes.push_back({"b", {4.0, 4.0, 0.0}, true});
  map.nodes.push_back({"dock_1", {10.0, 0.0, 0.0}, true});
  map.nodes.push_back({"dock_2", {8.0, 0.0, 0.0}, true});
  map.edges.push_back({"v", "a", 4.0});
  map.edges.push_back({"a", "b", 4.0});
  map.edges.push_back({"a", "dock_2", 4.0});
  map.edges.push_back({"dock_2", "dock_1", 2.0});
  return map;
}

std::vector<Eigen::Vector2d> Square() {
  return {{-0.3, -0.3}, {0.3, -0.3}, {0.3, 0.3}, {-0.3, 0.3}};
}

// One control tick of an ideal robot (its belief the truth): the controller
// commands, the wheels drive `pose` on; started and completed missions are
// appended to `started` and `completed` (either may be null).
void DriveTick(NavigationController& controller, const NavigationControllerOptions& options,
               std::int64_t tick, core::Pose2* pose, WheelSpeeds* held,
               std::vector<NavigationEvent>* started, std::vector<NavigationEvent>* completed) {
  if (const std::optional<WheelSpeeds> w =
          controller.OnTick(ControlTick{tick, tick * kStepS, *pose, *pose, false})) {
    *held = *w;
  }
  const core::WheelTravel travel{
      held->left_radps * options.odometry.left_wheel_radius_m * kStepS,
      held->right_radps * options.odometry.right_wheel_radius_m * kStepS};
  *pose = core::DiffDriveStep(*pose, travel, options.odometry.wheelbase_m);
  std::vector<NavigationEvent> events;
  controller.TakeEvents(&events);
  for (const NavigationEvent& e : events) {
    if (e.type == NavigationEvent::Type::kMissionStarted && started) started->push_back(e);
    if (e.type == NavigationEvent::Type::kMissionCompleted && completed) completed->push_back(e);
  }
}

struct RestRun {
  std::vector<NavigationEvent> started, completed;
  NavigationFigures figures;
  core::Pose2 pose;
  int published_occupied = -2;  // the robot's occupied station on the board at the end
};

// Robot 0 tours {a, b} from v; robot 1 occupies b until `b_free_s`; robot 2
// occupies `dock_taken` (-1: none). `start` places robot 0 (v by default).
RestRun Tour(const std::vector<std::string>& rest_among, int dock_taken, double b_free_s,
             double duration_s, core::Pose2 start = {}) {
  NavigationControllerOptions options;
  options.step_s = kStepS;
  options.dwell_s = 5.0;
  options.rest_among = rest_among;
  FleetCoordinator coordinator(3, FleetOptions{});
  coordinator.SetStations({"a", "b"});
  NavigationController controller(
      Floor(), Square(), MissionSequence::Tour({"a", "b"}, 2, true, core::RandomStream(5, 1)),
      options);
  controller.SetFleet({&coordinator, 0});
  coordinator.Join(1, Square());
  coordinator.Join(2, Square());
  RestRun run;
  run.pose = start;
  WheelSpeeds held;
  for (std::int64_t tick = 0; tick * kStepS < duration_s; ++tick) {
    const double now_s = tick * kStepS;
    FleetMessage one, two;
    one.pose = core::Pose2{-50.0, -50.0, 0.0};
    one.occupied_station = now_s < b_free_s ? kB : -1;
    two.pose = core::Pose2{-50.0, 50.0, 0.0};
    two.occupied_station = dock_taken;
    coordinator.Send(1, one);
    coordinator.Send(2, two);
    coordinator.Merge();
    DriveTick(controller, options, tick, &run.pose, &held, &run.started, &run.completed);
  }
  run.figures = *controller.navigation();
  run.published_occupied = coordinator.board().message(0).occupied_station;
  return run;
}

const std::vector<std::string> kDocks = {"dock_1", "dock_2"};

// b stays taken for good: after its visit to a, its dwell and station_wait_s
// of waiting, the robot makes way at the nearest free dock, and a is free.
TEST(NavigationControllerRest, MakesWayAtTheNearestFreeDockWhenNoStationIsFree) {
  const RestRun run = Tour(kDocks, -1, 1e9, 120.0);
  ASSERT_GE(run.completed.size(), 2u);
  EXPECT_EQ(run.completed[0].goal, "a");
  EXPECT_FALSE(run.completed[0].rest);
  ASSERT_GE(run.started.size(), 2u);
  EXPECT_EQ(run.started[1].goal, "dock_2");
  EXPECT_TRUE(run.started[1].rest);
  const NavigationControllerOptions defaults;
  EXPECT_NEAR(run.started[1].at_s - run.completed[0].at_s, 5.0 + defaults.station_wait_s, 0.3);
  EXPECT_EQ(run.completed[1].goal, "dock_2");
  EXPECT_TRUE(run.completed[1].rest);
  EXPECT_EQ(run.figures.rest_missions, 1);
  // It rests there: no third mission while b is taken, and the long wait at
  // the dock is not standing still with a mission.
  EXPECT_EQ(run.started.size(), 2u);
  EXPECT_LT(run.figures.longest_still_s, 30.0);
  EXPECT_NEAR(run.pose.x_m, 8.0, 0.2);
  EXPECT_NEAR(run.pose.y_m, 0.0, 0.2);
  EXPECT_EQ(run.published_occupied, kDock2);  // a is free for another robot
}

// The same without rest nodes: the robot stands at a, still with a mission.
TEST(NavigationControllerRest, WithoutRestNodesTheRobotStandsAtItsStation) {
  const RestRun run = Tour({}, -1, 1e9, 120.0);
  ASSERT_EQ(run.completed.size(), 1u);
  EXPECT_EQ(run.started.size(), 1u);
  EXPECT_EQ(run.figures.rest_missions, 0);
  EXPECT_GT(run.figures.longest_still_s, 90.0);
  EXPECT_EQ(run.published_occupied, kA);
}

// dock_2 is taken: the robot goes on to dock_1.
TEST(NavigationControllerRest, PassesOverATakenDock) {
  const RestRun run = Tour(kDocks, kDock2, 1e9, 120.0);
  ASSERT_GE(run.completed.size(), 2u);
  EXPECT_EQ(run.completed[1].goal, "dock_1");
  EXPECT_EQ(run.published_occupied, kDock1);
}

// Every dock taken: it waits at its station.
TEST(NavigationControllerRest, WaitsAtItsStationWhenEveryDockIsTaken) {
  const RestRun run = Tour({"dock_2"}, kDock2, 1e9, 120.0);
  EXPECT_EQ(run.started.size(), 1u);
  EXPECT_EQ(run.published_occupied, kA);
}

// b frees while the robot rests: it leaves the dock for b, a tour mission.
TEST(NavigationControllerRest, LeavesTheDockForAStationThatFrees) {
  const RestRun run = Tour(kDocks, -1, 60.0, 120.0);
  ASSERT_GE(run.started.size(), 3u);
  EXPECT_EQ(run.started[2].goal, "b");
  EXPECT_FALSE(run.started[2].rest);
  EXPECT_GE(run.started[2].at_s, 60.0);
  EXPECT_LT(run.started[2].at_s, 61.0);
}

// A robot standing at a dock when the run starts occupies it: no other robot
// is sent there, and it is released once the robot has left for a.
TEST(NavigationControllerRest, ARobotStartingAtADockOccupiesItUntilItLeaves) {
  const core::Pose2 at_dock_1{10.3, 0.0, 0.0};
  EXPECT_EQ(Tour(kDocks, -1, 1e9, 1.0, at_dock_1).published_occupied, kDock1);
  const RestRun run = Tour(kDocks, -1, 1e9, 30.0, at_dock_1);
  ASSERT_GE(run.started.size(), 1u);
  EXPECT_EQ(run.started[0].goal, "a");
  EXPECT_EQ(run.published_occupied, kA);
  // Without rest nodes nothing is occupied at the start.
  EXPECT_EQ(Tour({}, -1, 1e9, 1.0, at_dock_1).published_occupied, -1);
}

// A robot that waited for a station and then lost the freed one to another
// robot in the same cycle (robot order) waits on from when it began: it
// makes way station_wait_s after the wait began, not after the lost race.
TEST(NavigationControllerRest, ALostRaceKeepsTheTimeTheWaitBegan) {
  constexpr double kFreedS = 10.0;
  NavigationControllerOptions options;
  options.step_s = kStepS;
  options.rest_among = kDocks;
  options.station_wait_s = 15.0;  // every station taken from 0 s; the race at 10 s
  FleetCoordinator coordinator(3, FleetOptions{});
  coordinator.SetStations({"a", "b"});
  NavigationController controller(
      Floor(), Square(), MissionSequence::Tour({"a", "b"}, 2, true, core::RandomStream(5, 1)),
      options);
  controller.SetFleet({&coordinator, 1});  // robot 0 wins a same-cycle race
  coordinator.Join(0, Square());
  coordinator.Join(2, Square());
  core::Pose2 pose;
  WheelSpeeds held;
  std::vector<NavigationEvent> started;
  for (std::int64_t tick = 0; tick * kStepS < kFreedS + 10.0; ++tick) {
    const double now_s = tick * kStepS;
    // Robot 0 stands at a until kFreedS, when it leaves and, a cycle later,
    // reserves a again; robot 2 stands at b throughout.
    FleetMessage zero, two;
    zero.pose = core::Pose2{-50.0, -50.0, 0.0};
    if (now_s < kFreedS) zero.occupied_station = kA;
    if (now_s >= kFreedS + 0.1) zero.reserved_station = kA;
    two.pose = core::Pose2{-50.0, 50.0, 0.0};
    two.occupied_station = kB;
    coordinator.Send(0, zero);
    coordinator.Send(2, two);
    coordinator.Merge();
    DriveTick(controller, options, tick, &pose, &held, &started, nullptr);
  }
  // The race for a (started, then taken back), then the rest trip at 15 s.
  ASSERT_EQ(started.size(), 2u);
  EXPECT_EQ(started[0].goal, "a");
  EXPECT_NEAR(started[0].at_s, kFreedS, 0.11);
  EXPECT_TRUE(started[1].rest);
  EXPECT_NEAR(started[1].at_s, options.station_wait_s, 0.11);
  EXPECT_EQ(controller.navigation()->rest_missions, 1);
  EXPECT_EQ(controller.navigation()->missions_started, 1);  // the lost race is not counted
}

}  // namespace
}  // namespace pavilion::nav
