#include "sim/robot/sim_robot.h"

#include <algorithm>
#include <set>
#include <stdexcept>
#include <utility>

#include "sim/sensors/bumper_sensor.h"
#include "sim/sensors/camera_sensor.h"
#include "sim/sensors/encoder_sensor.h"
#include "sim/sensors/laser_sensor.h"

namespace pavilion::sim {
namespace {

core::RandomStream StreamFor(std::uint64_t seed, const std::string& robot,
                             const std::string& sensor) {
  return core::RandomStream(seed, core::RandomStream::StreamId((robot + "/" + sensor).c_str()));
}

}  // namespace

SimRobot::SimRobot(World* world, RobotConfig config, RobotPlacement placement, std::uint64_t seed)
    : world_(world),
      config_(std::move(config)),
      placement_(std::move(placement)),
      schedule_(1.0 / world->step_s()) {
  const double physics_hz = 1.0 / world->step_s();
  const std::string& id = placement_.id;
  const RobotDescription& model = config_.description;
  AddSensor(std::make_unique<EncoderSensor>(
      id, config_.encoders, model.left_wheel.radius_m, model.right_wheel.radius_m,
      StreamFor(seed, id, "encoders"), physics_hz, model.left_wheel.position_m,
      model.right_wheel.position_m));
  if (config_.bumpers.empty()) {
    // No zones, no readings: the rate is still checked.
    PeriodTicks(physics_hz, config_.bumper_rate_hz, id + " bumpers");
  } else {
    AddSensor(std::make_unique<BumperSensor>(config_.bumpers, config_.bumper_rate_hz));
  }
  std::set<std::string> ids;
  for (const LaserMount& mount : config_.lasers) {
    if (!ids.insert(mount.id).second) {
      throw std::invalid_argument("robot '" + id + "': two lasers named '" + mount.id + "'");
    }
    auto laser =
        std::make_unique<LaserSensor>(mount.id, mount.options, mount.robot_from_sensor, mount.z_m,
                                      StreamFor(seed, id, "laser/" + mount.id), physics_hz);
    lasers_.push_back(std::cref(laser->scanner()));
    mutable_lasers_.push_back(&laser->mutable_scanner());
    AddSensor(std::move(laser));
  }
  ids.clear();
  for (const CameraMount& mount : config_.cameras) {
    if (!ids.insert(mount.id).second) {
      throw std::invalid_argument("robot '" + id + "': two cameras named '" + mount.id + "'");
    }
    AddSensor(std::make_unique<CameraSensor>(mount, StreamFor(seed, id, "camera/" + mount.id),
                                             StreamFor(seed, id, "camera/" + mount.id + "/delay"),
                                             physics_hz));
  }
  index_ = world->AddRobot(model, config_.systematic, placement_);
}

void SimRobot::AddSensor(std::unique_ptr<Sensor> sensor) {
  for (const auto& s : sensors_) {
    if (s->id() == sensor->id()) {
      throw std::invalid_argument("robot '" + id() + "': two sensors named '" + sensor->id() + "'");
    }
  }
  // The task name is what a rate error names: "<robot> <sensor>".
  schedule_.Add(id() + " " + sensor->id(), sensor->sample_rate_hz());
  sensors_.push_back(std::move(sensor));
}

void SimRobot::SetWheelSpeeds(double left_radps, double right_radps) {
  command_radps_[0] = left_radps;
  command_radps_[1] = right_radps;
  CommandWorld();
}

// A wheel of true radius s r turning at w moves its floor contact at s r w.
// Both wheel models turn a wheel's rate into motion through the radius they
// built it with, r: the ray-cast drive's traction row drives the contact point
// at r times the commanded rate and a rolling wheel turns at v / r
// (raycast_drive.cc); the articulated reference's sphere of radius r rolls on
// the floor under its hinge motor. Rebuilding a Bullet wheel mid-run (its
// shape, the hinge's anchor) is not cheap, so, for both models alike, neither
// wheel is changed: the world turns the built wheel at s times the true wheel's
// commanded rate, which moves the floor exactly as the true wheel would, and
// the encoders count the built wheel's turns divided by s, the true wheel's
// turns for the same path (pushed with the motors off too: angle = path / radius).
// Not modelled: the lower stance of a smaller tyre (its axle s r above the
// floor); and the motors' limits act on the built wheel: the true wheel's
// speed limit is the model's for s <= 1 (the command is clamped first) and
// 1/s of it for s > 1, its acceleration limit 1/s of the model's (a wheel
// changed while at rest therefore ramps up slightly out of step with the
// other), and a torque's floor force is torque / r instead of torque / (s r).
void SimRobot::CommandWorld() {
  const double limit = config_.description.max_wheel_speed_radps;
  double simulated_radps[2];
  for (int side = 0; side < 2; ++side) {
    simulated_radps[side] =
        wheel_scale_[side].scale * std::clamp(command_radps_[side], -limit, limit);
  }
  world_->SetWheelSpeeds(index_, simulated_radps[0], simulated_radps[1]);
}

void SimRobot::SetWheelRadiusScale(int side, double scale) {
  if (side != 0 && side != 1) throw std::invalid_argument("wheel side must be 0 or 1");
  if (!(scale >= kMinWheelRadiusScale && scale <= kMaxWheelRadiusScale)) {
    throw std::invalid_argument("wheel radius scale must be in [0.5, 2]");
  }
  // The true wheel's angle goes on from where it is: a new breakpoint.
  const RobotState now = world_->robot_state(index_);
  const double simulated_rad = side == 0 ? now.left_wheel_rad : now.right_wheel_rad;
  WheelScale& w = wheel_scale_[side];
  w.true_at_rad = w.true_at_rad + (simulated_rad - w.simulated_at_rad) / w.scale;
  w.simulated_at_rad = simulated_rad;
  w.scale = scale;
  CommandWorld();
}

RobotState SimRobot::TrueWheels(RobotState s) const {
  const WheelScale& l = wheel_scale_[0];
  const WheelScale& r = wheel_scale_[1];
  s.left_wheel_rad = l.true_at_rad + (s.left_wheel_rad - l.simulated_at_rad) / l.scale;
  s.right_wheel_rad = r.true_at_rad + (s.right_wheel_rad - r.simulated_at_rad) / r.scale;
  s.left_wheel_radps /= l.scale;
  s.right_wheel_radps /= r.scale;
  return s;
}

bool SimRobot::SetLaserFault(const std::string& laser_id, const LaserFault& fault) {
  bool any = false;
  for (LaserScanner* laser : mutable_lasers_) {
    if (!laser_id.empty() && laser->id() != laser_id) continue;
    laser->SetFault(fault);
    any = true;
  }
  return any;
}

void SimRobot::UsePlanarCaster(PlanarCaster* caster) {
  planar_ = caster;
  if (planar_ == nullptr) return;
  // Every slice this robot needs exists before the first tick, so that SliceAt
  // never builds one while robots cast from several threads.
  for (const LaserScanner& laser : lasers_) planar_->SliceAt(laser.mount_height_m());
}

bool SimRobot::HeavyTick() const {
  const std::int64_t tick = world_->tick();
  const double end_s = world_->time_s();
  for (std::size_t k = 0; k < sensors_.size(); ++k) {
    if (schedule_.IsDue(static_cast<int>(k), tick) && sensors_[k]->Heavy(tick, end_s)) return true;
  }
  return false;
}

SensorOutputs SimRobot::AfterStep(const RobotState& before, const RobotState& after) {
  const World& world = *world_;
  SensorTick tick;
  tick.tick = world.tick();
  tick.end_s = world.time_s();
  tick.start_s = tick.end_s - world.step_s();
  tick.before = TrueWheels(before);
  tick.after = TrueWheels(after);
  tick.world = &world;
  tick.robot = index_;
  tick.group = world.robot_group(index_);
  tick.planar = planar_;
  SensorOutputs out;
  for (std::size_t k = 0; k < sensors_.size(); ++k) {
    if (schedule_.IsDue(static_cast<int>(k), tick.tick)) sensors_[k]->Sample(tick, &out);
  }
  return out;
}

}  // namespace pavilion::sim
