#pragma once

// The reactive sublayer of thesis §6.3.4: the dynamic window approach (Fox,
// Burgard & Thrun 1997) as modified by Philippsen & Siegwart (2003). The
// objective trading heading, speed and clearance is evaluated in the actuator
// space (v_l, v_r) of a differential drive with acceleration limits, for an
// arbitrary convex polygonal robot, with time to collision (not distance) as
// the clearance measure and every laser reading and ghost point within reach
// as an obstacle point. One Choose() per 10 Hz deadline cycle; the clearance
// comes from a look-up table (collision_table.h).
//
// Model: a candidate is held for one period, then both wheels brake
// proportionally at the acceleration limit, so the robot stops on the same
// arc. The transient from the current speeds to the candidate (reached within
// the period by the 1 kHz speed controller) is not modelled, as in Fox et al.

#include <Eigen/Core>
#include <span>
#include <vector>

#include "core/geometry/polygon.h"
#include "nav/reactive/collision_table.h"

namespace pavilion::nav {

// How the arc to collision of a candidate is found.
enum class ClearanceGeometry {
  kLookupTable,  // the table per direction bin; the chosen candidate confirmed exactly
  kExact,        // ExactTimeToCollision for every candidate and point (the baseline)
};

struct DynamicWindowOptions {
  double period_s = 0.1;              // cycle T, s, (0, 1]; the 10 Hz task of §6.3.4
  int samples_per_wheel = 11;         // grid samples per wheel, odd, [11, 101]
  double wheelbase_m = 0.504;         // b, m, (0, 5] (Robox: robots/robox/robot.yaml)
  double max_wheel_speed_mps = 0.8;   // rim speed limit, m/s, (0, 5]
  double max_wheel_accel_mps2 = 1.0;  // rim acceleration and braking, m/s², (0, 20]
  double max_speed_mps = 0.6;         // translation limit, m/s, (0, max_wheel_speed_mps]; Expo.02
  double ttc_horizon_s = 3.0;         // time to collision saturates here, s, (0, 60]
  double safety_margin_m = 0.02;      // the robot polygon grown by this, m, [0, 0.5]
  double lookahead_m = 1.2;           // clearance reach (generalized arc), m, (0, 10];
                                      // >= the braking reach of every candidate
  double table_cell_m = 0.025;        // look-up table cell, m, [0.005, 0.2]
  int table_direction_bins = 64;      // look-up table directions, multiple of 4, [8, 1024]
  // Objective weights, >= 0, not all 0 (the thesis gives none; chosen so the
  // heading dominates, speed keeps the robot moving, clearance breaks ties).
  double weight_heading = 1.0;
  double weight_speed = 0.5;
  double weight_clearance = 0.3;
  double goal_tolerance_m = 0.01;            // pose mode: position reached, m, (0, 1]
  double goal_heading_tolerance_rad = 0.01;  // pose mode: heading reached, rad, (0, 0.5]
  ClearanceGeometry clearance_geometry = ClearanceGeometry::kLookupTable;

