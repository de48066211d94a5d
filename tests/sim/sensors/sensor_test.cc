// The Sensor interface of a simulated robot: a sensor type the simulator does
// not know, added through SimRobot::AddSensor, is sampled at its scheduled
// rate after the built-in sensors and reports into SensorOutputs::custom.
#include "sim/sensors/sensor.h"

#include <gtest/gtest.h>

#include <any>
#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "sim/robot/sim_robot.h"
#include "sim/world/world.h"
#include "tests/support/floor_world.h"
#include "tests/support/world_robot.h"

namespace pavilion::sim {
namespace {

// What the test sensor reports each time it is sampled.
struct TickCount {
  std::int64_t tick = 0;
  double left_wheel_rad = 0.0;
};

// A test-only sensor: reports the tick index and the true left wheel angle.
class TickCounter final : public Sensor {
 public:
  TickCounter(std::string id, double rate_hz) : id_(std::move(id)), rate_hz_(rate_hz) {}

  const std::string& id() const override { return id_; }
  double sample_rate_hz() const override { return rate_hz_; }
  void Sample(const SensorTick& tick, SensorOutputs* out) override {
    ++samples;
    out->custom.push_back({id_, tick.end_s, TickCount{tick.tick, tick.after.left_wheel_rad}});
  }

  int samples = 0;

 private:
  std::string id_;
  double rate_hz_;
};

// Pygmalion-like, with 100 Hz encoders.
RobotConfig TestRobot() {
  RobotConfig config;
  config.description = pavilion::testing::PygmalionLikeModel("floor");
  config.encoders.rate_hz = 100.0;
  return config;
}

// Steps the world and samples the robot for `ticks` ticks; returns every output.
std::vector<SensorOutputs> StepAndSample(World* world, SimRobot* robot, int ticks) {
  std::vector<SensorOutputs> outputs;
  for (int k = 0; k < ticks; ++k) {
    const RobotState before = world->robot_state(robot->index());
    world->Step();
    outputs.push_back(robot->AfterStep(before, world->robot_state(robot->index())));
  }
  return outputs;
}

// A 50 Hz sensor on 200 Hz physics is sampled every fourth tick, stamped with
// the tick's end time, and its readings come out in `custom` beside the encoders.
TEST(SensorTest, AddedSensorIsSampledAtItsRateIntoCustom) {
  World world(testing::FloorWorld(5, false), WorldOptions{});  // 200 Hz physics
  SimRobot robot(&world, TestRobot(), RobotPlacement{"r", {}}, 1);
  auto sensor = std::make_unique<TickCounter>("tick_counter", 50.0);
  TickCounter* counter = sensor.get();
  robot.AddSensor(std::move(sensor));
  robot.SetWheelSpeeds(2.0, 2.0);

  const std::vector<SensorOutputs> outputs = StepAndSample(&world, &robot, 200);  // 1 s
  int customs = 0, encoders = 0;
  for (std::size_t k = 0; k < outputs.size(); ++k) {
    const std::int64_t tick = static_cast<std::int64_t>(k) + 1;
    const SensorOutputs& out = outputs[k];
    encoders += static_cast<int>(out.encoders.size());
    ASSERT_EQ(out.custom.size(), tick % 4 == 0 ? 1u : 0u) << "tick " << tick;
    for (const CustomReading& r : out.custom) {
      ++customs;
      EXPECT_EQ(r.sensor_id, "tick_counter");
      EXPECT_NEAR(r.stamp_s, static_cast<double>(tick) / 200.0, 1e-12);
      const TickCount* value = std::any_cast<TickCount>(&r.value);
      ASSERT_NE(value, nullptr);
      EXPECT_EQ(value->tick, tick);
    }
  }
  EXPECT_EQ(customs, 50);
  EXPECT_EQ(counter->samples, 50);
  EXPECT_EQ(encoders, 100);  // the built-in encoders keep their 100 Hz
  // The sensor saw the robot's true state: the wheels turned forward.
  const TickCount& last = std::any_cast<const TickCount&>(outputs.back().custom.back().value);
  EXPECT_GT(last.left_wheel_rad, 0.5);
}

// Two sensors of one robot may not share an id, and a sensor's rate must
// divide the physics rate.
TEST(SensorTest, AddSensorRejectsDuplicateIdsAndRatesOffTheTickGrid) {
  World world(testing::FloorWorld(5, false), WorldOptions{});
  SimRobot robot(&world, TestRobot(), RobotPlacement{"r", {}}, 1);
  robot.AddSensor(std::make_unique<TickCounter>("a", 100.0));
  EXPECT_THROW(robot.AddSensor(std::make_unique<TickCounter>("a", 100.0)), std::invalid_argument);
  EXPECT_THROW(robot.AddSensor(std::make_unique<TickCounter>("encoders", 100.0)),
               std::invalid_argument);
  EXPECT_THROW(robot.AddSensor(std::make_unique<TickCounter>("b", 70.0)), std::invalid_argument);
}

// Sensors are sampled in the order added: a second custom sensor at the same
// rate reports after the first within a tick.
TEST(SensorTest, SensorsReportInTheOrderAdded) {
  World world(testing::FloorWorld(5, false), WorldOptions{});
  SimRobot robot(&world, TestRobot(), RobotPlacement{"r", {}}, 1);
  robot.AddSensor(std::make_unique<TickCounter>("first", 100.0));
  robot.AddSensor(std::make_unique<TickCounter>("second", 100.0));
  const std::vector<SensorOutputs> outputs = StepAndSample(&world, &robot, 4);
  for (std::size_t k = 0; k < outputs.size(); ++k) {
    const std::vector<CustomReading>& custom = outputs[k].custom;
    if (k % 2 == 0) {
      EXPECT_TRUE(custom.empty());
      continue;
    }
    ASSERT_EQ(custom.size(), 2u);
    EXPECT_EQ(custom[0].sensor_id, "first");
    EXPECT_EQ(custom[1].sensor_id, "second");
  }
}

// A robot's tick is heavy exactly when its lasers cast: the ticks of each
// 10 Hz sweep (19.98 ms of readings, so 4 of every 20 ticks at 200 Hz, 5 when
// a reading's time rounds into the next tick), not the encoder-only ticks
// between them, which the scenario runner senses inline.
TEST(SensorTest, ATickIsHeavyExactlyWhenTheLasersCast) {
  World world(testing::FloorWorld(5, false), WorldOptions{});
  RobotConfig config = TestRobot();
  LaserMount laser;
  laser.id = "front";
  laser.z_m = 0.3;  // LaserScannerOptions: the LMS 200's, 10 Hz
  config.lasers.push_back(laser);
  SimRobot robot(&world, config, RobotPlacement{"r", {}}, 1);
  const LaserScanner& scanner = robot.lasers().front().get();
  int heavy = 0;
  const int ticks = 400;  // 2 s: 20 sweeps
  for (int k = 0; k < ticks; ++k) {
    const RobotState before = world.robot_state(robot.index());
    world.Step();
    const bool says_heavy = robot.HeavyTick();
    const std::int64_t rays = scanner.rays_cast();
    robot.AfterStep(before, world.robot_state(robot.index()));
    EXPECT_EQ(says_heavy, scanner.rays_cast() > rays) << "tick " << k;
    heavy += says_heavy ? 1 : 0;
  }
  EXPECT_GE(heavy, ticks / 20 * 4);
  EXPECT_LE(heavy, ticks / 20 * 5);
}

}  // namespace
}  // namespace pavilion::sim
