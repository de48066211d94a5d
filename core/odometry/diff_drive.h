#pragma once

#include "core/types/pose2.h"

namespace pavilion::core {

// Wheel travels of one odometry step (thesis eq. 2.5): the arc lengths the
// left and right wheel contact points covered, in metres.
struct WheelTravel {
  double left_m = 0.0;
  double right_m = 0.0;
};

// The differential-drive kinematic model f(x, u) of thesis eqs. 2.6–2.8: the
// pose after driving `travel` from `pose` with wheelbase `wheelbase_m`,
// integrating along the chord at the mean heading θ + Δθ/2.
Pose2 DiffDriveStep(const Pose2& pose, const WheelTravel& travel, double wheelbase_m);

}  // namespace pavilion::core
