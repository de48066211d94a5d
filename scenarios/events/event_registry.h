#pragma once

// Event types by name: the scenario loader reads each `events:` entry with the
// reader registered for its `type`. Built in: push, teleport, door, kidnap,
// spawn_group, sensor_fault, odometry_bias. An entry with a `random:` block
// instead of `at_s` is expanded into timed entries first (random_events.h).

#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "scenarios/config/yaml_reader.h"
#include "scenarios/events/event.h"
#include "sim/world/world_description.h"

namespace pavilion::scenarios {

// A robot's outline as events that place it check it against the world.
struct RobotFootprint {
  double radius_m = 0.0;  // the outline's circumradius about the base frame
  double bottom_m = 0.0;  // the chassis' underside above the floor
  double top_m = 0.0;     // the chassis' top above the floor
};

// The ids an event of the scenario may name, and what poses are checked against.
struct EventTargets {
  std::set<std::string> bodies;  // bodies and robots (push, teleport)
  std::set<std::string> robots;
  std::set<std::string> doors;
  std::map<std::string, RobotFootprint> footprints;        // by robot id
  const sim::WorldDescription* world = nullptr;            // the static geometry at the start
  int crowd_pool = 0;                                      // the crowd's bodies; 0: no crowd
  std::map<std::string, std::vector<std::string>> lasers;  // laser ids by robot id
};

// Reads one entry's type-specific keys (`at_s` and `type` are read already);
// reports problems through the reader's document and returns null for them.
using EventReader =
    std::function<std::shared_ptr<const ScenarioEvent>(MapReader& entry, const EventTargets&)>;

class EventRegistry {
 public:
  // The registry the scenario loader uses, with the built-in types.
  static EventRegistry& Global();

  // Adds a type; throws std::invalid_argument if the name is taken.
  void Register(const std::string& type, EventReader reader);
  // Null for an unknown type.
  const EventReader* Find(const std::string& type) const;
  // Registered names in registration order.
  std::vector<std::string> types() const;

 private:
  std::vector<std::pair<std::string, EventReader>> readers_;
};

}  // namespace pavilion::scenarios
