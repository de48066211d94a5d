#pragma once

// The goals a robot works through (issue 14's `mission:`): a fixed list of
// stations, or a tour of n stations drawn from the seed — each round visits n
// of the candidate stations once in a random order, rounds repeating when
// asked, and a round never starts where the last one ended.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/random/random_stream.h"

namespace pavilion::nav {

class MissionSequence {
 public:
  // The stations in this order, once.
  static MissionSequence List(std::vector<std::string> stations);
  // Rounds of `per_round` stations drawn from `among` (each once per round;
  // 1 <= per_round <= among.size(), checked by the caller's reader), forever
  // when `repeat`.
  static MissionSequence Tour(std::vector<std::string> among, int per_round, bool repeat,
                              core::RandomStream random);

  // The next goal, none when the sequence is done.
  std::optional<std::string> Next();

  // Goal coordination (thesis §6.3.5): the robot proposes the stations of the
  // round not yet visited that no other robot reserved or occupies (`taken`),
  // and the visitors choose one — a uniform draw from the sequence's stream.
  // A fixed list keeps its order and waits while its next station is taken.
  //
  // With `revisit`, a tour whose remaining stations are all taken proposes
  // instead a free station it already visited this round (not the one it just
  // left, none still ahead): the round keeps its remaining stations and gains
  // a stop. The caller asks so after waiting a while — robots each standing at
  // the station another one still has to visit would otherwise wait forever
  // (an hour-long expo_tours run ended with all ten in such a circle).
  struct Proposal {
    std::optional<std::string> goal;  // none: done, or wait (all remaining taken)
    bool wait = false;                // try again later: every remaining station is taken
    bool revisit = false;             // `goal` is a station visited before (not of the round)
  };
  Proposal NextFree(const std::function<bool(const std::string&)>& taken, bool revisit = false);
  // Every station the sequence can lead to (a list's, or a tour's candidates).
  const std::vector<std::string>& stations() const { return among_; }
  // Puts a proposed goal back among the round's remaining stations (another
  // robot reserved it in the same cycle and kept it); not for a revisit.
  void GiveBack(const std::string& goal);

 private:
  MissionSequence() = default;
  void DrawRound();
  Proposal Revisit(const std::function<bool(const std::string&)>& taken);

  std::vector<std::string> among_;
  int per_round_ = 0;
  bool repeat_ = false;
  std::optional<core::RandomStream> random_;
  std::vector<std::string> pending_;  // the current round, next goal last
  std::string last_;
  bool drawn_ = false;
};

}  // namespace pavilion::nav