  void Validate() const;  // throws std::invalid_argument naming the field
  CollisionTableOptions TableOptions() const;
};

// Rim speeds of the left and right wheel, m/s.
struct WheelVelocity {
  double left_mps = 0.0;
  double right_mps = 0.0;
};

// What the cycle steers to, in the robot frame now.
struct DwaGoal {
  // Position-only mode: a point ahead on the elastic band or a via node (§6.3.3).
  Eigen::Vector2d target_in_robot = Eigen::Vector2d::Zero();
  // Pose mode (the last node, §6.3.3): reach goal_in_robot, then turn on the
  // spot to goal_heading_in_robot_rad.
  bool pose_goal = false;
  Eigen::Vector2d goal_in_robot = Eigen::Vector2d::Zero();
  double goal_heading_in_robot_rad = 0.0;
  // The caller's translation limit, m/s, >= 0 (e.g. slower near the goal).
  double speed_limit_mps = 1e9;
};

struct DwaResult {
  WheelVelocity command;
  // Time to collision of the command at constant speed, s (the table's
  // conservative value; ttc_horizon_s or more when nothing is within reach).
  double time_to_collision_s = 0.0;
  // False: the command is the hardest proportional braking towards stop —
  // no candidate was admissible, or in_collision, or goal_reached.
  bool admissible_found = false;
  bool in_collision = false;      // a point is inside the robot polygon now
  bool goal_reached = false;      // pose mode: within both tolerances; braking
  int candidates_evaluated = 0;   // grid candidates considered (samples_per_wheel²)
  int candidates_admissible = 0;  // of those, within limits and admissible
  int points_in_reach = 0;        // obstacle points within the window's reach
  int exact_rejections = 0;       // table winners the exact geometry rejected
};

class DynamicWindow {
 public:
  // `robot_polygon` in the robot frame (x forward, y left), counter-clockwise,
  // convex, from the robot file. Builds the look-up table (tens of ms).
  DynamicWindow(const DynamicWindowOptions& options, core::Polygon2 robot_polygon);

  // One cycle: the best admissible wheel speeds within one period's
  // acceleration of `current`. Deterministic (fixed order, no RNG, no threads).
  DwaResult Choose(const WheelVelocity& current,
                   std::span<const Eigen::Vector2d> obstacles_in_robot, const DwaGoal& goal);

  // Positions (robot frame now) along the chosen command held for duration_s,
  // every kArcStep_s and at the end, for drawing.
  std::vector<Eigen::Vector2d> ChosenArc(const DwaResult& result, double duration_s) const;

  // Generalized arc (m, collision_table.h) from now to standstill when the
  // command is held one period and then braked proportionally.
  double StoppingArc(const WheelVelocity& command) const;

  const DynamicWindowOptions& options() const { return options_; }
  const core::Polygon2& robot_polygon() const { return robot_polygon_; }
  const CollisionTable& table() const { return table_; }

  static constexpr double kArcStep_s = 0.05;

 private:
  // One grid point of the window and its evaluation.
  struct Candidate {
    WheelVelocity wheels;
    BodyTwist twist;
    double speed_g = 0.0;     // generalized speed σ (collision_table.h)
    double stop_arc_m = 0.0;  // StoppingArc
    int bin = 0;
    bool within_limits = false;
    bool admissible = false;
    double arc_to_collision_m = 0.0;
    double ttc_s = 0.0;
    double score = 0.0;
  };
  // What one cycle derives from the goal and the current speeds.
  struct Scene {
    double speed_cap_mps = 0.0;    // effective translation cap
    double turn_cap_radps = 0.0;   // effective rotation cap
    double goal_distance_m = 0.0;  // pose mode: |goal_in_robot|
    bool orienting = false;        // pose mode, at the position: turn on the spot
    double reach_arc_m = 0.0;      // the largest generalized arc that matters
  };

  void GatherPoints(std::span<const Eigen::Vector2d> obstacles, double reach_m);
  void BuildCandidates(const WheelVelocity& current, const DwaGoal& goal, Scene& scene);
  void ScoreCandidates(const DwaGoal& goal, const Scene& scene);
  bool ConfirmExact(const Candidate& candidate) const;
  double ExactArc(const BodyTwist& twist, double up_to_m) const;
  WheelVelocity BrakeCommand(const WheelVelocity& current) const;
  double Objective(const Candidate& c, const DwaGoal& goal, const Scene& scene) const;

  DynamicWindowOptions options_;
  core::Polygon2 robot_polygon_;
  core::Polygon2 margin_polygon_;  // grown by safety_margin_m
  CollisionTable table_;
  // Per-cycle scratch, kept to avoid allocation in the deadline task.
  std::vector<Eigen::Vector2d> points_;
  std::vector<int> cells_;
  std::vector<Candidate> candidates_;
  std::vector<double> bin_arc_m_;
};

}  // namespace pavilion::nav
