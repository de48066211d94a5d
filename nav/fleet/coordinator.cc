#include "nav/fleet/coordinator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace pavilion::nav {
namespace {

void Require(bool ok, const std::string& field, const std::string& range) {
  if (!ok) throw std::invalid_argument("FleetOptions." + field + " must be " + range);
}

// The encoding's field sizes (bytes).
constexpr std::int64_t kRobotIndexBytes = 2;
constexpr std::int64_t kCountBytes = 2;
constexpr std::int64_t kNodeBytes = 2;
constexpr std::int64_t kWeightBytes = 4;
constexpr std::int64_t kPoseFlagBytes = 1;
constexpr std::int64_t kPoseBytes = 6 * 4;    // x, y, theta, speed, turn rate, sigma
constexpr std::int64_t kAlsoAtBytes = 3 * 4;  // x, y, theta
constexpr std::int64_t kStationBytes = 2;
constexpr std::int64_t kVertexBytes = 2 * 4;

bool SameMessage(const FleetMessage& a, const FleetMessage& b) {
  if (a.reserved_station != b.reserved_station || a.occupied_station != b.occupied_station ||
      a.pose.has_value() != b.pose.has_value() || a.lost != b.lost ||
      a.also_at.has_value() != b.also_at.has_value() || a.path.size() != b.path.size() ||
      a.claims != b.claims) {
    return false;
  }
  if (a.pose && (a.pose->x_m != b.pose->x_m || a.pose->y_m != b.pose->y_m ||
                 a.pose->theta_rad != b.pose->theta_rad || a.speed_mps != b.speed_mps ||
                 a.turn_rate_radps != b.turn_rate_radps)) {
    return false;
  }
  if (a.also_at && (a.also_at->x_m != b.also_at->x_m || a.also_at->y_m != b.also_at->y_m ||
                    a.also_at->theta_rad != b.also_at->theta_rad)) {
    return false;
  }
  for (std::size_t i = 0; i < a.path.size(); ++i) {
    if (a.path[i].node != b.path[i].node || a.path[i].weight != b.path[i].weight) return false;
  }
  return true;
}

}  // namespace

void FleetOptions::Validate() const {
  Require(peak_weight_m > 0.0 && peak_weight_m <= 1e4, "peak_weight_m", "in (0, 1e4] m");
  Require(falloff_m > 0.0 && falloff_m <= 1000.0, "falloff_m", "in (0, 1000] m");
  Require(horizon_m > 0.0 && horizon_m <= 1000.0, "horizon_m", "in (0, 1000] m");
  Require(occupied_station_cost_m >= 0.0 && occupied_station_cost_m <= 1e6,
          "occupied_station_cost_m", "in [0, 1e6] m");
  Require(release_distance_m >= 0.0 && release_distance_m <= 10.0, "release_distance_m",
          "in [0, 10] m");
  Require(claim_ahead_m >= 0.0 && claim_ahead_m <= 20.0, "claim_ahead_m", "in [0, 20] m");
  Require(claim_radius_m > 0.0 && claim_radius_m <= 10.0, "claim_radius_m", "in (0, 10] m");
}

std::int64_t EncodedBytes(const FleetMessage& message) {
  return kRobotIndexBytes + kCountBytes +
         static_cast<std::int64_t>(message.path.size()) * (kNodeBytes + kWeightBytes) +
         kPoseFlagBytes + (message.pose ? kPoseBytes : 0) + (message.also_at ? kAlsoAtBytes : 0) +
         2 * kStationBytes + kCountBytes +
         static_cast<std::int64_t>(message.claims.size()) * kNodeBytes;
}

void FleetBoard::AddOthersCosts(int self, double occupied_cost_m,
                                std::vector<double>* costs) const {
  const auto n = static_cast<int>(costs->size());
  for (int r = 0; r < robots(); ++r) {
    if (r == self) continue;
    const FleetMessage& m = messages_[static_cast<std::size_t>(r)];
    for (const PathWeight& w : m.path) {
      if (w.node >= 0 && w.node < n) (*costs)[static_cast<std::size_t>(w.node)] += w.weight;
    }
    for (int station : {m.reserved_station, m.occupied_station}) {
      if (station >= 0 && station < n) {
        (*costs)[static_cast<std::size_t>(station)] += occupied_cost_m;
      }
    }
  }
}

bool FleetBoard::StationTaken(int node, int self) const {
  for (int r = 0; r < robots(); ++r) {
    if (r == self) continue;
    const FleetMessage& m = messages_[static_cast<std::size_t>(r)];
    if (m.reserved_station == node || m.occupied_station == node) return true;
  }
  return false;
}

