// The run table of issue 21 on synthetic sequences: lost situations and their
// causes, recoveries after kidnaps and staff pushes, interventions, Table 4.3's
// missions without a match, and the fleet's sums and the reference's keys.
#include "scenarios/metrics/run_table.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>

#include "scenarios/config/run_reference.h"
#include "scenarios/metrics/run_metrics.h"

namespace pavilion::scenarios {
namespace {

using Mode = nav::LocalizationMode;

constexpr double kStepS = 0.01;  // a 100 Hz physics step
constexpr double kDeg = std::numbers::pi / 180.0;

// A cycle of the given mode and true error with `matched` lines.
LocalizationCycle Cycle(Mode mode, double position_error_m, double heading_error_rad,
                        int matched = 3) {
  LocalizationCycle c;
  c.mode = mode;
  c.lost = mode == Mode::kLost;
  c.position_error_m = position_error_m;
  c.heading_error_rad = heading_error_rad;
  c.matched_lines = matched;
  return c;
}

bool Lost(const LocalizationCycle& c) {
  return c.lost || c.position_error_m > kLostPositionErrorM ||
         std::abs(c.heading_error_rad) > kLostHeadingErrorRad;
}

// Drives the tracker: steps at `speed_mps` (standing `still_s` growing when
// `standing`), a cycle like `cycle` every 0.5 s, for `duration_s`.
struct Drive {
  RobotDayTracker* t;
  double now_s = 0.0;
  double still_s = 0.0;
  int mission = 1;

