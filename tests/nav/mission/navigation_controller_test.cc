// The mission layer of the navigation controller when the robot's estimator
// declares itself lost: the mission is held while it relocalizes and goes on
// from where the robot finds itself; it is aborted as lost only after
// relocalization_timeout_s (or at once with 0).
#include "nav/mission/navigation_controller.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

#include "core/odometry/diff_drive.h"

namespace pavilion::nav {
namespace {

constexpr double kStepS = 0.005;

// An empty floor with two stations 8 m apart and one edge.
core::RobotMap TwoStations() {
  core::RobotMap map;
  map.name = "two_stations";
  map.nodes.push_back({"a", {0.0, 0.0, 0.0}, true});
  map.nodes.push_back({"b", {8.0, 0.0, 0.0}, true});
  map.edges.push_back({"a", "b", 8.0});
  return map;
}

std::vector<Eigen::Vector2d> Square() {
  return {{-0.3, -0.3}, {0.3, -0.3}, {0.3, 0.3}, {-0.3, 0.3}};
}

struct MissionRun {
  std::vector<NavigationEvent> events;
  NavigationFigures figures;
  core::Pose2 pose;
};

// The robot drives to b on an ideal floor (its belief is the truth) and is
// lost, its belief frozen, from lost_from_s for lost_for_s.
MissionRun DriveToB(double relocalization_timeout_s, double lost_from_s, double lost_for_s,
                    double duration_s) {
  NavigationControllerOptions options;
  options.step_s = kStepS;
  options.relocalization_timeout_s = relocalization_timeout_s;
  NavigationController controller(TwoStations(), Square(), MissionSequence::List({"b"}), options);
  MissionRun run;
  const double b = options.odometry.wheelbase_m;
  WheelSpeeds held;  // a command holds until the controller changes it
  for (std::int64_t tick = 0; tick * kStepS < duration_s; ++tick) {
    const double now_s = tick * kStepS;
    const bool lost = now_s >= lost_from_s && now_s < lost_from_s + lost_for_s;
    if (const std::optional<WheelSpeeds> w =
            controller.OnTick(ControlTick{tick, now_s, run.pose, run.pose, lost})) {
      held = *w;
    }
    // While lost the estimator's fallback would drive; here the robot stands.
    if (!lost) {
      const core::WheelTravel travel{
          held.left_radps * options.odometry.left_wheel_radius_m * kStepS,
          held.right_radps * options.odometry.right_wheel_radius_m * kStepS};
      run.pose = core::DiffDriveStep(run.pose, travel, b);
    }
    controller.TakeEvents(&run.events);
  }
  run.figures = *controller.navigation();
  return run;
}

int Count(const MissionRun& run, NavigationEvent::Type type) {
  int n = 0;
  for (const NavigationEvent& e : run.events) n += e.type == type ? 1 : 0;
  return n;
}

TEST(NavigationController, ReachesTheStationWhenNeverLost) {
  const MissionRun run = DriveToB(30.0, 1e9, 0.0, 60.0);
  EXPECT_EQ(run.figures.missions_completed, 1);
  EXPECT_NEAR(run.pose.x_m, 8.0, 0.1);
}

TEST(NavigationController, HoldsTheMissionWhileRelocalizingAndReplans) {
  const MissionRun run = DriveToB(30.0, 3.0, 5.0, 60.0);
  EXPECT_EQ(run.figures.missions_started, 1);
  EXPECT_EQ(run.figures.missions_completed, 1);
  EXPECT_EQ(run.figures.missions_aborted_total(), 0);
  bool replanned = false;
  for (const NavigationEvent& e : run.events) {
    if (e.type == NavigationEvent::Type::kReplanned && e.cause == "relocalized") {
      replanned = true;
      EXPECT_NEAR(e.at_s, 8.0, 0.01);  // at the first tick localized again
    }
  }
  EXPECT_TRUE(replanned);
  EXPECT_NEAR(run.pose.x_m, 8.0, 0.1);
}

// The run's one mission was aborted as lost at `at_s`.
void ExpectAbortedAsLostAt(const MissionRun& run, double at_s) {
  ASSERT_EQ(Count(run, NavigationEvent::Type::kMissionAborted), 1);
  for (const NavigationEvent& e : run.events) {
    if (e.type != NavigationEvent::Type::kMissionAborted) continue;
    EXPECT_EQ(e.reason, AbortReason::kLost);
    EXPECT_NEAR(e.at_s, at_s, 0.01);
  }
}

TEST(NavigationController, AbortsAsLostWhenRelocalizationTakesTooLong) {
  const MissionRun run = DriveToB(30.0, 3.0, 1e9, 40.0);
  ExpectAbortedAsLostAt(run, 33.0);
  EXPECT_EQ(run.figures.missions_completed, 0);
}

TEST(NavigationController, AbortsAtOnceWithoutARelocalizationTimeout) {
  const MissionRun run = DriveToB(0.0, 3.0, 5.0, 60.0);
  ExpectAbortedAsLostAt(run, 3.0);
  // The one mission of the list is gone; nothing more is started.
  EXPECT_EQ(run.figures.missions_started, 1);
  EXPECT_EQ(run.figures.missions_completed, 0);
}

}  // namespace
}  // namespace pavilion::nav
