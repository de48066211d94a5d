#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/polygon.h"
#include "core/types/pose2.h"
#include "sim/crowd/person.h"
#include "sim/crowd/social_force.h"

namespace pavilion::sim::crowd {

// What visitors do besides visiting exhibits (thesis §6.5: "people were
// curious, stood in front of the robot, crowded around it in a U, blocked
// its way, followed it, and pushed or kicked it"). Fractions of the visitors
// who behave so when a robot comes within notice range; the rest ignore
// robots but for walking around them.
enum class Behaviour { kOrdinary, kCurious, kCrowding, kBlocking, kFollowing, kPushing };
const char* ToString(Behaviour behaviour);

struct BehaviourOptions {
  double curious = 0.0;          // approach a robot and stand in front of it, [0, 1]
  double crowding = 0.0;         // stand in a U around a robot with others, [0, 1]
  double blocking = 0.0;         // step into a robot's path and stay, [0, 1]
  double following = 0.0;        // walk behind a robot, [0, 1]
  double pushing = 0.0;          // push or kick a robot, [0, 1]; the fractions sum to <= 1
  double notice_range_m = 4.0;   // a robot this close starts an episode, m, (0, 50]
  double episode_mean_s = 30.0;  // episode length N(mean, mean/3), at least 5 s, s, (0, 3600]
  double cooldown_s = 120.0;     // time between a visitor's episodes, s, [0, 1e5]
  // A push: a force pulse on the robot's body, bounded by the contact limit
  // (SocialForceOptions::max_push_force_n); a third of pushes are kicks
  // (shorter, at the limit). Chosen.
  double push_force_n = 200.0;   // N, (0, 1e4]
  double push_duration_s = 0.5;  // s, (0, 10]
  double kick_duration_s = 0.1;  // s, (0, 10]

  void Validate() const;  // throws std::invalid_argument naming the field
};

// A visit (§6.5: 400 arrivals an hour kept about 100 visitors present, so a
// visit lasted about 15 minutes). Visitors enter, visit U{min..max} exhibits
// drawn by their attraction, dwell N(dwell_mean, dwell_std) at each, stop at
// watch spots of the floor (to watch the robots) while their visit's time is
// not up, and leave by the exit.
struct VisitOptions {
  int min_exhibits = 1;                  // [0, 50]
  int max_exhibits = 6;                  // [min_exhibits, 50]
  double dwell_mean_s = 60.0;            // s, [0, 3600]
  double dwell_std_s = 20.0;             // s, [0, 3600]
  double visit_mean_s = 900.0;           // total visit length N(mean, std), s, [0, 86400]
  double visit_std_s = 300.0;            // s, [0, 86400]
  double desired_speed_mean_mps = 1.34;  // N(1.34, 0.26): W93 and HM95, m/s, (0, 3]
  double desired_speed_std_mps = 0.26;   // m/s, [0, 1]
  double group_fraction = 0.3;           // share of arrivals that come as a group, [0, 1]
  int min_group_size = 2;                // [2, max_group_size]
  int max_group_size = 5;                // [min_group_size, 20]

  void Validate() const;  // throws std::invalid_argument naming the field
};

struct CrowdOptions {
  int pool_size = 100;      // bodies available; at most this many present, [1, 10000]
  int initial_present = 0;  // placed mid-visit at t = 0, [0, pool_size]
  double arrivals_per_hour =
      0;                  // Poisson arrivals of parties (a group counts its members), [0, 1e5]
  int max_present = 100;  // arrivals wait while this many are present, [0, pool_size]
  VisitOptions visit;
  BehaviourOptions behaviours;
  PersonBodyOptions body;
  SocialForceOptions social;
  double route_cell_m = 0.2;       // floor-field grid cell, m, (0, 1]
  double route_clearance_m = 0.3;  // floor fields keep routes this far from obstacles, m, [0, 1]
  int watch_spots = 12;            // random places on the floor where visitors stop, [0, 200]