  void operator()(double duration_s, double speed_mps, const LocalizationCycle& cycle,
                  bool standing = false) {
    const int steps = static_cast<int>(duration_s / kStepS + 0.5);
    for (int k = 1; k <= steps; ++k) {
      now_s += kStepS;
      still_s = standing ? still_s + kStepS : 0.0;
      t->OnStep(now_s, kStepS, speed_mps, still_s);
      if (k % 50 == 0) t->OnCycle(now_s, cycle, Lost(cycle), mission);
    }
  }
};

// Confirms a kidnap followed by 12 s of motion lost and then a correct
// localization is one loss caused by the kidnap and one recovery after 12 s of
// motion; a push whose robot never loses track recovers at its first cycle
// after the motors engage.
TEST(RunTableTest, KidnapAndPushRecoveriesAreTimedInMotion) {
  RobotDayTracker t;
  Drive d{&t};
  const LocalizationCycle good = Cycle(Mode::kLocalized, 0.02, 0.5 * kDeg);
  d(5.0, 0.3, good);
  t.OnKidnap(d.now_s);
  d(4.0, 0.3, Cycle(Mode::kLost, 3.0, 40 * kDeg, 0));
  d(3.0, 0.0, Cycle(Mode::kLost, 3.0, 40 * kDeg, 0));  // standing: no motion time
  d(8.0, 0.3, Cycle(Mode::kNotLocalized, 3.0, 40 * kDeg, 0));
  d(5.0, 0.3, good);
  t.OnPush(d.now_s, 1.5, /*motors_disengaged=*/true);
  d(3.0, 0.3, good);  // judged only from the motors' engagement on
  t.OnMotorsEngaged(d.now_s);
  d(2.0, 0.3, good);
  const RobotDayFigures f = t.Figures(d.now_s);
  EXPECT_EQ(f.kidnaps, 1);
  EXPECT_EQ(f.pushes, 1);
  EXPECT_EQ(f.recovered, 2);
  ASSERT_EQ(f.recovery_motion_s.size(), 2u);
  // 4 + 8 s moving (not the 3 s at rest) and the half second to the first good cycle.
  EXPECT_NEAR(f.recovery_motion_s[0], 12.5, 0.02);
  EXPECT_NEAR(f.recovery_motion_s[1], 0.5, 0.02);  // the first cycle after engagement
  EXPECT_EQ(f.lost_by_cause[static_cast<std::size_t>(LossCause::kKidnap)], 1);
  EXPECT_EQ(f.lost_situations(), 1);
  EXPECT_EQ(f.lost_over_30s, 0);  // 15 s lost
  EXPECT_NEAR(f.longest_lost_s, 15.0, 0.6);
}

// Confirms a disturbance not recovered within 30 s of motion is not counted
// recovered, however good the estimate becomes later, and that a loss lasting
// longer than 30 s is one intervention.
TEST(RunTableTest, LateRecoveryIsNotRecoveredAndLongLossIsAnIntervention) {
  RobotDayTracker t;
  Drive d{&t};
  d(2.0, 0.3, Cycle(Mode::kLocalized, 0.02, 0.0));
  t.OnKidnap(d.now_s);
  d(40.0, 0.3, Cycle(Mode::kNotLocalized, 2.0, 0.0, 0));
  d(5.0, 0.3, Cycle(Mode::kLocalized, 0.02, 0.0));
  const RobotDayFigures f = t.Figures(d.now_s);
  EXPECT_EQ(f.kidnaps, 1);
  EXPECT_EQ(f.recovered, 0);
  EXPECT_EQ(f.unrecovered_at_end, 0);
  EXPECT_EQ(f.lost_over_30s, 1);
}

// Confirms the cause of a loss: a collision within 30 s before it, and
// nothing when the last collision was longer ago.
TEST(RunTableTest, LossesAreAttributedToARecentCollisionOnly) {
  RobotDayTracker t;
  Drive d{&t};
  const LocalizationCycle good = Cycle(Mode::kLocalized, 0.02, 0.0);
  const LocalizationCycle off = Cycle(Mode::kLocalized, 0.1, 15 * kDeg);
  d(2.0, 0.3, good);
  t.OnCollision(d.now_s);
  d(10.0, 0.3, good);
  d(2.0, 0.3, off);  // begins 10 s after the collision
  d(40.0, 0.3, good);
  d(2.0, 0.3, off);  // begins 52 s after it
  const RobotDayFigures f = t.Figures(d.now_s);
  EXPECT_EQ(f.lost_by_cause[static_cast<std::size_t>(LossCause::kCollision)], 1);
  EXPECT_EQ(f.lost_by_cause[static_cast<std::size_t>(LossCause::kUnexplained)], 1);
}

// Confirms a loss that flickers — off, briefly right, off again for a minute
// after its collision — is counted as begun by the collision each time, not
// as unexplained once the collision is more than 30 s past.
TEST(RunTableTest, ALossThatFlickersKeepsItsCause) {
  RobotDayTracker t;
  Drive d{&t};
  const LocalizationCycle good = Cycle(Mode::kLocalized, 0.02, 0.0);
  const LocalizationCycle off = Cycle(Mode::kLocalized, 20.0, 0.0);
  d(2.0, 0.3, good);
  t.OnCollision(d.now_s);
  for (int k = 0; k < 6; ++k) {
    d(10.0, 0.3, off);
    d(1.0, 0.3, Cycle(Mode::kNotLocalized, 0.1, 0.0, 0));
  }
  const RobotDayFigures f = t.Figures(d.now_s);
  EXPECT_EQ(f.lost_situations(), 6);
  EXPECT_EQ(f.lost_by_cause[static_cast<std::size_t>(LossCause::kCollision)], 6);
}

// Confirms a robot standing with a mission for more than 60 s is one
// intervention per episode, not one per tick.
TEST(RunTableTest, StandingOverAMinuteIsOneInterventionPerEpisode) {
  RobotDayTracker t;
  Drive d{&t};
  const LocalizationCycle good = Cycle(Mode::kLocalized, 0.02, 0.0);
  d(59.0, 0.0, good, /*standing=*/true);
  EXPECT_EQ(t.Figures(d.now_s).still_over_60s, 0);
  d(30.0, 0.0, good, true);
  d(5.0, 0.3, good);
  d(70.0, 0.0, good, true);
  EXPECT_EQ(t.Figures(d.now_s).still_over_60s, 2);
}

// Confirms Table 4.3's count: a mission with a 6 s stretch without a match
// counts for 5 s only, one with 11 s for both, one with matches throughout
// for neither; the stretch is measured within its mission.
TEST(RunTableTest, MissionsWithoutMatchCountTheirLongestStretch) {
  RobotDayTracker t;
  Drive d{&t};
  const LocalizationCycle matched = Cycle(Mode::kLocalized, 0.02, 0.0, 2);
  const LocalizationCycle unmatched = Cycle(Mode::kLocalized, 0.02, 0.0, 0);
  d(3.0, 0.3, matched);
  d(6.0, 0.3, unmatched);
  d(3.0, 0.3, matched);
  d.mission = 2;
  d(11.0, 0.3, unmatched);
  d.mission = 3;
  d(20.0, 0.3, matched);
  const RobotDayFigures f = t.Figures(d.now_s);
  EXPECT_EQ(f.missions_without_match_5s, 2);
  EXPECT_EQ(f.missions_without_match_10s, 1);
  EXPECT_NEAR(f.longest_without_match_s, 10.5, 0.6);
}

// Confirms the fleet's table sums its robots and takes its ratios over the
// sums, and that a run without a localizing robot has none.
TEST(RunTableTest, FleetTableSumsRobots) {
  RunMetrics m;
  m.sim_duration_s = 7200.0;
  EXPECT_FALSE(MakeRunTable(m).has_value());
  for (int k = 0; k < 2; ++k) {
    RobotMetrics r;
    r.id = std::to_string(k);  // (GCC 12 warns falsely, -Wrestrict, on "r" + ...)
    r.distance_m = 1000.0;
    r.navigation.emplace();
    r.navigation->missions_started = 10;
    r.navigation->missions_completed = 9 - k;
    r.navigation->missions_aborted[0] = k;
    r.day.emplace();
    r.day->driving_s = 4000.0;
    r.day->kidnaps = 1;
    r.day->pushes = 1;
    r.day->recovered = 2 - k;
    r.day->still_over_60s = k;
    m.robots.push_back(r);
  }
  const RunTable t = *MakeRunTable(m);
  EXPECT_DOUBLE_EQ(t.robot_hours, 4.0);
  EXPECT_DOUBLE_EQ(t.distance_km, 2.0);
  EXPECT_NEAR(t.mean_speed_mps, 2000.0 / (4 * 3600.0), 1e-12);
  EXPECT_NEAR(t.mean_driving_speed_mps, 0.25, 1e-12);
  EXPECT_EQ(t.missions_in_progress(), 2);
  EXPECT_NEAR(t.missions_completed_ratio(), 17.0 / 18.0, 1e-12);  // of the ended
  EXPECT_NEAR(t.recovered_ratio(), 0.75, 1e-12);
  EXPECT_NEAR(t.interventions_per_robot_hour(), 0.25, 1e-12);
  const nlohmann::ordered_json j = RunTableToJson(t);
  EXPECT_EQ(j["missions"]["in_progress"], 2);
  EXPECT_EQ(j["interventions"]["total"], 1);
}

// Confirms the reference's keys are the table's numeric leaves.
TEST(RunTableTest, ReferencePathsAreTheTablesFigures) {
  const std::vector<std::string> paths = RunTablePaths();
  const auto has = [&](const std::string& p) {
    return std::find(paths.begin(), paths.end(), p) != paths.end();
  };
  EXPECT_TRUE(has("distance_km"));
  EXPECT_TRUE(has("missions.started"));
  EXPECT_TRUE(has("lost_by_cause.unexplained"));
  EXPECT_TRUE(has("collisions.invisible_object"));
  EXPECT_FALSE(has("missions"));  // a section, not a figure
}

}  // namespace
}  // namespace pavilion::scenarios
