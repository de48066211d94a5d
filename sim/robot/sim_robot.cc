#include "sim/robot/sim_robot.h"

#include <set>
#include <stdexcept>
#include <utility>

#include "sim/sensors/bumper_sensor.h"
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
  AddSensor(std::make_unique<EncoderSensor>(id, config_.encoders, model.left_wheel.radius_m,
                                            model.right_wheel.radius_m,
                                            StreamFor(seed, id, "encoders"), physics_hz));
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
  world_->SetWheelSpeeds(index_, left_radps, right_radps);
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

SensorOutputs SimRobot::AfterStep(const RobotState& before, const RobotState& after) {
  const World& world = *world_;
  SensorTick tick;
  tick.tick = world.tick();
  tick.end_s = world.time_s();
  tick.start_s = tick.end_s - world.step_s();
  tick.before = before;
  tick.after = after;
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
