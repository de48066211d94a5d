#include "nav/stack/navigator.h"

#include <stdexcept>
#include <utility>

namespace pavilion::nav {

Navigator::Navigator(const NavigatorOptions& options, std::unique_ptr<PoseEstimator> estimator,
                     std::unique_ptr<Controller> controller)
    : odometry_(options.odometry, options.start_pose),
      estimator_(std::move(estimator)),
      controller_(std::move(controller)),
      collision_refractory_s_(options.collision_refractory_s) {
  if (!(options.collision_refractory_s >= 0.0)) {
    throw std::invalid_argument("NavigatorOptions.collision_refractory_s must be >= 0");
  }
}

std::optional<WheelSpeeds> Navigator::Control(std::int64_t tick, double now_s) {
  if (!controller_) return std::nullopt;
  const ControlTick control{tick, now_s, belief(), odometry_.pose(), not_localized()};
  std::optional<WheelSpeeds> command = controller_->OnTick(control);
  if (estimator_) estimator_->SetPaused(controller_->localization_paused(), now_s);
  return command;
}

SenseResult Navigator::Sense(const SensorFrame& frame) {
  SenseResult result;
  for (const core::EncoderReading& reading : frame.encoders) odometry_.Update(reading);
  // A zone pressed anew, and the release after a press: a collision moves the
  // robot in ways its odometry does not see, for as long as it lasts. One
  // collision's noise per refractory period, however often the zones flicker.
  for (const core::BumperReading& b : frame.bumpers) {
    const bool pressed_anew = (b.zones_in_contact & ~bumper_zones_) != 0;
    const bool released = b.zones_in_contact == 0 && bumper_zones_ != 0;
    if ((pressed_anew || released) && estimator_ &&
        b.stamp_s - last_collision_noise_s_ >= collision_refractory_s_) {
      estimator_->OnCollision();
      last_collision_noise_s_ = b.stamp_s;
    }
    bumper_zones_ = b.zones_in_contact;
  }
  if (controller_ && !frame.bumpers.empty()) {
    const ScanContext context{frame.now_s, belief(), odometry_.pose()};
    for (const core::BumperReading& b : frame.bumpers) controller_->OnBumper(b, context);
  }
  if (estimator_) {
    if (!frame.images.empty()) estimator_->AddImages(frame.images);
    result.cycle = estimator_->Update(frame.encoders, frame.scans);
  }
  if (shadow_) result.shadow_cycle = shadow_->Update(frame.encoders, frame.scans);
  if (controller_) {
    const ScanContext context{frame.now_s, belief(), odometry_.pose()};
    for (const core::LaserScan* scan : frame.scans) {
      if (auto command = controller_->OnScan(*scan, context)) result.command = command;
    }
  }
  return result;
}

core::Pose2 Navigator::belief() const {
  return estimator_ ? estimator_->estimate().pose : odometry_.pose();
}

}  // namespace pavilion::nav
