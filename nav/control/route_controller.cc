#include "nav/control/route_controller.h"

#include <stdexcept>
#include <string>
#include <utility>

namespace pavilion::nav {
namespace {
// Tick times are compared with the start time up to this rounding (s).
constexpr double kDueToleranceS = 1e-9;
}  // namespace

void RouteControllerOptions::Validate() const {
  follower.Validate();
  odometry.Validate();
  const auto require = [](bool ok, const std::string& field, const std::string& expected) {
    if (!ok)
      throw std::invalid_argument("RouteControllerOptions." + field + " must be " + expected);
  };
  require(start_s >= 0.0, "start_s", ">= 0");
  require(period_ticks >= 1, "period_ticks", ">= 1");
  require(step_s > 0.0, "step_s", "> 0");
}

RouteController::RouteController(std::vector<Eigen::Vector2d> path,
                                 const RouteControllerOptions& options)
    : options_(options), follower_(std::move(path), options.follower) {
  options_.Validate();
  status_.path_length_m = follower_.length_m();
}

std::optional<WheelSpeeds> RouteController::OnTick(const ControlTick& tick) {
  if (status_.done || tick.now_s + kDueToleranceS < options_.start_s ||
      tick.tick % options_.period_ticks != 0) {
    return std::nullopt;
  }
  const double period_s = static_cast<double>(options_.period_ticks) * options_.step_s;
  const VelocityCommand command = follower_.Update(tick.belief, period_s);
  const core::EncoderOdometryOptions& o = options_.odometry;
  const WheelSpeeds wheels =
      ToWheelSpeeds(command, o.left_wheel_radius_m, o.right_wheel_radius_m, o.wheelbase_m);
  if (follower_.done()) {
    status_.done = true;
    status_.done_at_s = tick.now_s;
  }
  return wheels;
}

}  // namespace pavilion::nav
