#include "nav/mission/mission_sequence.h"

#include <algorithm>
#include <utility>

namespace pavilion::nav {

MissionSequence MissionSequence::List(std::vector<std::string> stations) {
  MissionSequence s;
  s.among_ = stations;
  std::reverse(stations.begin(), stations.end());
  s.pending_ = std::move(stations);
  s.drawn_ = true;
  return s;
}

MissionSequence MissionSequence::Tour(std::vector<std::string> among, int per_round, bool repeat,
                                      core::RandomStream random) {
  MissionSequence s;
  s.among_ = std::move(among);
  s.per_round_ = per_round;
  s.repeat_ = repeat;
  s.random_.emplace(std::move(random));
  return s;
}

void MissionSequence::DrawRound() {
  // Fisher-Yates over the candidates; the first `per_round_` form the round.
  std::vector<std::string> order = among_;
  for (std::size_t i = 0; i + 1 < order.size(); ++i) {
    const auto j = static_cast<std::size_t>(random_->UniformInt(
        static_cast<std::int64_t>(i), static_cast<std::int64_t>(order.size()) - 1));
    std::swap(order[i], order[j]);
  }
  order.resize(static_cast<std::size_t>(per_round_));
  // A round does not start at the station the robot stands at.
  if (order.size() > 1 && order.front() == last_) std::swap(order.front(), order.back());
  std::reverse(order.begin(), order.end());
  pending_ = std::move(order);
  drawn_ = true;
}

std::optional<std::string> MissionSequence::Next() {
  if (pending_.empty() && random_ && (!drawn_ || repeat_) && per_round_ > 0) DrawRound();
  if (pending_.empty()) return std::nullopt;
  last_ = pending_.back();
  pending_.pop_back();
  return last_;
}

MissionSequence::Proposal MissionSequence::NextFree(
    const std::function<bool(const std::string&)>& taken, bool revisit) {
  if (pending_.empty() && random_ && (!drawn_ || repeat_) && per_round_ > 0) DrawRound();
  if (pending_.empty()) return {};
  if (!random_) {  // a fixed list: in order
    if (taken(pending_.back())) return {std::nullopt, true};
    return {Next(), false};
  }
  std::vector<std::size_t> free;
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    if (!taken(pending_[i])) free.push_back(i);
  }
  if (free.empty()) return revisit ? Revisit(taken) : Proposal{std::nullopt, true};
  const auto pick = free[static_cast<std::size_t>(
      random_->UniformInt(0, static_cast<std::int64_t>(free.size()) - 1))];
  last_ = pending_[pick];
  pending_.erase(pending_.begin() + static_cast<std::ptrdiff_t>(pick));
  return {last_, false};
}

MissionSequence::Proposal MissionSequence::Revisit(
    const std::function<bool(const std::string&)>& taken) {
  std::vector<const std::string*> free;
  for (const std::string& s : among_) {
    const bool ahead = std::find(pending_.begin(), pending_.end(), s) != pending_.end();
    if (!ahead && s != last_ && !taken(s)) free.push_back(&s);
  }
  if (free.empty()) return {std::nullopt, true};
  last_ = *free[static_cast<std::size_t>(
      random_->UniformInt(0, static_cast<std::int64_t>(free.size()) - 1))];
  return {last_, false, true};
}

void MissionSequence::GiveBack(const std::string& goal) { pending_.push_back(goal); }

}  // namespace pavilion::nav
