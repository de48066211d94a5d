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
//
// Admissibility (Fox et al. 1997: the robot can stop before it collides):
// - far points, outside the safety-margin polygon grown by one table cell
//   diagonal: the table's time to collision with the margin polygon (the
//   winner confirmed exactly) exceeds the stopping arc;
// - band points, outside the margin polygon but within a cell diagonal of it
//   (where the table's grown cells would report contact in every direction):
//   the same test with ExactTimeToCollision on the margin polygon;
// - contact points, inside the margin polygon, on or up to
//   max_contact_depth_m inside the robot polygon (a walker touching the
//   robot, a wall after a push): escape motions only. The signed distance to
//   the exact polygon must not decrease at t = 0+ faster than sliding along
//   the contact allows (contact normal · point velocity >= -sin 2° · |point
//   velocity|: a mesh hull's side is facets a degree apart, and a strict
//   test there froze a robot pressed along its side), and the exact polygon
//   offset to pass kContactSlack_m
//   inside the point must not reach it before standstill, so no contact
//   point gets more than kContactSlack_m deeper. In their presence the
//   clearance term scores the first-order growth of the clearance over a
//   period (stopping scores 0) and reversing is not penalised, so the robot
//   backs or turns away rather than waits.
// A point deeper than max_contact_depth_m inside the robot forces braking.

#include <Eigen/Core>
#include <cstdint>
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
  // Turn rate limit, rad/s, (0, 20]: the travel limit alone lets the wheels
  // spin the robot at 2 v_wheel / b, which swept a square robot's corners into
  // a door post faster than it could brake (issue 14, office_errands).
  double max_turn_rate_radps = 1.0;
  // Position-only mode judges the heading where a candidate leads in this
  // time, s, [period_s, 10].
  double heading_horizon_s = 1.0;
  double ttc_horizon_s = 3.0;         // time to collision saturates here, s, (0, 60]
  double safety_margin_m = 0.02;      // the robot polygon grown by this, m, [0, 0.5]
  double lookahead_m = 1.2;           // clearance reach (generalized arc), m, (0, 10];
                                      // >= the braking reach of every candidate
  double table_cell_m = 0.025;        // look-up table cell, m, [0.005, 0.2]
  double max_contact_depth_m = 0.02;  // deepest contact the robot may escape, m, [0, 0.1];
                                      // must leave the robot polygon shrunk by it convex
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

// The speed controller's step (§6.3.4: below the 10 Hz window a 1 kHz speed
// controller): `from` moved towards `to` by at most `max_step_mps` on either
// wheel, both wheels in proportion (the straight segment between the two in
// (v_l, v_r)). Sent as steps, a robot's motors take each new command at their
// own torque limit (2.7 m/s² of rim for Robox, against the window's 1 m/s²),
// and a stop commanded outside the window (a mission's end, a loss) comes at
// that limit: the 115 kg body skidded round on its wheels, its heading off by
// up to 3° in half a second where the calibrated odometry allows 0.3°, and the
// EKF then failed its gates six cycles running — a false loss (expo_day,
// docs/navigation.md).
WheelVelocity RampTowards(const WheelVelocity& from, const WheelVelocity& to, double max_step_mps);

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
  // Position-only mode: drive backwards, the robot's rear judged as its
  // front for heading and speed (backing out of a pocket it cannot turn in).
  bool reverse = false;
  // Judge every candidate against the exact swept polygon, as
  // ClearanceGeometry::kExact does, for this cycle. The table's cells make
  // it a cell diagonal more cautious beside the robot: in a gap a few
  // centimetres wider than the robot no motion but a crawl is admissible.
  // Costlier (tens of times the table); for rare cycles such as an escape.
  bool exact_clearance = false;
  // The safety margin for this cycle, m, in [0, options' safety_margin_m];
  // negative: the options'. Needs exact_clearance (the table is built for
  // the options' margin). For an escape's creep: where a point lies within
  // the margin beside a vertex of the outline that the drive can only move
  // along the robot's axis (a wheel hub on the wheel axis), every motion
  // brings it nearer, the contact rules admit none, and the robot stands
  // for good (Pygmalion askew in a 0.9 m door, computer2000 seed 1).
  double margin_m = -1.0;
  // How much deeper (m) a contact point may get before standstill, in
  // [0, kMaxContactSlack_m]; negative: kContactSlack_m, with the first-order
  // sliding test. Set, the sliding test is waived and this bound alone
  // holds. For an escape's creep: a wheel hub's round side pressed on a door
  // post's corner, the corner's points on both sides of the wheel axis, is
  // made deeper by every motion the drive allows (the hub moves only along
  // the robot's axis), by about a millimetre while it passes; Pygmalion stood
  // so for 18 hours (computer2000, seed 1 at the slip re-match, office_09's
  // door with a suitcase it had pushed in beside it).
  double contact_slack_m = -1.0;
};

struct DwaResult {
  WheelVelocity command;
  // Time to collision of the command at constant speed, s (the table's
  // conservative value; ttc_horizon_s or more when nothing is within reach).
  double time_to_collision_s = 0.0;
  // False: the command is the hardest proportional braking towards stop —
  // no candidate was admissible, or a point is deeper inside the robot than
  // max_contact_depth_m, or goal_reached.
  bool admissible_found = false;
  // A point is inside the robot polygon now; escape motions stay admissible
  // while every such point is within max_contact_depth_m of the boundary.
  bool in_collision = false;
  bool goal_reached = false;     // pose mode: within both tolerances; braking
  int candidates_evaluated = 0;  // grid candidates considered (samples_per_wheel²)
  // Of those, within limits and admissible against the contact rules and the
  // far points; the band and contact points are judged best candidate first,
  // only until the winner is known.
  int candidates_admissible = 0;
  int points_in_reach = 0;   // obstacle points within the window's reach
  int contact_points = 0;    // of those, inside the margin polygon (escape only)
  int band_points = 0;       // of those, judged exactly with the margin polygon
  int exact_rejections = 0;  // table winners the exact geometry rejected
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
  const CollisionTable& table() const { return *table_; }

