#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/types/sensor_data.h"
#include "sim/raycast/planar_caster.h"
#include "sim/robot/robot_config.h"
#include "sim/runtime/schedule.h"
#include "sim/sensors/laser_scanner.h"
#include "sim/sensors/robot_sensors.h"
#include "sim/sensors/sensor.h"
#include "sim/world/world.h"

namespace pavilion::sim {

// A simulated robot: its articulated body in the world and its sensors (wheel
// encoders, bumpers, laser scanners, and any added with AddSensor), all
// sampled in simulation time. Every random draw comes from streams derived
// from (seed, robot id, sensor id).
class SimRobot {
 public:
  // Adds the robot of `config` to `world` at `placement`, with the
  // encoders, bumpers and lasers of its robot file. The config's materials
  // (its model's and markers') must be materials of the world. Throws
  // std::invalid_argument for an inconsistent robot (sensor rates that do not
  // divide the physics rate, duplicate ids). Encoders may also run at a whole
  // multiple of the physics rate: they then read several times a tick, at
  // wheel angles interpolated within it.
  SimRobot(World* world, RobotConfig config, RobotPlacement placement, std::uint64_t seed);

  const std::string& id() const { return placement_.id; }
  int index() const { return index_; }
  const RobotConfig& config() const { return config_; }
  const RobotPlacement& placement() const { return placement_; }
  // The laser scanners of the robot file, in its order.
  const std::vector<std::reference_wrapper<const LaserScanner>>& lasers() const { return lasers_; }

  // Faults the laser named `laser_id` (every laser when empty) from now on
  // (LaserFault). Returns false when the robot has no such laser.
  bool SetLaserFault(const std::string& laser_id, const LaserFault& fault);

  // Adds a sensor, sampled after those added before it (the robot's encoders,
  // bumpers and lasers come first, in that order). Throws std::invalid_argument
  // for an id already used on this robot or a rate that does not divide the
  // physics rate.
  void AddSensor(std::unique_ptr<Sensor> sensor);

  // True when one of its sensors casts rays or renders in the tick the world
  // has just stepped (Sensor::Heavy): AfterStep then needs the planar slices
  // current, and is worth a worker thread.
  bool HeavyTick() const;

  // Casts this robot's scans with `caster` (shared by the world's robots; it
  // must outlive the robot) where the beam plane allows, Bullet elsewhere;
  // null (the default): Bullet for every scan.
  void UsePlanarCaster(PlanarCaster* caster);

  // Wheel-speed command (rad/s, positive forward), held until changed.
  void SetWheelSpeeds(double left_radps, double right_radps);

  // The true radius of a drive wheel (side 0 left, 1 right) from now on, as a
  // factor of the radius it was built with (a flat tyre, a carpet's pile):
  // the floor moves by the new radius per turn, the encoders count the wheel's
  // turns, and the robot's calibrated odometry is not told. Throws
  // std::invalid_argument for a side not 0 or 1 or a scale outside
  // [kMinWheelRadiusScale, kMaxWheelRadiusScale].
  void SetWheelRadiusScale(int side, double scale);
  double wheel_radius_scale(int side) const { return wheel_scale_[side].scale; }
  static constexpr double kMinWheelRadiusScale = 0.5;
  static constexpr double kMaxWheelRadiusScale = 2.0;

  // Samples the sensors due in the tick that just ended, in the order they
  // were added: `before` and `after` are the robot's true states at its start
  // and end (times world.time_s() − step and world.time_s()). Laser readings
  // due in the tick are cast from poses interpolated between the two. With a
  // planar caster, a sweep's readings of this tick fall back to Bullet when the
  // robot's tilt at either end exceeds the caster's max_tilt_rad or a body the
  // plane does not cut exactly is within range.
  //
  // Robots may sample from several threads at once (each robot from one) when
  // the world is not stepped meanwhile and the planar caster has been brought
  // up to date (PlanarCaster::Update) after the step: each robot then writes
  // only its own state, draws from its own streams, and Bullet fallback casts
  // are serialized by the world (Sensor states the same contract for every
  // sensor).
  SensorOutputs AfterStep(const RobotState& before, const RobotState& after);

 private:
  World* world_;
  RobotConfig config_;
  RobotPlacement placement_;
  int index_ = -1;
  PeriodicSchedule schedule_;  // task i samples sensors_[i]
  std::vector<std::unique_ptr<Sensor>> sensors_;
  std::vector<std::reference_wrapper<const LaserScanner>> lasers_;
  std::vector<LaserScanner*> mutable_lasers_;  // the same, for faults
  PlanarCaster* planar_ = nullptr;

  // SetWheelRadiusScale (sim_robot.cc): the world simulates the wheel it
  // built, turning at `scale` times the true wheel's rate. Per side: the scale
  // and, at its last change, the simulated and the true wheel's angles (rad).
  struct WheelScale {
    double scale = 1.0;
    double simulated_at_rad = 0.0;
    double true_at_rad = 0.0;
  };
  // The true wheels' angles and rates of a state of the simulated ones.
  RobotState TrueWheels(RobotState simulated) const;
  void CommandWorld();
  WheelScale wheel_scale_[2];
  double command_radps_[2] = {0.0, 0.0};  // the last command (true wheel rates)
};

}  // namespace pavilion::sim
