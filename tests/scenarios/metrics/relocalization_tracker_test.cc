// The relocalization figures (metrics.md "Relocalization", issue 18) on
// synthetic sequences of steps, kidnaps and estimator cycles.
#include "scenarios/metrics/relocalization_tracker.h"

#include <gtest/gtest.h>

#include <numbers>

namespace pavilion::scenarios {
namespace {

using Mode = nav::LocalizationMode;

constexpr double kStepS = 0.01;  // a 100 Hz physics step
constexpr double kDeg = std::numbers::pi / 180.0;

// Drives the tracker through time: steps at `speed_mps` and a cycle every
// `cycle_s` in `mode` with the given true error, from `*now_s` for `duration_s`.
void Drive(RelocalizationTracker* t, double* now_s, double duration_s, double speed_mps, Mode mode,
           int n, double position_error_m, double heading_error_rad, double cycle_s = 0.5) {
  const int steps = static_cast<int>(duration_s / kStepS + 0.5);
  const int per_cycle = static_cast<int>(cycle_s / kStepS + 0.5);
  for (int k = 1; k <= steps; ++k) {
    t->OnStep(kStepS, speed_mps * kStepS);
    *now_s += kStepS;
    if (k % per_cycle == 0) t->OnCycle(*now_s, mode, n, position_error_m, heading_error_rad);
  }
}

// Confirms a kidnap, then a declared loss, then a correct localization is one
// recovered kidnap with the motion time and distance to each.
TEST(RelocalizationTrackerTest, KidnapThenLostThenCorrectIsRecovered) {
  RelocalizationTracker t;
  double now_s = 0.0;
  Drive(&t, &now_s, 5.0, 0.3, Mode::kLocalized, 1, 0.02, 0.01);
  t.OnKidnap(now_s);
  // Still localized, 3 m off, for 2 s of motion; then lost for 3 s of motion,
  // 1 s standing still, 4 s more of motion; then localized 0.1 m off.
  Drive(&t, &now_s, 2.0, 0.3, Mode::kLocalized, 1, 3.0, 0.5);
  Drive(&t, &now_s, 3.0, 0.3, Mode::kLost, 0, 3.0, 0.5);
  Drive(&t, &now_s, 1.0, 0.0, Mode::kLost, 0, 3.0, 0.5);
  Drive(&t, &now_s, 4.0, 0.3, Mode::kNotLocalized, 3, 3.0, 0.5);
  const RelocalizationChange change = t.OnCycle(now_s, Mode::kLocalized, 1, 0.1, 2.0 * kDeg);
  EXPECT_TRUE(change.localized);
  EXPECT_TRUE(change.relocalized);
  EXPECT_TRUE(change.correct);
  Drive(&t, &now_s, 12.0, 0.3, Mode::kLocalized, 1, 0.1, 2.0 * kDeg);
  ASSERT_TRUE(t.active());
  const RelocalizationFigures f = t.Figures();
  ASSERT_EQ(f.kidnaps, 1);
  const KidnapOutcome& k = f.outcomes[0];
  EXPECT_NEAR(k.at_s, 5.0, 1e-9);
  EXPECT_TRUE(k.lost_declared);
  EXPECT_NEAR(k.motion_to_lost_s, 2.5, 1e-9);  // the first lost cycle, 0.5 s into the loss
  EXPECT_TRUE(k.recovered);
  EXPECT_NEAR(k.motion_to_relocalize_s, 9.0, 1e-9);  // 2 + 3 + 4 s of motion, not the 1 s at rest
  EXPECT_NEAR(k.distance_to_relocalize_m, 2.7, 1e-9);
  EXPECT_EQ(f.recovered, 1);
  EXPECT_DOUBLE_EQ(f.recovered_ratio, 1.0);
  EXPECT_DOUBLE_EQ(f.lost_declared_within_10s_ratio, 1.0);
  EXPECT_EQ(f.false_relocalizations, 0);  // off while localized was the kidnap's doing
  EXPECT_EQ(f.declared_losses, 1);
  EXPECT_EQ(f.max_hypotheses, 3);
  EXPECT_GT(f.mean_hypotheses, 0.5);
  EXPECT_LT(f.mean_hypotheses, 1.5);
}

// Confirms a relocalization 30 s of motion after the kidnap is not a recovery,
// and a loss declared after 10 s of motion is not a timely one.
TEST(RelocalizationTrackerTest, LateRelocalizationIsNotRecovered) {
  RelocalizationTracker t;
  double now_s = 0.0;
  t.OnKidnap(now_s);
  Drive(&t, &now_s, 12.0, 0.3, Mode::kLocalized, 1, 3.0, 0.5);
  Drive(&t, &now_s, 20.0, 0.3, Mode::kLost, 0, 3.0, 0.5);
  Drive(&t, &now_s, 5.0, 0.3, Mode::kLocalized, 1, 0.05, 0.01);
  const RelocalizationFigures f = t.Figures();
  ASSERT_EQ(f.kidnaps, 1);
  EXPECT_TRUE(f.outcomes[0].lost_declared);
  EXPECT_NEAR(f.outcomes[0].motion_to_lost_s, 12.5, 1e-9);
  EXPECT_FALSE(f.outcomes[0].recovered);
  EXPECT_DOUBLE_EQ(f.lost_declared_within_10s_ratio, 0.0);
  EXPECT_DOUBLE_EQ(f.recovered_ratio, 0.0);
}

// Confirms that declaring localized while 1 m off counts once per transition,
// not per cycle, and that the relocalized event then says incorrect.
TEST(RelocalizationTrackerTest, FalseRelocalizationCountedPerTransition) {
  RelocalizationTracker t;
  double now_s = 0.0;
  t.OnKidnap(now_s);
  Drive(&t, &now_s, 2.0, 0.3, Mode::kLost, 0, 3.0, 0.5);
  const RelocalizationChange wrong = t.OnCycle(now_s, Mode::kLocalized, 1, 1.0, 0.01);
  EXPECT_TRUE(wrong.relocalized);
  EXPECT_FALSE(wrong.correct);
  Drive(&t, &now_s, 5.0, 0.3, Mode::kLocalized, 1, 1.0, 0.01);  // still off: same event
  // Lost again, then localized 20 deg off: a second false relocalization.
  Drive(&t, &now_s, 2.0, 0.3, Mode::kLost, 0, 1.0, 0.01);
  Drive(&t, &now_s, 2.0, 0.3, Mode::kLocalized, 1, 0.05, 20.0 * kDeg);
  const RelocalizationFigures f = t.Figures();
  EXPECT_EQ(f.false_relocalizations, 2);
  EXPECT_EQ(f.declared_losses, 2);
  EXPECT_FALSE(f.outcomes[0].recovered);
}

// Confirms that being off long after a correct relocalization (a shove the
// tracking did not follow) is not a false relocalization: that is a lost
// situation of the localization figures.
TEST(RelocalizationTrackerTest, OffLongAfterACorrectRelocalizationIsNotFalse) {
  RelocalizationTracker t;
  double now_s = 0.0;
  t.OnKidnap(now_s);
  Drive(&t, &now_s, 2.0, 0.3, Mode::kLost, 0, 3.0, 0.5);
  Drive(&t, &now_s, 10.0, 0.3, Mode::kLocalized, 1, 0.01, 0.001);
  Drive(&t, &now_s, 2.0, 0.3, Mode::kLocalized, 1, 0.05, 12.0 * kDeg);  // pushed, still "localized"
  EXPECT_EQ(t.Figures().false_relocalizations, 0);
  EXPECT_TRUE(t.Figures().outcomes[0].recovered);
}

// Confirms the Fox-Burgard-Thrun recovery: within 0.45 m for more than 10 s,
// the stretch restarting when the estimate leaves; the recovery time is from
// the kidnap to the start of the stretch that lasted.
TEST(RelocalizationTrackerTest, FbtWindowNeedsMoreThanTenSecondsWithin) {
  RelocalizationTracker t;
  double now_s = 0.0;
  t.OnKidnap(now_s);
  Drive(&t, &now_s, 3.0, 0.3, Mode::kNotLocalized, 2, 2.0, 0.5);
  Drive(&t, &now_s, 8.0, 0.3, Mode::kNotLocalized, 2, 0.3, 0.5);  // 8 s within: too short
  Drive(&t, &now_s, 1.0, 0.3, Mode::kNotLocalized, 2, 0.6, 0.5);  // out again
  Drive(&t, &now_s, 11.0, 0.3, Mode::kNotLocalized, 2, 0.4, 0.5);
  RelocalizationFigures f = t.Figures();
  ASSERT_EQ(f.kidnaps, 1);
  EXPECT_TRUE(f.outcomes[0].fbt_recovered);
  EXPECT_NEAR(f.outcomes[0].fbt_recovery_s, 12.5, 1e-9);  // the first cycle within: 12.5 s
  EXPECT_DOUBLE_EQ(f.fbt_recovered_ratio, 1.0);
  EXPECT_NEAR(f.fbt_mean_recovery_s, 12.5, 1e-9);
  // A second kidnap whose good stretch ends after 9.5 s at the next kidnap.
  t.OnKidnap(now_s);
  Drive(&t, &now_s, 9.5, 0.3, Mode::kNotLocalized, 2, 0.2, 0.1);
  t.OnKidnap(now_s);
  f = t.Figures();
  ASSERT_EQ(f.kidnaps, 3);
  EXPECT_FALSE(f.outcomes[1].fbt_recovered);
  EXPECT_NEAR(f.fbt_recovered_ratio, 1.0 / 3.0, 1e-12);
}

// Confirms that a run without a kidnap or a declared loss has no section, and
// a declared loss alone makes one with no kidnaps.
TEST(RelocalizationTrackerTest, NoKidnapNoSection) {
  RelocalizationTracker t;
  double now_s = 0.0;
  Drive(&t, &now_s, 20.0, 0.3, Mode::kLocalized, 1, 0.8, 0.01);  // off by truth only
  EXPECT_FALSE(t.active());
  Drive(&t, &now_s, 1.0, 0.3, Mode::kLost, 0, 0.8, 0.01);
  EXPECT_TRUE(t.active());
  EXPECT_EQ(t.Figures().kidnaps, 0);
  EXPECT_EQ(t.Figures().declared_losses, 1);
}

// Confirms that motion time counts only steps faster than kMovingSpeedMps.
TEST(RelocalizationTrackerTest, MotionTimeCountsMovingStepsOnly) {
  RelocalizationTracker t;
  double now_s = 0.0;
  t.OnKidnap(now_s);
  Drive(&t, &now_s, 4.0, 0.5 * kMovingSpeedMps, Mode::kLost, 0, 3.0, 0.5);
  Drive(&t, &now_s, 3.0, 2.0 * kMovingSpeedMps, Mode::kLost, 0, 3.0, 0.5);
  const KidnapOutcome k = t.Figures().outcomes[0];
  EXPECT_NEAR(k.motion_s, 3.0, 1e-9);
  EXPECT_NEAR(k.distance_m, 4.0 * 0.5 * kMovingSpeedMps + 3.0 * 2.0 * kMovingSpeedMps, 1e-12);
}

}  // namespace
}  // namespace pavilion::scenarios
