#pragma once

// Multi-robot planning of thesis §6.3.5 as the central server of Expo.02
// (§6.5: "a central server for multi-robot planning"):
//
// - Path coordination, a topological potential field: each robot publishes
//   (i, w_i) for the nodes i of its current plan, the weights falling with the
//   distance along the plan from the robot; the planner of every robot plans
//   on the superposed weights of the others, so it picks nodes "currently
//   unused by other robots".
// - Goal coordination: a robot proposes its next station among the
//   unoccupied ones of its tour not yet visited, and the chosen one is
//   reserved for it; the station it stands at stays occupied until it has
//   left it.
// - Station passage (ours: the acceptance's "never two robots within 1 m of
//   the same station node at once" holds for robots passing through a
//   station as much as for the one visiting it): a robot claims the stations
//   of its tour that its plan reaches within claim_ahead_m (up to the first
//   one another robot holds: it waits there and claims nothing beyond), those
//   whose ring it stands in, and the one it occupies; a claim is held while
//   it drives within claim_radius_m. A station is one robot's at
//   a time: a claim another robot already holds on the board is not made; two claims made in the
//   same cycle go to the robot first in robot order. The others keep out of a claimed station (the
//   controller's rings).
// - Robot positions: each robot's believed pose, so that the others' dynamic
//   windows see its true hull where their lasers see a recessed body
//   (§6.3.5.1; the markers are the fall-back when coordination is down).
//
// Time and determinism (architecture.md): a robot writes only its own
// outbox while it is controlled; Merge() — called once per tick after the
// tick's parallel phase — copies the outboxes into the board in robot order,
// and everybody reads the board during the next tick. The board is therefore
// the same for any thread count. Messages are counted in the bytes of a
// compact encoding (a node index and a weight: "a matter of a few bytes").

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/types/pose2.h"

namespace pavilion::nav {

// One element (i, w_i) of a robot's path message (§6.3.5).
struct PathWeight {
  int node = 0;         // node index of the shared map
  double weight = 0.0;  // cost the others add to the node, m of path, >= 0
};

struct FleetOptions {
  // Weight of the node the robot stands at or heads for first, m of path
  // (0, 1e4]. Chosen: the length of a typical hall detour (two or three
  // arcs of the expo_hall graph), so that a free alternative wins over a
  // shared node but a long way round does not.
  double peak_weight_m = 8.0;
  // The weights fall as exp(-d / falloff_m) with the distance d along the
  // plan, m, (0, 1000]. Chosen: nodes further than ~3 falloffs ahead (the
  // robot needs ~40 s to get there) hardly count.
  double falloff_m = 4.0;
  // Nodes further along the plan than this are not published, m, (0, 1000].
  double horizon_m = 12.0;
  // A station another robot reserved or occupies costs this much to enter, m
  // of path, [0, 1e6]: the planner passes through it only without a way round.
  double occupied_station_cost_m = 200.0;
  // A station stays occupied until its robot is this far from it, m, [0, 10].
  // Chosen: the acceptance's 1 m around a station node plus half a Robox.
  double release_distance_m = 1.5;
  // A station the plan reaches within this distance (along the plan) is
  // claimed for passage, m, [0, 20]. Chosen: a Robox at 0.6 m/s brakes in
  // 0.2 m; this leaves the one that loses a claim ~1 m to stop outside the
  // station's 1 m, with a cycle of latency and the ring's margin.
  double claim_ahead_m = 2.5;
  // A claim is held while the robot drives within this distance of the
  // node, m, (0, 10] (a robot also claims a station whose ring it stands in).
  // Chosen: claim_ahead_m, so that a passer whose plan has moved on beyond
  // the node (2 m before it) keeps the claim it made. Not while dwelling:
  // station_06 and station_12 of expo_hall are 1.25 m apart, and a robot
  // dwelling at one held the other while the robots waiting for that one
  // blocked its way out (an hour-long run jammed four robots there).
  double claim_radius_m = 2.5;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// What one robot sends (its outbox), once per dynamic-window cycle.
struct FleetMessage {
  std::vector<PathWeight> path;     // its plan's nodes with weights, robot first
  std::optional<core::Pose2> pose;  // its believed pose (also while lost)
  double speed_mps = 0.0;           // its commanded forward speed (with the pose)
  int reserved_station = -1;        // node index of the station it heads for, -1: none
  int occupied_station = -1;        // the station it stands at or is leaving, -1: none
  std::vector<int> claims;          // the stations it holds for passage, ascending
  bool lost = false;                // it declared itself lost: `pose` may be wrong
  double turn_rate_radps = 0.0;     // its commanded turn rate (with the pose)
  // 1 sigma of where its outline is (with the pose): its position's plus its
  // circumradius times its heading's, m.
  double outline_sigma_m = 0.0;
  // Not localized with one hypothesis that is not `pose`: where that
  // hypothesis puts it. The others draw its hull at both poses.
  std::optional<core::Pose2> also_at = std::nullopt;
};

// Bytes of the compact encoding of a message (a 2-byte robot index; per path
// element a 2-byte node index and a 4-byte float weight, plus a 2-byte count;
// the pose, speed, turn rate and outline sigma as six 4-byte floats, a 1-byte flag that also holds
// `lost` and whether `also_at` follows, as three 4-byte floats; two 2-byte stations;
// the claims as a 2-byte count and 2 bytes each).
std::int64_t EncodedBytes(const FleetMessage& message);

// What every robot reads: the last merged messages of the fleet.
class FleetBoard {
 public:
  explicit FleetBoard(int robots)
      : messages_(static_cast<std::size_t>(robots)),
        footprints_(static_cast<std::size_t>(robots)) {}
  int robots() const { return static_cast<int>(messages_.size()); }
  const FleetMessage& message(int robot) const { return messages_.at(robot); }
  // The robot's outline (robot frame, convex), sent once when it joins.
  const std::vector<Eigen::Vector2d>& footprint(int robot) const { return footprints_.at(robot); }

