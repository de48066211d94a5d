// The robots-block-each-other deadlock rule (nav/fleet/deadlock_monitor.h,
// thesis §6.5) on constructed cycle sequences of the 10 Hz dynamic window.
#include "nav/fleet/deadlock_monitor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace pavilion::nav {
namespace {

constexpr double kDt = 0.1;  // the dynamic window's cycle (§6.3.4)

// The first cycle of a stretch of cycles with each output, -1 for none.
struct Stretch {
  int detected_at = -1;
  int clip_at = -1;
  int retreat_at = -1;
};

// Cycles [from, to) of a robot with a goal that stays stalled with a contour
// overlapping its hull, without moving.
Stretch Deadlocked(DeadlockMonitor* m, int from, int to) {
  Stretch run;
  for (int k = from; k < to; ++k) {
    const DeadlockMonitor::Step s = m->Update(k * kDt, true, true, true, 0.0);
    if (s.detected && run.detected_at < 0) run.detected_at = k;
    if (s.clip && run.clip_at < 0) run.clip_at = k;
    if (s.retreat && run.retreat_at < 0) run.retreat_at = k;
    EXPECT_TRUE(!s.retreat || s.clip);  // a retreat is with clipped contours
  }
  return run;
}

// Overlap and stall for less than detect_s is no deadlock; a break restarts
// the count.
TEST(DeadlockMonitorTest, ShortStallIsNotDetected) {
  DeadlockMonitor m(DeadlockOptions{}, 1);
  EXPECT_EQ(Deadlocked(&m, 0, 30).detected_at, -1);  // 0 .. 2.9 s
  m.Update(3.0, true, true, false, 0.0);             // moving again
  EXPECT_EQ(Deadlocked(&m, 31, 60).detected_at, -1);
  EXPECT_EQ(m.detected(), 0);
}

// Overlap and stall for detect_s is detected once, at the first cycle 3 s in.
TEST(DeadlockMonitorTest, DetectedOnceAfterDetectTime) {
  DeadlockOptions options;
  options.give_up_s = 100.0;
  DeadlockMonitor m(options, 1);
  int detections = 0;
  for (int k = 0; k < 400; ++k) detections += m.Update(k * kDt, true, true, true, 0.0).detected;
  EXPECT_EQ(detections, 1);
  EXPECT_EQ(m.detected(), 1);
  DeadlockMonitor again(options, 1);
  EXPECT_EQ(Deadlocked(&again, 0, 40).detected_at, 30);
  // Neither without a goal nor without a stall.
  DeadlockMonitor idle(options, 1);
  for (int k = 0; k < 100; ++k) {
    EXPECT_FALSE(idle.Update(k * kDt, false, true, true, 0.0).detected);
    EXPECT_FALSE(idle.Update(k * kDt, true, true, false, 0.0).detected);
  }
}

// Clipping starts after the back-off, drawn in [0, backoff_max_s]: the same
// draw for the same seed, different draws over a few seeds.
TEST(DeadlockMonitorTest, BackoffIsSeededAndBounded) {
  std::set<double> draws;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    DeadlockMonitor m(DeadlockOptions{}, seed);
    const Stretch run = Deadlocked(&m, 0, 100);
    ASSERT_EQ(run.detected_at, 30);
    EXPECT_GE(m.backoff_s(), 0.0);
    EXPECT_LE(m.backoff_s(), 4.0);
    // The first clipping cycle is the first at or after detection + back-off.
    ASSERT_GE(run.clip_at, run.detected_at);
    EXPECT_GE((run.clip_at - run.detected_at) * kDt, m.backoff_s() - 1e-9);
    EXPECT_LT((run.clip_at - run.detected_at - 1) * kDt, m.backoff_s());
    DeadlockMonitor twin(DeadlockOptions{}, seed);
    Deadlocked(&twin, 0, 100);
    EXPECT_EQ(twin.backoff_s(), m.backoff_s());
    draws.insert(m.backoff_s());
  }
  EXPECT_EQ(draws.size(), 8u);
}

// Moving resolved_move_m after detection resolves it, with its duration; so
// does 1 s with neither overlap nor stall.
TEST(DeadlockMonitorTest, ResolvedAfterMovingOrClearing) {
  DeadlockMonitor m(DeadlockOptions{}, 3);
  Deadlocked(&m, 0, 80);  // detected at 3 s, clipping from 3 s + back-off < 7 s
  DeadlockMonitor::Step s = m.Update(8.0, true, true, false, 0.2);
  EXPECT_TRUE(s.clip);
  EXPECT_FALSE(s.resolved);
  s = m.Update(8.1, true, true, false, 0.31);
  EXPECT_TRUE(s.resolved);
  EXPECT_FALSE(s.clip);
  EXPECT_NEAR(s.resolution_s, 8.1 - 3.0, 1e-9);
  EXPECT_EQ(m.resolved(), 1);
  EXPECT_NEAR(m.longest_resolution_s(), 5.1, 1e-9);

  DeadlockMonitor c(DeadlockOptions{}, 3);
  Deadlocked(&c, 0, 40);
  int resolved_at = -1;
  for (int k = 40; k < 60 && resolved_at < 0; ++k) {
    if (c.Update(k * kDt, true, false, false, 0.0).resolved) resolved_at = k;
  }
  EXPECT_EQ(resolved_at, 50);  // free from 4.0 s, resolved at 5.0 s
  EXPECT_EQ(c.resolved(), 1);
  EXPECT_NEAR(c.longest_resolution_s(), 2.0, 1e-9);
}

