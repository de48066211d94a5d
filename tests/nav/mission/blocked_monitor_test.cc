#include "nav/mission/blocked_monitor.h"

#include <gtest/gtest.h>

namespace pavilion::nav {
namespace {

constexpr double kDt = 0.1;

// Slower than 2 cm/s for more than 5 s is blocked; replans at 10 s and every
// 10 s after; the mission is given up at the abort time; moving resets it.
TEST(BlockedMonitorTest, BlockedReplansAndAborts) {
  BlockedMonitor m{BlockedMonitorOptions{}};
  int blocked_at = -1, replans = 0, abort_at = -1;
  for (int k = 0; k <= 500; ++k) {
    const BlockedMonitor::Step s = m.Update(k * kDt, 0.01, 0.0, true);
    if (s.became_blocked) blocked_at = k;
    replans += s.replan;
    if (s.abort) abort_at = k;
  }
  EXPECT_EQ(blocked_at, 51);  // first sample past 5 s
  EXPECT_EQ(replans, 5);      // at 10, 20, 30, 40, 50 s
  EXPECT_EQ(abort_at, 450);   // 45 s
  EXPECT_NEAR(m.time_blocked_s(), 50.0, 1e-9);
  m.Update(50.1, 0.3, 0.0, true);
  EXPECT_FALSE(m.blocked());
  EXPECT_EQ(m.episodes(), 1);
  EXPECT_NEAR(m.longest_blocked_s(), 50.0, 1e-9);
}

// Turning on the spot is progress; so is a robot without a goal never blocked.
TEST(BlockedMonitorTest, TurningOrNoGoalIsNotBlocked) {
  BlockedMonitor m{BlockedMonitorOptions{}};
  for (int k = 0; k <= 200; ++k) {
    EXPECT_FALSE(m.Update(k * kDt, 0.0, 0.3, true).became_blocked);
    EXPECT_FALSE(m.Update(k * kDt, 0.0, 0.0, false).became_blocked);
  }
  EXPECT_EQ(m.episodes(), 0);
  EXPECT_EQ(m.time_blocked_s(), 0.0);
}

// Turning left and right in place, each faster than 0.05 rad/s but with no
// net turn, is not progress: blocked after 5 s as if standing. Turning
// steadily either way, or drifting round at 0.06 rad/s net, is.
TEST(BlockedMonitorTest, ADitherInPlaceIsBlocked) {
  BlockedMonitor dither{BlockedMonitorOptions{}};
  int blocked_at = -1;
  for (int k = 0; k <= 100; ++k) {
    const double rate = k % 2 == 0 ? 0.3 : -0.3;
    if (dither.Update(k * kDt, 0.005, rate, true).became_blocked && blocked_at < 0) blocked_at = k;
  }
  EXPECT_GE(blocked_at, 50);
  EXPECT_LE(blocked_at, 53);
  for (const double net : {0.06, -0.06, -0.3}) {
    BlockedMonitor turning{BlockedMonitorOptions{}};
    for (int k = 0; k <= 200; ++k) {
      const double rate = net + (k % 2 == 0 ? 0.2 : -0.2);
      EXPECT_FALSE(turning.Update(k * kDt, 0.0, rate, true).became_blocked) << net << " " << k;
    }
  }
}

// A pause shorter than 5 s is not an episode.
TEST(BlockedMonitorTest, ShortStopIsNotBlocked) {
  BlockedMonitor m{BlockedMonitorOptions{}};
  for (int k = 0; k < 45; ++k) m.Update(k * kDt, 0.0, 0.0, true);
  m.Update(4.5, 0.5, 0.0, true);
  EXPECT_EQ(m.episodes(), 0);
}

}  // namespace
}  // namespace pavilion::nav