  static constexpr double kArcStep_s = 0.05;
  // How much deeper (m) a contact point may get before standstill: room for
  // the second-order approach of motions that leave it tangentially.
  static constexpr double kContactSlack_m = 2.5e-4;
  static constexpr double kMaxContactSlack_m = 0.005;  // DwaGoal::contact_slack_m's bound

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
    double escape_gain_m = 0.0;  // first-order clearance growth over one period
    double score = 0.0;          // an upper bound until near_checked
    bool near_checked = false;   // the band and contact points judged (NearArc)
  };
  // A point inside the margin polygon and its escape constraint.
  struct ContactPoint {
    Eigen::Vector2d point;
    Eigen::Vector2d normal;   // outward contact normal of the robot polygon
    double distance_m = 0.0;  // signed distance to the robot polygon
    int polygon = 0;          // index in contact_polygons_: offset to pass inside the point
  };
  // What one cycle derives from the goal and the current speeds.
  struct Scene {
    double speed_cap_mps = 0.0;    // effective translation cap
    double turn_cap_radps = 0.0;   // effective rotation cap
    double goal_distance_m = 0.0;  // pose mode: |goal_in_robot|
    bool orienting = false;        // pose mode, at the position: turn on the spot
    double reach_arc_m = 0.0;      // the largest generalized arc that matters
    bool use_table = true;         // the table judges the far points (else exact)
  };

  // Sorts the points within reach into far, band and contact points; false
  // when one is deeper inside the robot than max_contact_depth_m.
  bool GatherPoints(std::span<const Eigen::Vector2d> obstacles, double reach_m);
  void AddContact(const Eigen::Vector2d& point, double edge_distance_m);
  // Mitred signed distance: the largest distance outside an edge's line (m).
  double EdgeDistance(const Eigen::Vector2d& point) const;
  bool RecedesFromContacts(Candidate& c) const;
  // The arc to collision, at most `arc_m`, with the band and contact points.
  double NearArc(const Candidate& c, double arc_m) const;
  // Admissible against the contact rules and the far points (table or
  // exact); the band and contact points are left to CheckNear.
  bool Admissible(Candidate& c, const Scene& scene);
  // Lowers the arc by the band and contact points; rescores or drops `c`.
  void CheckNear(Candidate& c, const DwaGoal& goal, const Scene& scene);
  void BuildCandidates(const WheelVelocity& current, const DwaGoal& goal, Scene& scene);
  void ScoreCandidates(const DwaGoal& goal, const Scene& scene);
  bool ConfirmExact(const Candidate& candidate) const;
  double ExactArc(const BodyTwist& twist, double up_to_m) const;
  WheelVelocity BrakeCommand(const WheelVelocity& current) const;
  double Objective(const Candidate& c, const DwaGoal& goal, const Scene& scene) const;

  DynamicWindowOptions options_;
  core::Polygon2 robot_polygon_;
  core::Polygon2 margin_polygon_;  // grown by safety_margin_m
  // This cycle's margin (DwaGoal::margin_m or the options') and whether its
  // polygon is reduced_polygon_ (grown by reduced_margin_m_) rather than
  // margin_polygon_.
  double cycle_margin_m_ = 0.0;
  bool cycle_reduced_ = false;
  // This cycle's contact slack and whether the sliding test is waived (DwaGoal::contact_slack_m).
  double cycle_contact_slack_m_ = kContactSlack_m;
  bool cycle_slide_waived_ = false;
  double reduced_margin_m_ = -1.0;
  core::Polygon2 reduced_polygon_;
  const core::Polygon2& CyclePolygon() const {
    return cycle_reduced_ ? reduced_polygon_ : margin_polygon_;
  }
  // Shared with every dynamic window of the same robot polygon and table
  // options (SharedCollisionTable): immutable.
  std::shared_ptr<const CollisionTable> table_;
  std::vector<Eigen::Vector2d> edge_normals_;  // outward unit normals of robot_polygon_
  std::vector<double> edge_offsets_;           // normal · vertex per edge (m)
  core::Polygon2 miter_;                       // vertex motion per metre of mitred offset
  double near_offset_m_ = 0.0;                 // margin + table cell diagonal (m)
  double near_radius_m_ = 0.0;                 // circumradius of that offset polygon (m)
  // Per-cycle scratch, kept to avoid allocation in the deadline task.
  std::vector<Eigen::Vector2d> points_;  // far points (the table's)
  std::vector<Eigen::Vector2d> band_points_;
  std::vector<ContactPoint> contacts_;
  std::vector<core::Polygon2> contact_polygons_;
  double nearest_contact_m_ = 0.0;         // the clearance: least contact distance (m)
  std::vector<int> cells_;                 // the far points' table cells, each once
  std::vector<std::uint32_t> cell_stamp_;  // per table cell: the cycle it was last added
  std::uint32_t stamp_ = 0;
  std::vector<Candidate> candidates_;
  std::vector<double> bin_arc_m_;
};

}  // namespace pavilion::nav
