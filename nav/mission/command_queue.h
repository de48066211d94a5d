#pragma once

// The command queue of the execution layer (thesis §6.3.3): the global plan's
// nodes go to the behaviour layer one by one. Via nodes are reached inside a
// large disk around them (2 m) and are position-only goals; the last node must
// be met with its full pose. Near the last node (10 cm) localization pauses,
// because its corrections make the estimate too noisy for any position
// controller to settle on the goal.
//
// With the map's walls given (SetWalls), a via node counts as passed only
// when the robot also sees the node after it over those walls with room for
// its body: the straight line and its two parallels `clearance_m` to either
// side cross no wall (a square robot that heads for a door's far side from
// beside the door enters it askew and jams in it). 2 m from the
// via node in front of a door, the room's station behind the wall is out of
// sight; the local grid, which holds only what the lasers see now, would
// lead through the next room's door and a wall it has not seen yet, and the
// band would snap and replan in a loop (issue 14, office_errands' mail room).

#include <Eigen/Core>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/types/pose2.h"

namespace pavilion::nav {

struct CommandQueueOptions {
  double via_reached_radius_m = 2.0;  // §6.3.3 "a large disk around the node (2 m)", (0, 10]
  double localization_pause_radius_m = 0.1;  // §6.3.3 "10 cm in our implementation", [0, 1]
  // Localization resumes when the robot is pushed this many times the pause
  // radius away from the goal again (hysteresis), [1, 100].
  double resume_factor = 3.0;
  // The final pose is met within these (§6.5: goals were reached to about 1 cm).
  double goal_position_tolerance_m = 0.03;   // (0, 1]
  double goal_heading_tolerance_rad = 0.05;  // (0, pi]

  void Validate() const;  // throws std::invalid_argument naming the field
};

// A node of the plan handed to the behaviour layer.
struct QueuedNode {
  std::string id;
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();  // world frame
};

class CommandQueue {
 public:
  explicit CommandQueue(const CommandQueueOptions& options);

  // A new plan: its nodes in order, the last one the goal met with `goal_pose`
  // (its position replaces the last node's). Requires at least one node.
  void Load(std::vector<QueuedNode> nodes, const core::Pose2& goal_pose);
  void Clear();
  // The walls (endpoint pairs, world frame) a via node's successor must be
  // seen over, `clearance_m` (>= 0) to either side of the line, before the
  // via node counts as passed; none: the disk alone.
  void SetWalls(std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> walls,
                double clearance_m = 0.0) {
    walls_ = std::move(walls);
    sight_clearance_m_ = clearance_m;
  }

  // Advances past every via node whose disk holds the robot's belief (and
  // whose successor it sees, with walls set), and updates the localization
  // pause and arrival at the goal.
  void Update(const core::Pose2& belief);

  bool empty() const { return next_ >= nodes_.size(); }
  // The node the behaviour layer works towards; requires !empty().
  const QueuedNode& current() const { return nodes_[next_]; }
  // The current node is the last: the full pose must be met.
  bool at_goal_node() const { return !empty() && next_ + 1 == nodes_.size(); }
  const core::Pose2& goal_pose() const { return goal_pose_; }
  // The nodes still ahead, the current one first.
  std::span<const QueuedNode> remaining() const {
    return std::span<const QueuedNode>(nodes_).subspan(std::min(next_, nodes_.size()));
  }
  bool localization_paused() const { return paused_; }
  // The final pose is met within the tolerances (set by Update).
  bool arrived() const { return arrived_; }

 private:
  CommandQueueOptions options_;
  // The straight line from `from` to `to`, and its parallels
  // sight_clearance_m_ to either side, cross none of walls_.
  bool Sees(const Eigen::Vector2d& from, const Eigen::Vector2d& to) const;

  std::vector<QueuedNode> nodes_;
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> walls_;
  double sight_clearance_m_ = 0.0;
  std::size_t next_ = 0;
  core::Pose2 goal_pose_;
  bool paused_ = false;
  bool arrived_ = false;
};

}  // namespace pavilion::nav
