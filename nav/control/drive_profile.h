#pragma once

// A scripted wheel-speed profile: each step's speeds are held from its time
// until the next step's (the scenarios' `drive:` block).

#include <cstddef>
#include <vector>

#include "nav/control/controller.h"

namespace pavilion::nav {

struct DriveStep {
  double at_s = 0.0;        // held from this time (s), >= 0
  double left_radps = 0.0;  // wheel speeds, rad/s, positive forward
  double right_radps = 0.0;
};

class DriveProfileController : public Controller {
 public:
  // `steps` sorted by time.
  explicit DriveProfileController(std::vector<DriveStep> steps);
  // The last step due by `tick.now_s` that was not yet applied, if any.
  std::optional<WheelSpeeds> OnTick(const ControlTick& tick) override;

 private:
  std::vector<DriveStep> steps_;
  std::size_t next_ = 0;
};

}  // namespace pavilion::nav
