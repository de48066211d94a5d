#pragma once

// The odometry buffer of on-the-fly localization (thesis §4.4.3): every
// odometry step is recorded with its time stamp, its input and the filter's
// estimate after it, so that an observation stamped T_A can be matched against
// the state predicted at T_A, and the estimate corrected at T_A can be carried
// forward to the present by forward simulation of the odometry model (eqs.
// 4.6, 4.7) with the recorded inputs.

#include <cstddef>
#include <deque>
#include <optional>

#include "core/odometry/diff_drive.h"
#include "core/types/pose2.h"

namespace pavilion::core {

// One recorded odometry step.
struct OdometryNode {
  double stamp_s = 0.0;
  WheelTravel travel;        // input u = [s_r, s_l] from the previous node (zero for the first)
  Pose2 odometry_pose;       // dead-reckoned pose, never corrected (relative motion, §4.4.4)
  PoseWithCovariance state;  // the filter's estimate at stamp_s
};

// A time-ordered buffer of odometry nodes spanning at least `span_s` seconds
// back from the latest (a ring buffer in the thesis; a deque here, since a
// node can be inserted where an observation's time stamp splits a step).
class OdometryBuffer {
 public:
  OdometryBuffer(double wheelbase_m, const WheelNoise& noise, double span_s);

  // Starts over with a single node.
  void Reset(double stamp_s, const PoseWithCovariance& state, const Pose2& odometry_pose);

  // Records one odometry step ending at `stamp_s` (>= latest_stamp_s(); throws
  // std::invalid_argument otherwise or when empty): the state prediction of
  // eqs. 4.6-4.7 (DiffDriveStepWithCovariance) and the dead-reckoned pose.
  // Nodes older than the span are dropped.
  void Append(double stamp_s, const WheelTravel& travel);

  bool empty() const { return nodes_.empty(); }
  std::size_t size() const { return nodes_.size(); }
  const OdometryNode& node(std::size_t i) const { return nodes_[i]; }
  const OdometryNode& latest() const { return nodes_.back(); }
  double oldest_stamp_s() const { return nodes_.front().stamp_s; }
  double latest_stamp_s() const { return nodes_.back().stamp_s; }

  // stamp_s in [oldest_stamp_s(), latest_stamp_s()].
  bool Covers(double stamp_s) const;

  // Makes a node sit exactly at `stamp_s` (Covers must hold; throws
  // std::out_of_range otherwise) and returns its index. A step (t0, t1]
  // containing it is split in two with the travel shared in proportion to
  // time, the first part's state predicted from the node at t0. So the
  // prediction used for matching has no time-stamp error (the thesis takes the
  // temporally closest buffered state, T_err <= dt/2, §4.4.3); the split
  // is consistent with the wheel-space model, whose U = diag(k|s|) is additive
  // in the travel (§2.3). Where several nodes carry the stamp, the latest.
  std::size_t SplitAt(double stamp_s);

  // Replaces the state of node `index` (e.g. by the EKF's posterior at that
  // time) and recomputes every later node's state from it with the recorded
  // inputs: the "forward simulation of the odometry model (4.6) and (4.7) from
  // T_l to t given the data in the buffer" of §4.4.3.
  void CorrectAt(std::size_t index, const PoseWithCovariance& corrected);

  // The linearized state transition from node `from` to node `to` (from <=
  // to < size()): the product of the steps' grad f_x (eq. 2.11), each taken
  // at the recorded state and input. Error propagation x_to = Phi x_from + w,
  // with w independent of anything before `from`.
  Eigen::Matrix3d Transition(std::size_t from, std::size_t to) const;

  // The dead-reckoned pose at `stamp_s`, interpolated within its step;
  // nullopt outside [oldest_stamp_s(), latest_stamp_s()].
  std::optional<Pose2> OdometryPoseAt(double stamp_s) const;

 private:
  // Index of the first node with stamp > stamp_s (nodes_.size() if none).
  std::size_t UpperBound(double stamp_s) const;

  double wheelbase_m_;
  WheelNoise noise_;
  double span_s_;
  std::deque<OdometryNode> nodes_;
};

}  // namespace pavilion::core