// Still stalled retreat_after_s after the back-off, the robot yields: the
// retreat starts then, never before, and ends with the episode.
TEST(DeadlockMonitorTest, RetreatsWhenClippingFindsNoWayOn) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    DeadlockMonitor m(DeadlockOptions{}, seed);
    const Stretch run = Deadlocked(&m, 0, 120);
    ASSERT_EQ(run.detected_at, 30);
    ASSERT_GE(run.retreat_at, 0);
    const double retreat_s = 3.0 + m.backoff_s() + DeadlockOptions{}.retreat_after_s;
    EXPECT_GE(run.retreat_at * kDt, retreat_s - 1e-9);
    EXPECT_LT((run.retreat_at - 1) * kDt, retreat_s);
    // Moving away resolves it; the retreat stops.
    const DeadlockMonitor::Step s = m.Update(12.0, true, true, false, 0.5);
    EXPECT_TRUE(s.resolved);
    EXPECT_FALSE(s.retreat);
  }
}

// The yield goes straight away from the other robot where nothing is in the
// way, and sideways where a wall is behind (the room counts, not the angle).
TEST(YieldDirectionTest, AwayFromTheOtherWhereThereIsRoom) {
  const Eigen::Vector2d other(1.0, 0.0);
  const Eigen::Vector2d open = YieldDirection(other, 0.3, 1.0, {});
  EXPECT_NEAR(open.x(), -1.0, 1e-12);
  EXPECT_NEAR(open.y(), 0.0, 1e-12);
  std::vector<Eigen::Vector2d> wall;  // 0.5 m behind, 4 m long
  for (int i = -40; i <= 40; ++i) wall.emplace_back(-0.5, 0.05 * i);
  const Eigen::Vector2d side = YieldDirection(other, 0.3, 1.0, wall);
  EXPECT_NEAR(side.x(), 0.0, 1e-12);
  EXPECT_NEAR(side.y(), 1.0, 1e-12);  // the first of the two open sides
  // With the left side closed too, the right.
  for (int i = -10; i <= 10; ++i) wall.emplace_back(0.05 * i, 0.6);
  const Eigen::Vector2d right = YieldDirection(other, 0.3, 1.0, wall);
  EXPECT_NEAR(right.x(), 0.0, 1e-12);
  EXPECT_NEAR(right.y(), -1.0, 1e-12);
}

// With resolve off the deadlock is detected and counted, but contours are
// never clipped and nothing counts as resolved.
TEST(DeadlockMonitorTest, ObserveOnlyNeverClipsOrResolves) {
  DeadlockOptions options;
  options.resolve = false;
  DeadlockMonitor m(options, 1);
  const Stretch run = Deadlocked(&m, 0, 200);
  EXPECT_EQ(run.detected_at, 30);
  EXPECT_EQ(run.clip_at, -1);
  EXPECT_EQ(run.retreat_at, -1);
  for (int k = 200; k < 230; ++k) {
    const DeadlockMonitor::Step s = m.Update(k * kDt, true, false, false, 1.0 + k);
    EXPECT_FALSE(s.resolved);
    EXPECT_FALSE(s.clip);
  }
  EXPECT_EQ(m.detected(), 1);
  EXPECT_EQ(m.resolved(), 0);
}

// give_up_s after detection an open deadlock is counted unresolved and the
// rule starts over: suspect from the next cycle, detected again detect_s later.
TEST(DeadlockMonitorTest, GivesUpAndStartsOver) {
  DeadlockMonitor m(DeadlockOptions{}, 5);
  std::vector<int> detections;
  for (int k = 0; k < 700; ++k) {
    if (m.Update(k * kDt, true, true, true, 0.0).detected) detections.push_back(k);
    if (k == 329) {
      EXPECT_EQ(m.unresolved(), 0);  // 32.9 s: 29.9 s after detection
    }
  }
  // Detected at 3 s, given up at 33 s, suspect from 33.1 s, detected at
  // 36.1 s, given up at 66.1 s, suspect from 66.2 s, detected at 69.2 s.
  EXPECT_EQ(detections, (std::vector<int>{30, 361, 692}));
  EXPECT_EQ(m.detected(), 3);
  EXPECT_EQ(m.unresolved(), 2);
  EXPECT_EQ(m.resolved(), 0);
}

// Validate names the field; bad cycle inputs are rejected.
TEST(DeadlockMonitorTest, RejectsBadInput) {
  const auto message = [](const DeadlockOptions& o) {
    try {
      o.Validate();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  DeadlockOptions o;
  EXPECT_EQ(message(o), "");
  o.detect_s = 0.0;
  EXPECT_NE(message(o).find("detect_s"), std::string::npos);
  o = {};
  o.backoff_max_s = -1.0;
  EXPECT_NE(message(o).find("backoff_max_s"), std::string::npos);
  o = {};
  o.resolved_move_m = 0.0;
  EXPECT_NE(message(o).find("resolved_move_m"), std::string::npos);
  o = {};
  o.give_up_s = 2.0;  // not above the back-off's 4 s
  EXPECT_NE(message(o).find("give_up_s"), std::string::npos);
  DeadlockMonitor m(DeadlockOptions{}, 1);
  EXPECT_THROW(m.Update(std::nan(""), true, true, true, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::nav