std::vector<Eigen::Vector2d> FleetBoard::TrustedPositions(int self) const {
  std::vector<Eigen::Vector2d> positions;
  for (int r = 0; r < robots(); ++r) {
    const FleetMessage& m = messages_[static_cast<std::size_t>(r)];
    if (r != self && m.pose && !m.lost) positions.push_back(m.pose->translation());
  }
  return positions;
}

bool FleetBoard::ReservationLost(int node, int self) const {
  for (int r = 0; r < robots(); ++r) {
    if (r == self) continue;
    const FleetMessage& m = messages_[static_cast<std::size_t>(r)];
    if (m.occupied_station == node || (m.reserved_station == node && r < self)) return true;
  }
  return false;
}

bool FleetBoard::ClaimedByOther(int node, int self) const {
  for (int r = 0; r < robots(); ++r) {
    const std::vector<int>& c = messages_[static_cast<std::size_t>(r)].claims;
    if (r != self && std::binary_search(c.begin(), c.end(), node)) return true;
  }
  return false;
}

std::vector<int> FleetBoard::ResolveClaims(int self, std::span<const int> wanted,
                                           std::span<const int> held, int occupied) const {
  std::vector<int> claims;
  for (int node : wanted) {
    bool keep = true;
    if (node != occupied) {
      const bool was_held = std::binary_search(held.begin(), held.end(), node);
      for (int r = 0; r < robots() && keep; ++r) {
        const std::vector<int>& c = messages_[static_cast<std::size_t>(r)].claims;
        if (r == self || !std::binary_search(c.begin(), c.end(), node)) continue;
        keep = was_held && self < r;  // a same-cycle claim: the first in robot order
      }
    }
    if (keep) claims.push_back(node);
  }
  if (occupied >= 0 && !std::binary_search(claims.begin(), claims.end(), occupied)) {
    claims.insert(std::lower_bound(claims.begin(), claims.end(), occupied), occupied);
  }
  return claims;
}

FleetCoordinator::FleetCoordinator(int robots, const FleetOptions& options)
    : options_(options),
      board_(robots),
      outbox_(static_cast<std::size_t>(robots)),
      bytes_up_(static_cast<std::size_t>(robots), 0),
      bytes_down_(static_cast<std::size_t>(robots), 0),
      messages_(static_cast<std::size_t>(robots), 0) {
  if (robots < 1) throw std::invalid_argument("FleetCoordinator needs at least one robot");
  options_.Validate();
}

void FleetCoordinator::Join(int robot, std::vector<Eigen::Vector2d> footprint) {
  const auto r = static_cast<std::size_t>(robot);
  const auto bytes = static_cast<std::int64_t>(footprint.size()) * kVertexBytes;
  bytes_up_.at(r) += bytes;
  for (std::size_t o = 0; o < bytes_down_.size(); ++o) {
    if (o != r) bytes_down_[o] += bytes;
  }
  board_.footprints_.at(r) = std::move(footprint);
}

void FleetCoordinator::Send(int robot, FleetMessage message) {
  outbox_.at(static_cast<std::size_t>(robot)) = std::move(message);
}

void FleetCoordinator::Merge() {
  ++merges_;
  for (std::size_t r = 0; r < outbox_.size(); ++r) {
    if (!outbox_[r]) continue;
    const std::int64_t bytes = EncodedBytes(*outbox_[r]);
    bytes_up_[r] += bytes;
    ++messages_[r];
    // The server forwards a message to the others only when it changed.
    if (!SameMessage(*outbox_[r], board_.messages_[r])) {
      for (std::size_t o = 0; o < outbox_.size(); ++o) {
        if (o != r) bytes_down_[o] += bytes;
      }
    }
    board_.messages_[r] = std::move(*outbox_[r]);
    outbox_[r].reset();
  }
}

std::vector<PathWeight> PlanWeights(const Eigen::Vector2d& position, std::span<const int> nodes,
                                    std::span<const Eigen::Vector2d> positions,
                                    const FleetOptions& options) {
  std::vector<PathWeight> weights;
  double along_m = 0.0;
  Eigen::Vector2d from = position;
  for (std::size_t i = 0; i < nodes.size() && i < positions.size(); ++i) {
    along_m += (positions[i] - from).norm();
    from = positions[i];
    if (along_m > options.horizon_m) break;
    weights.push_back({nodes[i], options.peak_weight_m * std::exp(-along_m / options.falloff_m)});
  }
  return weights;
}

}  // namespace pavilion::nav