  void Validate() const;  // throws std::invalid_argument naming the field
};

// A station people visit: a place in front of an exhibit.
struct Attraction {
  std::string name;
  core::Pose2 pose;     // where a visitor stands, facing the exhibit
  double weight = 1.0;  // relative chance of being chosen (the world's `attraction`), >= 0
};

// Where a crowd lives: the floor, its entrance and exit, the exhibits.
struct CrowdSite {
  Eigen::Vector2d floor_min_m{0, 0};
  Eigen::Vector2d floor_max_m{0, 0};
  core::Polygon2 entrance;   // arrivals appear inside (free spots only)
  core::Polygon2 exit;       // visitors leave when they reach it
  core::Polygon2 roam_area;  // where watch spots and initial visitors are drawn; empty: the floor
  std::vector<Attraction> attractions;
  // Obstacles people walk around (walls, exhibits, furniture, closed doors).
  std::vector<WallSegment> walls;
  std::vector<WallCircle> pillars;
  // Outlines (world frame, convex) nobody is placed on at the start: the robots.
  std::vector<std::vector<Eigen::Vector2d>> keep_clear;
};

// A robot as the crowd sees it now.
struct CrowdRobot {
  core::Pose2 pose;
  Eigen::Vector2d velocity_mps{0, 0};
  double yaw_rate_radps = 0.0;
  std::vector<Eigen::Vector2d> footprint_in_robot_m;  // convex, counter-clockwise
};

// A push or kick pulse on a robot (world frame), this step.
struct RobotPush {
  int robot = -1;
  int person = -1;
  Eigen::Vector2d force_n{0, 0};
  Eigen::Vector2d point_m{0, 0};
  bool kick = false;
};

// What the crowd did to robots in a step: forces to apply to their bodies.
struct CrowdStepResult {
  std::vector<RobotContactForce> contacts;  // bodies touching robots (bounded)
  std::vector<RobotPush> pushes;            // deliberate pushes and kicks
};

// Per person, for metrics: what they do now.
enum class Activity { kParked, kWalking, kDwelling, kWatching, kEpisode, kLeaving };
const char* ToString(Activity activity);

// A crowd of visitors from a fixed pool: arrivals, visits, behaviours near
// robots, and their motion by the social force model. Steps at the caller's
// rate (the physics rate); decisions are made at the social force rate.
// Deterministic: every draw comes from streams of `seed`.
class Crowd {
 public:
  Crowd(CrowdSite site, CrowdOptions options, std::uint64_t seed);
  ~Crowd();
  Crowd(const Crowd&) = delete;
  Crowd& operator=(const Crowd&) = delete;

  const CrowdOptions& options() const { return options_; }
  // The obstacles changed (a door moved): routes are rebuilt.
  void SetObstacles(std::vector<WallSegment> walls, std::vector<WallCircle> pillars);

  // Advances by dt with the robots as they are now; fills `result` with the
  // forces the crowd exerts on robots over the step.
  void Step(double dt, const std::vector<CrowdRobot>& robots, CrowdStepResult* result);

  double time_s() const { return time_s_; }
  int size() const;  // the pool
  int present() const;
  const PersonState& person(int i) const;
  const std::vector<PersonState>& people() const { return people_; }
  Activity activity(int i) const;
  Behaviour behaviour(int i) const;
  // True while person i wants to walk but a robot stands in the way (within
  // 1 m, the person slower than 0.1 m/s): "visitors blocked by robots".
  bool blocked_by_robot(int i) const;
  // Arrivals that entered so far, and those who had to wait for room.
  std::int64_t arrivals() const;
  std::int64_t departures() const;
  // Pushes and kicks begun on robots so far.
  std::int64_t pushes() const;
  // Largest overlap of bodies with each other, walls or robots in the last step (m).
  double max_overlap_m() const;
  // The same by what was overlapped: another person, a wall or exhibit, a robot.
  std::array<double, 3> max_overlaps_m() const;
  // Episodes near robots begun so far, by behaviour (index: Behaviour).
  const std::array<std::int64_t, 6>& episodes() const;

  // Puts a group of `count` visitors at `position` now (a burst of arrivals:
  // the scenario timeline's spawn_group). Returns how many found a body and room.
  int SpawnGroup(const Eigen::Vector2d& position_m, int count);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  CrowdOptions options_;
  std::vector<PersonState> people_;
  double time_s_ = 0.0;
};

}  // namespace pavilion::sim::crowd
