#include "nav/mission/command_queue.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/geometry/segment2.h"

namespace pavilion::nav {
namespace {

void Require(bool ok, const std::string& field, const std::string& range) {
  if (!ok) throw std::invalid_argument("CommandQueueOptions." + field + " must be " + range);
}

}  // namespace

void CommandQueueOptions::Validate() const {
  Require(via_reached_radius_m > 0.0 && via_reached_radius_m <= 10.0, "via_reached_radius_m",
          "in (0, 10] m");
  Require(localization_pause_radius_m >= 0.0 && localization_pause_radius_m <= 1.0,
          "localization_pause_radius_m", "in [0, 1] m");
  Require(resume_factor >= 1.0 && resume_factor <= 100.0, "resume_factor", "in [1, 100]");
  Require(goal_position_tolerance_m > 0.0 && goal_position_tolerance_m <= 1.0,
          "goal_position_tolerance_m", "in (0, 1] m");
  Require(goal_heading_tolerance_rad > 0.0 && goal_heading_tolerance_rad <= std::numbers::pi,
          "goal_heading_tolerance_rad", "in (0, pi] rad");
}

CommandQueue::CommandQueue(const CommandQueueOptions& options) : options_(options) {
  options_.Validate();
}

void CommandQueue::Load(std::vector<QueuedNode> nodes, const core::Pose2& goal_pose) {
  if (nodes.empty()) throw std::invalid_argument("CommandQueue::Load needs at least one node");
  nodes_ = std::move(nodes);
  nodes_.back().position_m = goal_pose.translation();
  goal_pose_ = goal_pose;
  next_ = 0;
  paused_ = false;
  arrived_ = false;
}

bool CommandQueue::Sees(const Eigen::Vector2d& from, const Eigen::Vector2d& to) const {
  const Eigen::Vector2d d = to - from;
  Eigen::Vector2d side = Eigen::Vector2d::Zero();
  if (d.squaredNorm() > 0.0)
    side = Eigen::Vector2d(-d.y(), d.x()).normalized() * sight_clearance_m_;
  for (const double k : {0.0, 1.0, -1.0}) {
    if (k != 0.0 && sight_clearance_m_ == 0.0) break;
    for (const auto& [a, b] : walls_) {
      if (core::SegmentsCross(from + k * side, to + k * side, a, b)) return false;
    }
  }
  return true;
}

void CommandQueue::Clear() {
  nodes_.clear();
  next_ = 0;
  paused_ = false;
  arrived_ = false;
}

void CommandQueue::Update(const core::Pose2& belief) {
  if (empty()) return;
  const Eigen::Vector2d p = belief.translation();
  // Past the last via node whose disk holds the robot: a robot pushed on
  // beyond a node it never came near does not turn back for it.
  for (std::size_t k = nodes_.size() - 1; k-- > next_;) {
    if ((nodes_[k].position_m - p).norm() <= options_.via_reached_radius_m &&
        Sees(p, nodes_[k + 1].position_m)) {
      next_ = k + 1;
      break;
    }
  }
  if (!at_goal_node()) {
    paused_ = false;
    arrived_ = false;
    return;
  }
  const double distance_m = (goal_pose_.translation() - p).norm();
  if (distance_m <= options_.localization_pause_radius_m) {
    paused_ = true;
  } else if (distance_m > options_.resume_factor * options_.localization_pause_radius_m) {
    paused_ = false;
  }
  const double heading_error_rad =
      std::abs(core::NormalizeAngle(goal_pose_.theta_rad - belief.theta_rad));
  arrived_ = distance_m <= options_.goal_position_tolerance_m &&
             heading_error_rad <= options_.goal_heading_tolerance_rad;
}

}  // namespace pavilion::nav
