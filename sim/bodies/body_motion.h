#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <vector>

#include "core/geometry/polygon.h"
#include "core/random/random_stream.h"
#include "sim/world/world.h"

namespace pavilion::sim {

// The velocity a driven body should hold next, in the world frame.
struct PlanarVelocity {
  Eigen::Vector2d linear_mps{0, 0};
  double yaw_rate_radps = 0.0;
};

// Decides a driven body's velocity each physics step from the time and its state.
class BodyMotion {
 public:
  virtual ~BodyMotion() = default;
  virtual PlanarVelocity Update(double time_s, const BodyState& state) = 0;
};

// One piece of a scripted velocity profile.
struct VelocitySegment {
  double duration_s = 1.0;             // s, (0, 1e7]
  Eigen::Vector2d velocity_mps{0, 0};  // m/s, finite; in the body frame if body_frame, else world
  double yaw_rate_radps = 0.0;         // rad/s, [-100, 100]

  void Validate() const;  // throws std::invalid_argument naming the field
};

struct ScriptedMotionOptions {
  std::vector<VelocitySegment> segments;  // played in order from t = 0, then stop
  bool body_frame = true;                 // velocities in the body frame (like a robot)
  bool loop = false;                      // start over after the last segment
};

// Plays a piecewise-constant velocity profile.
class ScriptedMotion : public BodyMotion {
 public:
  explicit ScriptedMotion(ScriptedMotionOptions options);
  PlanarVelocity Update(double time_s, const BodyState& state) override;

 private:
  ScriptedMotionOptions options_;
  double total_s_ = 0.0;
};

struct RandomWalkOptions {
  double speed_mps = 0.8;      // walking speed, m/s, [0, 5]
  double mean_leg_s = 4.0;     // mean time between heading changes (exponential), s, [1e-3, 1e4]
  double blocked_ratio = 0.3;  // below this fraction of the speed the walker is blocked, [0, 1]
  double blocked_s = 0.5;      // ... for this long (s, >= 0), it turns to a new heading
  // When set, a walker found outside this polygon heads back to its centroid.
  std::optional<core::Polygon2> roam_area;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// A walker that keeps a heading for exponentially distributed times and picks a
// new uniform heading when the time is up or it has been blocked; outside its
// roam area it walks back towards the area's centroid. Stands in for
// visitors until the crowd model exists. Its draws come from its own stream.
class RandomWalkMotion : public BodyMotion {
 public:
  RandomWalkMotion(RandomWalkOptions options, core::RandomStream stream);
  PlanarVelocity Update(double time_s, const BodyState& state) override;

 private:
  void NewLeg(double time_s);

  RandomWalkOptions options_;
  core::RandomStream stream_;
  double heading_rad_ = 0.0;
  double leg_end_s_ = -1.0;
  double blocked_since_s_ = -1.0;
};

}  // namespace pavilion::sim
