#include "nav/stack/navigator.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
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
  const core::Pose2& odometry = odometry_.pose();
  ControlTick control{tick, now_s, belief(), odometry, not_localized()};
  if (estimator_ && !control.localization_lost) {
    localized_at_ = Anchor{control.belief, odometry};
  } else if (localized_at_) {
    control.last_localized = localized_at_->belief * (localized_at_->odometry.Inverse() * odometry);
  }
  control.lone_hypothesis = estimator_ && estimator_->mode() == LocalizationMode::kNotLocalized &&
                            estimator_->hypothesis_count() == 1;
  if (estimator_) {
    const Eigen::Matrix3d& p = estimator_->estimate().covariance;
    const Eigen::Matrix2d position = p.topLeftCorner<2, 2>();
    const double major_m2 =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(position, Eigen::EigenvaluesOnly)
            .eigenvalues()
            .maxCoeff();
    control.position_sigma_m = std::sqrt(std::max(0.0, major_m2));
    control.heading_sigma_rad = std::sqrt(std::max(0.0, p(2, 2)));
  }
  std::optional<WheelSpeeds> command = controller_->OnTick(control);
  if (estimator_) estimator_->SetPaused(controller_->localization_paused(), now_s);
  return command;
}

SenseResult Navigator::Sense(const SensorFrame& frame) {
  SenseResult result;
  const double heading_before_rad = odometry_.pose().theta_rad;
  for (const core::EncoderReading& reading : frame.encoders) odometry_.Update(reading);
  const BumperContact contact = FeelBumpers(
      frame, std::abs(core::NormalizeAngle(odometry_.pose().theta_rad - heading_before_rad)));
  if (estimator_ && (contact.press || contact.held_s > 0.0 || contact.turned_rad > 0.0)) {
    estimator_->OnContact(contact);
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

BumperContact Navigator::FeelBumpers(const SensorFrame& frame, double turned_rad) {
  BumperContact contact;
  const auto hold_until = [&](double t) {
    if (bumper_zones_ != 0) contact.held_s += std::max(0.0, t - held_until_s_);
    held_until_s_ = std::max(held_until_s_, t);
  };
  for (const core::BumperReading& b : frame.bumpers) {
    hold_until(b.stamp_s);
    // A zone pressed anew: a collision, unless one counted within the
    // refractory period (the same bump flickering).
    if ((b.zones_in_contact & ~bumper_zones_) != 0 &&
        b.stamp_s - last_press_s_ >= collision_refractory_s_) {
      contact.press = true;
      last_press_s_ = b.stamp_s;
    }
    bumper_zones_ = b.zones_in_contact;
  }
  // Readings come only on a change: zones still pressed stay pressed to the
  // end of the tick.
  hold_until(frame.now_s);
  if (contact.press) collision_turn_rad_ = 0.0;
  if (contact.press || contact.held_s > 0.0 ||
      frame.now_s - last_press_s_ <= collision_refractory_s_) {
    contact.turned_before_rad = collision_turn_rad_;
    contact.turned_rad = turned_rad;
    collision_turn_rad_ += turned_rad;
  }
  return contact;
}

core::Pose2 Navigator::belief() const {
  return estimator_ ? estimator_->estimate().pose : odometry_.pose();
}

}  // namespace pavilion::nav
