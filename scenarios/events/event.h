#pragma once

// The scenario timeline's seam: a scripted event acts on the run at its time
// and describes itself in events.jsonl. Push, teleport and door are built in
// (scripted_events.h); a new type registers a reader (event_registry.h) and
// needs no change to the runner.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/random/random_stream.h"
#include "sim/sensors/laser_scanner.h"
#include "sim/world/world.h"

namespace pavilion::sim {
class SimRobot;
}  // namespace pavilion::sim

namespace pavilion::scenarios {

// The fields of an events.jsonl record after its time_s and type, in order.
using EventFields = nlohmann::ordered_json;

// The seeded random streams of a run's events by name: stream `name` is
// core::RandomStream(seed, StreamId(name)), made on first use and shared by
// every event that names it (in timeline order: deterministic).
class EventStreams {
 public:
  explicit EventStreams(std::uint64_t seed) : seed_(seed) {}
  core::RandomStream& Get(const std::string& name);

 private:
  std::uint64_t seed_;
  std::map<std::string, core::RandomStream> streams_;
};

// A robot moved by an event without telling it (a kidnap): for the
// relocalization figures, which judge its estimator against the truth.
struct KidnapNote {
  int robot = -1;  // world robot index
  core::Pose2 before;
  core::Pose2 after;
};

// What an event may act on: the world, the ids of its robots and bodies, and
// the state snapshot the tick's work reads (kept in step with teleports).
struct EventContext {
  sim::World* world = nullptr;
  const std::map<std::string, int>* robot_index = nullptr;  // world robot index by id
  const std::map<std::string, int>* body_index = nullptr;   // world body index by id
  sim::TickSnapshot* snapshot = nullptr;
  EventStreams* streams = nullptr;
  // By world robot index: the true distance each robot moved in the last step (m).
  const std::vector<double>* robot_step_m = nullptr;
  std::vector<KidnapNote>* kidnaps = nullptr;  // appended by events that move a robot
  // Faults a robot's laser (every laser for an empty sensor id); false when
  // the robot or laser is unknown.
  std::function<bool(const std::string& robot, const std::string& sensor, const sim::LaserFault&)>
      set_laser_fault;
  // The simulated robot of a world robot index (its hardware: odometry_bias
  // changes its wheels); null or empty when the run has none.
  std::function<sim::SimRobot*(int robot)> sim_robot;
};

class ScenarioEvent {
 public:
  virtual ~ScenarioEvent() = default;
  // The record's `type` (the key `type` of the scenario file).
  virtual std::string type() const = 0;
  // Acts on the run before the physics step it is due at; returns its record's
  // fields, or null for no record.
  virtual EventFields Apply(const EventContext& context) const = 0;
  // A process that keeps acting after its time (random kidnaps by distance):
  // Continue is then called before every later physics step and returns a
  // record's fields or null.
  virtual bool ongoing() const { return false; }
  virtual EventFields Continue(const EventContext& /*context*/) const { return nullptr; }
};

// An event of the timeline with the time it is due at.
struct TimedEvent {
  double at_s = 0.0;
  std::shared_ptr<const ScenarioEvent> event;
};

}  // namespace pavilion::scenarios
