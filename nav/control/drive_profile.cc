#include "nav/control/drive_profile.h"

#include <utility>

namespace pavilion::nav {
namespace {
// A step is due when its time is reached up to this rounding of tick times (s).
constexpr double kDueToleranceS = 1e-9;
}  // namespace

DriveProfileController::DriveProfileController(std::vector<DriveStep> steps)
    : steps_(std::move(steps)) {}

std::optional<WheelSpeeds> DriveProfileController::OnTick(const ControlTick& tick) {
  std::optional<WheelSpeeds> command;
  while (next_ < steps_.size() && steps_[next_].at_s <= tick.now_s + kDueToleranceS) {
    command = WheelSpeeds{steps_[next_].left_radps, steps_[next_].right_radps};
    ++next_;
  }
  return command;
}

}  // namespace pavilion::nav
