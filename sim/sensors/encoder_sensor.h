#pragma once

#include <Eigen/Core>
#include <string>

#include "core/random/random_stream.h"
#include "sim/sensors/robot_sensors.h"
#include "sim/sensors/sensor.h"

namespace pavilion::sim {

// A robot's wheel encoders as a Sensor (id "encoders"), reading into
// SensorOutputs::encoders. They may run at a whole multiple of the physics
// rate: they are then sampled every tick and read several times in it, at
// wheel angles interpolated between the tick's two states.
class EncoderSensor final : public Sensor {
 public:
  // `robot_id` names the robot in errors. Throws std::invalid_argument for
  // invalid options or a rate that is neither a divisor nor a whole multiple
  // of `physics_rate_hz`.
  // `left_wheel_m`, `right_wheel_m`: the wheels' floor contacts in the base
  // frame (for the floor patches of options.patches).
  EncoderSensor(const std::string& robot_id, const EncoderOptions& options, double left_radius_m,
                double right_radius_m, core::RandomStream stream, double physics_rate_hz,
                const Eigen::Vector2d& left_wheel_m = {0, 0},
                const Eigen::Vector2d& right_wheel_m = {0, 0});

  const std::string& id() const override { return id_; }
  double sample_rate_hz() const override { return sample_rate_hz_; }
  void Sample(const SensorTick& tick, SensorOutputs* out) override;

 private:
  std::string id_ = "encoders";
  WheelEncoders encoders_;
  double sample_rate_hz_;
  int readings_per_tick_ = 1;  // > 1 when the encoders are faster than the physics
  Eigen::Vector2d wheel_m_[2];
  // How far each wheel turns per metre where it stands (1 off any of the
  // options' floor patches).
  double PatchScale(const core::Pose2& world_from_base, int side) const;
};

}  // namespace pavilion::sim
