#pragma once

// Social-navigation figures (metrics.md, "Navigation and fleet"; docs/crowd.md):
// per robot, how close it came to visitors in Hall's proxemic zones, and for
// the run, what the crowd did. Ground truth stays on the runner's side: the
// trackers read the world's state after each physics step.
//
// The gap between a robot and a visitor is measured as crowd-navigation
// benchmarks measure it, surface to surface: from the robot's footprint (its
// convex hull) to the visitor's body disc (PersonState::shape.radius_m). It is
// negative while the two overlap.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/types/pose2.h"
#include "sim/crowd/crowd.h"
#include "sim/crowd/person.h"

namespace pavilion::scenarios {

// Outer edges of Hall's proxemic zones, m (E. T. Hall, "The Hidden
// Dimension", 1966: intimate to 18 in, personal to 4 ft, social to 12 ft).
inline constexpr double kIntimateZoneM = 0.45;
inline constexpr double kPersonalZoneM = 1.2;
inline constexpr double kSocialZoneM = 3.6;
// A visitor closer than this is uncomfortably close (metrics.md; CrowdNav's
// discomfort distance, Chen et al., ICRA 2019), m.
inline constexpr double kDiscomfortGapM = 0.2;

// One robot's figures over a run.
struct SocialNavigationFigures {
  // Time with the closest present visitor's gap < 0.45 m, in [0.45, 1.2) m and
  // in [1.2, 3.6) m, s. Disjoint: a tick counts in the closest visitor's zone.
  double intimate_time_s = 0.0;
  double personal_time_s = 0.0;
  double social_time_s = 0.0;
  // Visitors crossing into the zone's disc (gap below its outer edge) from
  // farther out. Nested: a visitor stepping from outside straight into the
  // intimate zone counts in all three; one that appears (arrives, or is first
  // seen) already inside counts once in its zone and the zones around it.
  std::int64_t intimate_intrusions = 0;
  std::int64_t personal_intrusions = 0;
  std::int64_t social_intrusions = 0;
  // Smallest gap to any present visitor over the run, m (<= 0: in contact);
  // +inf until a visitor was present.
  double min_visitor_gap_m = std::numeric_limits<double>::infinity();
  double closer_than_0_2_m_time_s = 0.0;  // time with some visitor's gap < 0.2 m, s
};

// Accumulates one robot's figures, one Update() per physics tick. Cost per
// tick: a squared distance per present visitor, and the hull distance only for
// visitors that may be within 3.6 m (or closer than the smallest gap so far)
// and whose gap's bounds (the footprint's circumradius and inradius about the
// base origin) leave their zone or the discomfort gap open.
class SocialNavigationTracker {
 public:
  // `footprint_in_robot_m`: the robot's convex outline in its base frame
  // (counter-clockwise; a clockwise one is reversed). Throws
  // std::invalid_argument for fewer than three vertices, non-finite ones or a
  // concave outline.
  explicit SocialNavigationTracker(std::vector<Eigen::Vector2d> footprint_in_robot_m);

  // The state after a step of `dt_s` seconds: the robot's true pose and the
  // crowd's pool (by person index, a fixed pool; people not `present` are
  // ignored). Throws std::invalid_argument for a negative or non-finite dt.
  void Update(double dt_s, const core::Pose2& world_from_robot,
              const std::vector<sim::crowd::PersonState>& people);

  SocialNavigationFigures Figures() const { return figures_; }
  // At least one present visitor was seen: the figures mean something.
  bool active() const { return active_; }

 private:
  // Zones by index, closest first; kOutside: beyond 3.6 m or not on the floor.
  enum Zone : std::uint8_t { kIntimate = 0, kPersonal = 1, kSocial = 2, kOutside = 3 };
  static Zone ZoneOf(double gap_m);
  static int BandOf(double gap_m);

  std::vector<Eigen::Vector2d> footprint_in_robot_m_;  // counter-clockwise
  double circumradius_m_ = 0.0;                        // of the footprint about the base origin
  // The largest circle about the base origin inside the footprint (0 when the
  // origin is not inside): with the circumradius it brackets every gap.
  double inradius_m_ = 0.0;
  std::vector<Zone> zone_;  // by person: where they were at the last tick
  SocialNavigationFigures figures_;
  bool active_ = false;
};

// The crowd over a run (one per run with a crowd).
struct CrowdFigures {
  std::int64_t pool = 0;        // bodies available
  std::int64_t arrivals = 0;    // visitors that entered
  std::int64_t departures = 0;  // visitors that left
  double mean_present = 0.0;    // visitors on the floor, time-averaged over the ticks
  std::int64_t max_present = 0;
  // Worst interpenetration of bodies with each other, walls or robots, m, and
  // by what was overlapped.
  double max_overlap_m = 0.0;
  double max_overlap_people_m = 0.0;
  double max_overlap_walls_m = 0.0;
  double max_overlap_robots_m = 0.0;
  // Person-seconds a visitor wanted to walk but a robot stood in the way
  // (Crowd::blocked_by_robot), s.
  double visitor_blocked_by_robot_s = 0.0;
  std::int64_t pushes = 0;  // push and kick pulses begun on robots
  // Episodes near robots begun (§6.5 behaviours), by behaviour name.
  std::vector<std::pair<std::string, std::int64_t>> episodes;
};

// Accumulates the crowd's figures, one Update() per physics tick after the
// crowd has stepped.
class CrowdTracker {
 public:
  // Throws std::invalid_argument for a negative or non-finite dt.
  void Update(double dt_s, const sim::crowd::Crowd& crowd);
  CrowdFigures Figures() const;

 private:
  CrowdFigures figures_;
  double time_s_ = 0.0;
  double present_s_ = 0.0;  // ∫ present dt
};

}  // namespace pavilion::scenarios
