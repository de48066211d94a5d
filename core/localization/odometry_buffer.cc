#include "core/localization/odometry_buffer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pavilion::core {

OdometryBuffer::OdometryBuffer(double wheelbase_m, const WheelNoise& noise, double span_s)
    : wheelbase_m_(wheelbase_m), noise_(noise), span_s_(span_s) {
  if (!(std::isfinite(wheelbase_m) && wheelbase_m > 0.0)) {
    throw std::invalid_argument("OdometryBuffer: wheelbase_m must be > 0");
  }
  if (!(std::isfinite(span_s) && span_s >= 0.0)) {
    throw std::invalid_argument("OdometryBuffer: span_s must be >= 0");
  }
}

void OdometryBuffer::Reset(double stamp_s, const PoseWithCovariance& state,
                           const Pose2& odometry_pose) {
  nodes_.clear();
  nodes_.push_back({stamp_s, WheelTravel{}, odometry_pose, state});
}

void OdometryBuffer::Append(double stamp_s, const WheelTravel& travel) {
  if (nodes_.empty()) throw std::invalid_argument("OdometryBuffer::Append: buffer not reset");
  if (!(stamp_s >= nodes_.back().stamp_s)) {
    throw std::invalid_argument("OdometryBuffer::Append: stamp_s goes back in time");
  }
  const OdometryNode& last = nodes_.back();
  OdometryNode next;
  next.stamp_s = stamp_s;
  next.travel = travel;
  next.odometry_pose = DiffDriveStep(last.odometry_pose, travel, wheelbase_m_);
  next.state = DiffDriveStepWithCovariance(last.state, travel, wheelbase_m_, noise_);
  nodes_.push_back(next);
  while (nodes_.size() >= 2 && nodes_[1].stamp_s <= stamp_s - span_s_) nodes_.pop_front();
}

bool OdometryBuffer::Covers(double stamp_s) const {
  return !nodes_.empty() && stamp_s >= nodes_.front().stamp_s && stamp_s <= nodes_.back().stamp_s;
}

std::size_t OdometryBuffer::UpperBound(double stamp_s) const {
  return static_cast<std::size_t>(
      std::upper_bound(nodes_.begin(), nodes_.end(), stamp_s,
                       [](double t, const OdometryNode& n) { return t < n.stamp_s; }) -
      nodes_.begin());
}

std::size_t OdometryBuffer::SplitAt(double stamp_s) {
  if (!Covers(stamp_s)) throw std::out_of_range("OdometryBuffer::SplitAt: stamp outside buffer");
  const std::size_t after = UpperBound(stamp_s);  // >= 1 since stamp >= front
  const OdometryNode& before = nodes_[after - 1];
  if (before.stamp_s == stamp_s || after == nodes_.size()) return after - 1;
  OdometryNode& next = nodes_[after];
  const double f = (stamp_s - before.stamp_s) / (next.stamp_s - before.stamp_s);
  OdometryNode split;
  split.stamp_s = stamp_s;
  split.travel = {f * next.travel.left_m, f * next.travel.right_m};
  split.odometry_pose = DiffDriveStep(before.odometry_pose, split.travel, wheelbase_m_);
  split.state = DiffDriveStepWithCovariance(before.state, split.travel, wheelbase_m_, noise_);
  next.travel = {next.travel.left_m - split.travel.left_m,
                 next.travel.right_m - split.travel.right_m};
  nodes_.insert(nodes_.begin() + static_cast<std::ptrdiff_t>(after), split);
  return after;
}

void OdometryBuffer::CorrectAt(std::size_t index, const PoseWithCovariance& corrected) {
  if (index >= nodes_.size()) throw std::out_of_range("OdometryBuffer::CorrectAt: bad index");
  nodes_[index].state = corrected;
  for (std::size_t k = index + 1; k < nodes_.size(); ++k) {
    nodes_[k].state =
        DiffDriveStepWithCovariance(nodes_[k - 1].state, nodes_[k].travel, wheelbase_m_, noise_);
  }
}

Eigen::Matrix3d OdometryBuffer::Transition(std::size_t from, std::size_t to) const {
  if (from > to || to >= nodes_.size()) {
    throw std::out_of_range("OdometryBuffer::Transition: bad node range");
  }
  Eigen::Matrix3d phi = Eigen::Matrix3d::Identity();
  for (std::size_t k = from + 1; k <= to; ++k) {
    phi = DiffDriveStepJacobians(nodes_[k - 1].state.pose, nodes_[k].travel, wheelbase_m_)
              .J_next_pose *
          phi;
  }
  return phi;
}

std::optional<Pose2> OdometryBuffer::OdometryPoseAt(double stamp_s) const {
  if (!Covers(stamp_s)) return std::nullopt;
  const std::size_t after = UpperBound(stamp_s);
  const OdometryNode& before = nodes_[after - 1];
  if (before.stamp_s == stamp_s || after == nodes_.size()) return before.odometry_pose;
  const OdometryNode& next = nodes_[after];
  const double f = (stamp_s - before.stamp_s) / (next.stamp_s - before.stamp_s);
  return DiffDriveStep(before.odometry_pose, {f * next.travel.left_m, f * next.travel.right_m},
                       wheelbase_m_);
}

}  // namespace pavilion::core
