#include "nav/mission/mission_sequence.h"

#include <gtest/gtest.h>

#include <map>
#include <set>

namespace pavilion::nav {
namespace {

// A list gives its stations once, in order.
TEST(MissionSequenceTest, ListInOrder) {
  MissionSequence s = MissionSequence::List({"a", "b", "a"});
  EXPECT_EQ(s.Next(), "a");
  EXPECT_EQ(s.Next(), "b");
  EXPECT_EQ(s.Next(), "a");
  EXPECT_EQ(s.Next(), std::nullopt);
}

// A tour visits n of the candidates, each once per round; repeated rounds
// never give the same station twice in a row; the same seed gives the same tour.
TEST(MissionSequenceTest, TourRoundsFromTheSeed) {
  const std::vector<std::string> among = {"s1", "s2", "s3", "s4", "s5", "s6"};
  MissionSequence s = MissionSequence::Tour(among, 4, true, core::RandomStream(7, 1));
  MissionSequence t = MissionSequence::Tour(among, 4, true, core::RandomStream(7, 1));
  std::string last;
  std::map<std::string, int> visits;
  for (int round = 0; round < 300; ++round) {
    std::set<std::string> in_round;
    for (int k = 0; k < 4; ++k) {
      const std::optional<std::string> g = s.Next();
      ASSERT_TRUE(g);
      EXPECT_EQ(g, t.Next());
      EXPECT_TRUE(in_round.insert(*g).second) << "twice in one round";
      EXPECT_NE(*g, last);
      last = *g;
      ++visits[*g];
    }
  }
  // Every candidate drawn about 4/6 of the rounds (binomial, 300 rounds: sd ~8).
  for (const std::string& a : among) EXPECT_NEAR(visits[a], 200, 40) << a;
}

// Without repeat a tour ends after its round.
TEST(MissionSequenceTest, TourWithoutRepeatEnds) {
  MissionSequence s = MissionSequence::Tour({"a", "b", "c"}, 3, false, core::RandomStream(1, 2));
  std::set<std::string> seen;
  for (int k = 0; k < 3; ++k) seen.insert(*s.Next());
  EXPECT_EQ(seen.size(), 3u);
  EXPECT_EQ(s.Next(), std::nullopt);
}

}  // namespace
}  // namespace pavilion::nav
