#pragma once

// The kidnapped robot (issue 17, issue 18): a robot lifted to another pose
// without telling it (its motors and odometry are not told), the test of
// global localization (thesis §5.7, §6.5: staff pushing robots at Expo.02).
// To a given pose, to a random free pose drawn from the seed, or turned in
// place with a probability per metre travelled (Fox, Burgard & Thrun 1999).
// For robots, `teleport` is this event with a given pose.

#include <memory>
#include <optional>
#include <string>

#include "core/types/pose2.h"
#include "scenarios/events/event_registry.h"

namespace pavilion::scenarios {

struct KidnapOptions {
  // Random pose: at least this far from the robot's true position, m, [0, 1e3]
  // (issue 18: >= 2 m).
  double min_distance_m = 2.0;
  // Random pose: at least this turn from the robot's true heading, rad, [0, pi]
  // (issue 18: >= 30 deg).
  double min_turn_rad = 0.5235987755982988;
  // Free space kept around the footprint's circumradius at a random pose, m,
  // [0, 10] (chosen: a hand-placed robot is not set down touching anything).
  double margin_m = 0.1;
  // Random mode by distance: the probability per metre truly travelled that
  // the robot is turned in place after a tick, 1/m, [0, 100]; 0: off (Fox,
  // Burgard & Thrun, JAIR 1999: 0.005).
  double per_m = 0.0;
  // The turn of the random mode, rad, [-2 pi, 2 pi] (Fox et al. 1999: 180 deg).
  double turn_rad = 3.141592653589793;
  // Random pose: draws before the event gives up with an error record, [1, 1e6]
  // (chosen: free space of a few percent of the floor is still found).
  int max_draws = 2000;

  void Validate() const;  // throws std::invalid_argument naming the field
};

class KidnapEvent : public ScenarioEvent {
 public:
  // `pose`: to that pose; none: a random free pose (or, with per_m > 0, the
  // random turns), drawn from the stream "<robot>/kidnap" of the scenario seed.
  KidnapEvent(std::string robot, std::optional<core::Pose2> pose, KidnapOptions options);
  std::string type() const override { return "kidnap"; }
  // Moves the robot now (none for the random mode by distance, which starts now).
  EventFields Apply(const EventContext& context) const override;
  bool ongoing() const override { return options_.per_m > 0.0; }
  // The random mode by distance: after each tick, a turn in place with
  // probability per_m * (the distance truly travelled in it).
  EventFields Continue(const EventContext& context) const override;

  const std::string& robot() const { return robot_; }
  const std::optional<core::Pose2>& pose() const { return pose_; }
  const KidnapOptions& options() const { return options_; }

 private:
  EventFields MoveTo(const EventContext& context, int index, const core::Pose2& to,
                     const char* mode) const;
  std::optional<core::Pose2> DrawFreePose(const EventContext& context, int index) const;

  std::string robot_;
  std::optional<core::Pose2> pose_;
  KidnapOptions options_;
};

// The footprint of a robot at `pose` against the world's static geometry at
// the start (walls, boxes, cylinders, meshes, doors as they start) and its
// floor: empty when it fits, else what it runs into (load-time checks).
std::string StaticObstacleAt(const sim::WorldDescription& world, const RobotFootprint& footprint,
                             const core::Pose2& pose);

// Reads the kidnap of `robot` to the pose under `pose_key` (none if absent and
// not required: a random one): the pose is checked with StaticObstacleAt and
// problems reported at its key; null when the entry has an error.
std::shared_ptr<const ScenarioEvent> ReadKidnapTo(MapReader& r, const EventTargets& targets,
                                                  const std::string& robot,
                                                  const std::string& pose_key, bool pose_required,
                                                  const KidnapOptions& options);

// Registers `kidnap` (reads robot, pose or the random options).
void RegisterKidnapEvent(EventRegistry* registry);

}  // namespace pavilion::scenarios