  // Adds the weights of every robot but `self` to `costs` (one per node;
  // nodes beyond its size are ignored), and occupied_cost_m to every station
  // another robot reserved or occupies.
  void AddOthersCosts(int self, double occupied_cost_m, std::vector<double>* costs) const;
  // True when a robot other than `self` reserved or occupies station `node`.
  bool StationTaken(int node, int self) const;
  // True when `self`'s reservation of `node` loses to another robot's: one
  // that occupies it, or reserved it too and comes first in robot order (two
  // robots that chose in the same cycle; the rule every robot applies alike).
  bool ReservationLost(int node, int self) const;
  // The claims `self` holds after this cycle (ascending), from the stations
  // it wants (`wanted`, ascending) and those it held as of its last message
  // (`held`, ascending): a wanted station no other robot claims on the board
  // is claimed; one another robot claims is kept only when `self` held it
  // too (both claimed in the same cycle) and comes first in robot order.
  // `occupied` (-1: none) is always kept: the robot stands there.
  std::vector<int> ResolveClaims(int self, std::span<const int> wanted, std::span<const int> held,
                                 int occupied) const;
  // True when a robot other than `self` claims station `node`.
  bool ClaimedByOther(int node, int self) const;
  // Where the robots other than `self` are, for explaining the markers
  // `self` sees (world frame): those that send a pose and are not lost. A
  // lost robot's pose may be wrong by decimetres (an hour-long expo_tours run:
  // 0.2-0.5 m within seconds of the loss), and a marker "explained" by it
  // would drop the contour at its true place for a hull at the wrong one.
  std::vector<Eigen::Vector2d> TrustedPositions(int self) const;

 private:
  friend class FleetCoordinator;
  std::vector<FleetMessage> messages_;
  std::vector<std::vector<Eigen::Vector2d>> footprints_;
};

class FleetCoordinator {
 public:
  FleetCoordinator(int robots, const FleetOptions& options);

  const FleetOptions& options() const { return options_; }
  int robots() const { return board_.robots(); }

  // A robot joins with its outline (robot frame, convex, counter-clockwise);
  // counted as 8 bytes per vertex sent once to each of the others.
  void Join(int robot, std::vector<Eigen::Vector2d> footprint);

  // The stations the fleet shares (node ids), claimed for passage; empty:
  // each robot claims the stations of its own missions.
  void SetStations(std::vector<std::string> ids) { stations_ = std::move(ids); }
  const std::vector<std::string>& stations() const { return stations_; }

  // The board as of the last Merge(): read by every robot during a tick.
  const FleetBoard& board() const { return board_; }
  // Robot `robot`'s outbox: written only by that robot, at most once per tick
  // (a later write in the tick replaces the earlier one).
  void Send(int robot, FleetMessage message);

  // Publishes the tick's outboxes in robot order (end of the tick).
  void Merge();

  // Bytes robot `robot` sent, and that the server sent back (the board's
  // changed messages, to each of the others), since the start.
  std::int64_t bytes_up(int robot) const { return bytes_up_.at(robot); }
  std::int64_t bytes_down(int robot) const { return bytes_down_.at(robot); }
  std::int64_t messages(int robot) const { return messages_.at(robot); }
  std::int64_t merges() const { return merges_; }

 private:
  FleetOptions options_;
  FleetBoard board_;
  std::vector<std::optional<FleetMessage>> outbox_;
  std::vector<std::int64_t> bytes_up_;
  std::vector<std::int64_t> bytes_down_;
  std::vector<std::int64_t> messages_;
  std::int64_t merges_ = 0;
  std::vector<std::string> stations_;
};

// The weights a robot publishes for its plan (§6.3.5): `plan` the remaining
// nodes (positions in the map frame, node indices alongside), `position` the
// robot's; the distance to a node is the robot's straight leg to the plan's
// first node plus the plan's arcs up to it.
std::vector<PathWeight> PlanWeights(const Eigen::Vector2d& position, std::span<const int> nodes,
                                    std::span<const Eigen::Vector2d> positions,
                                    const FleetOptions& options);

// A robot's link to the coordinator: its index among the fleet.
struct FleetLink {
  FleetCoordinator* coordinator = nullptr;
  int robot = 0;
};

}  // namespace pavilion::nav
