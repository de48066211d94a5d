#pragma once

#include <any>
#include <cstdint>
#include <string>
#include <vector>

#include "core/types/sensor_data.h"
#include "sim/world/world.h"

namespace pavilion::sim {

class PlanarCaster;

// A finished scan with its ground truth.
struct ScanRecord {
  core::LaserScan scan;
  core::LaserScanTruth truth;
  // Some readings were cast with Bullet instead of the planar caster (the beam
  // plane tilted, or a body the plane does not cut exactly was in range).
  bool fallback = false;
};

// A finished camera image with its ground truth.
struct ImageRecord {
  core::CameraImage image;
  double exposure_s = 0.0;        // when it was taken (simulation time)
  core::Pose2 world_from_camera;  // the camera's true planar pose then
};

// A reading of a sensor type the simulator has no typed output for.
struct CustomReading {
  std::string sensor_id;  // Sensor::id() of the sensor that produced it
  double stamp_s = 0.0;   // simulation time of the reading
  std::any value;         // whatever the sensor reports
};

// What a robot's sensors produced during one tick, in the order they fired.
struct SensorOutputs {
  std::vector<core::EncoderReading> encoders;
  std::vector<core::BumperReading> bumpers;  // only when the pressed set changed
  std::vector<ScanRecord> scans;
  std::vector<ImageRecord> images;
  std::vector<CustomReading> custom;
};

// The tick that just ended, as a robot's sensors see it.
struct SensorTick {
  std::int64_t tick = 0;  // World::tick() after the step
  double start_s = 0.0;   // simulation time at the start of the tick
  double end_s = 0.0;     // ... and at its end (World::time_s())
  RobotState before;      // the robot's true state at start_s
  RobotState after;       // ... and at end_s
  const World* world = nullptr;
  int robot = -1;  // the robot's index in `world`
  int group = -1;  // its element group: its own sensors' rays ignore these elements
  // The planar laser caster shared by the world's robots, brought up to date
  // for this tick, or null (Bullet rays only).
  PlanarCaster* planar = nullptr;
};

// A sensor on a simulated robot (sim::SimRobot). The robot samples each of its
// sensors at the ticks its PeriodicSchedule gives for sample_rate_hz(), in the
// order the sensors were added. Sample may run while other robots' sensors
// sample on other threads (SimRobot::AfterStep): it must write only its own
// state and `out`, draw only from its own random streams, and use the world
// only through const calls.
class Sensor {
 public:
  virtual ~Sensor() = default;

  // Unique among the sensors of one robot.
  virtual const std::string& id() const = 0;
  // How often Sample runs (Hz): the physics rate divided by a whole number.
  virtual double sample_rate_hz() const = 0;
  // Appends the readings of the tick that just ended to `out`.
  virtual void Sample(const SensorTick& tick, SensorOutputs* out) = 0;
  // True when Sample of the tick `tick` (World::tick() after its step), ending
  // at end_s, does heavy work: casts rays or renders. Ticks in which no sensor
  // of any robot does are sensed on the calling thread, without bringing the
  // planar slices up to date (SimRobot::HeavyTick). A sensor that casts or
  // renders must say so, or it would cast from several threads.
  virtual bool Heavy(std::int64_t tick, double end_s) const {
    (void)tick;
    (void)end_s;
    return false;
  }
};

}  // namespace pavilion::sim
