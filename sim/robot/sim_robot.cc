#include "sim/robot/sim_robot.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "sim/runtime/schedule.h"

namespace pavilion::sim {
namespace {

core::RandomStream StreamFor(std::uint64_t seed, const std::string& robot,
                             const std::string& sensor) {
  return core::RandomStream(seed, core::RandomStream::StreamId((robot + "/" + sensor).c_str()));
}

}  // namespace

SimRobot::SimRobot(World* world, SimRobotSetup setup, std::uint64_t seed)
    : world_(world),
      setup_(std::move(setup)),
      encoders_(setup_.encoders, setup_.spec.model.left_wheel.radius_m,
                setup_.spec.model.right_wheel.radius_m,
                StreamFor(seed, setup_.spec.id, "encoders")) {
  const double physics_hz = 1.0 / world->step_s();
  const std::string& id = setup_.spec.id;
  if (setup_.encoders.rate_hz > physics_hz) {
    // Encoders faster than the physics (the thesis' 200 Hz odometry over
    // 100 Hz physics) read several times a tick, at wheel angles interpolated
    // within it; the rate must then be a whole multiple of the physics rate.
    const double ratio = setup_.encoders.rate_hz / physics_hz;
    if (std::abs(ratio - std::round(ratio)) > 1e-9 * ratio) {
      throw std::invalid_argument(
          id + " encoders: rate " + std::to_string(setup_.encoders.rate_hz) +
          " Hz is neither a divisor nor a whole multiple of the physics rate " +
          std::to_string(physics_hz) + " Hz");
    }
    encoder_readings_per_tick_ = static_cast<int>(std::round(ratio));
  } else {
    encoder_period_ticks_ = PeriodTicks(physics_hz, setup_.encoders.rate_hz, id + " encoders");
  }
  bumper_period_ticks_ = PeriodTicks(physics_hz, setup_.bumper_rate_hz, id + " bumpers");
  std::set<std::string> ids;
  for (const LaserMountSetup& mount : setup_.lasers) {
    if (!ids.insert(mount.id).second) {
      throw std::invalid_argument("robot '" + id + "': two lasers named '" + mount.id + "'");
    }
    lasers_.emplace_back(mount.id, mount.options, mount.robot_from_sensor, mount.mount_height_m,
                         StreamFor(seed, id, "laser/" + mount.id));
    next_sweep_s_.push_back(0.0);
    sweeping_.push_back(false);
    fell_back_.push_back(false);
  }
  index_ = world->AddRobot(setup_.spec);
}

void SimRobot::SetWheelSpeeds(double left_radps, double right_radps) {
  world_->SetWheelSpeeds(index_, left_radps, right_radps);
}

void SimRobot::UsePlanarCaster(PlanarCaster* caster) {
  planar_ = caster;
  if (planar_ == nullptr) return;
  // Every slice this robot needs exists before the first tick, so that SliceAt
  // never builds one while robots cast from several threads.
  for (const LaserScanner& laser : lasers_) planar_->SliceAt(laser.mount_height_m());
}

SensorOutputs SimRobot::AfterStep(const RobotState& before, const RobotState& after) {
  const World& world = *world_;
  SensorOutputs out;
  const std::int64_t tick = world.tick();
  const double t1 = world.time_s();
  const double t0 = t1 - world.step_s();
  if (tick % encoder_period_ticks_ == 0) {
    const int n = encoder_readings_per_tick_;
    for (int k = 1; k < n; ++k) {
      const double f = static_cast<double>(k) / n;
      out.encoders.push_back(encoders_.Read(
          t0 + f * (t1 - t0),
          before.left_wheel_rad + f * (after.left_wheel_rad - before.left_wheel_rad),
          before.right_wheel_rad + f * (after.right_wheel_rad - before.right_wheel_rad)));
    }
    out.encoders.push_back(encoders_.Read(t1, after.left_wheel_rad, after.right_wheel_rad));
  }
  if (!setup_.bumpers.empty() && tick % bumper_period_ticks_ == 0) {
    const std::uint32_t pressed =
        PressedBumperZones(setup_.bumpers, world.RobotContactPoints(index_));
    if (pressed != pressed_) out.bumpers.push_back({t1, pressed});
    pressed_ = pressed;
  }
  const int group = world.robot_group(index_);
  const WorldHitFinder bullet(world);
  for (std::size_t k = 0; k < lasers_.size(); ++k) {
    LaserScanner& laser = lasers_[k];
    // Sweeps start every 1/scan_rate from t = 0; one may start inside the tick.
    if (!sweeping_[k] && next_sweep_s_[k] < t1) {
      laser.BeginSweep(next_sweep_s_[k]);
      sweeping_[k] = true;
      fell_back_[k] = false;
    }
    if (!sweeping_[k]) continue;
    const LaserHitFinder* finder = &bullet;
    if (planar_ != nullptr) {
      // Brings the slice to this tick (once per tick, and only in ticks with
      // readings to cast).
      const PlanarSlice& slice = planar_->SliceAt(laser.mount_height_m());
      const bool level =
          std::max(before.tilt_rad, after.tilt_rad) <= planar_->options().max_tilt_rad;
      // Every reading of the tick starts between the sensor's two positions.
      const Eigen::Vector2d from = (before.pose * laser.robot_from_sensor()).translation();
      const Eigen::Vector2d to = (after.pose * laser.robot_from_sensor()).translation();
      if (level && slice.Covers(to, laser.options().max_range_m + (to - from).norm(), group)) {
        finder = &slice;
      } else {
        fell_back_[k] = true;
      }
    }
    laser.Cast(*finder, t0, before.pose, t1, after.pose, group);
    if (laser.SweepComplete()) {
      out.scans.push_back({laser.scan(), laser.truth(), fell_back_[k]});
      sweeping_[k] = false;
      next_sweep_s_[k] += 1.0 / laser.options().scan_rate_hz;
    }
  }
  return out;
}

}  // namespace pavilion::sim
