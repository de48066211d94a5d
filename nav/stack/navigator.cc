#include "nav/stack/navigator.h"

#include <utility>

namespace pavilion::nav {

Navigator::Navigator(const NavigatorOptions& options, std::unique_ptr<PoseEstimator> estimator,
                     std::unique_ptr<Controller> controller)
    : odometry_(options.odometry, options.start_pose),
      estimator_(std::move(estimator)),
      controller_(std::move(controller)) {}

std::optional<WheelSpeeds> Navigator::Control(std::int64_t tick, double now_s) {
  if (!controller_) return std::nullopt;
  return controller_->OnTick(ControlTick{tick, now_s, belief()});
}

SenseResult Navigator::Sense(const SensorFrame& frame) {
  SenseResult result;
  for (const core::EncoderReading& reading : frame.encoders) odometry_.Update(reading);
  if (estimator_) result.cycle = estimator_->Update(frame.encoders, frame.scans);
  if (controller_) {
    for (const core::LaserScan* scan : frame.scans) {
      if (auto command = controller_->OnScan(*scan)) result.command = command;
    }
  }
  return result;
}

core::Pose2 Navigator::belief() const {
  return estimator_ ? estimator_->estimate().pose : odometry_.pose();
}

}  // namespace pavilion::nav
