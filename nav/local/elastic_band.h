#pragma once

// The elastic band of the path-planning sublayer (thesis §6.3.4; Quinlan &
// Khatib 1993): a chain of bubbles from the robot to the (local) goal,
// initialized by NF1, that "continuously evolves towards a smoother curve"
// at several Hz; when it "snaps", the caller replans. The robot is a circle
// (§6.3.4). A bubble is the free disc of the robot's centre: its radius is
// the clearance (distance to the nearest obstacle point) less the robot
// radius. An internal contraction force and an external repulsion force along
// the distance field's gradient move the bubbles normal to the band; bubbles
// are inserted where neighbours stop overlapping and deleted where redundant.

#include <Eigen/Core>
#include <vector>

#include "nav/local/distance_field.h"

namespace pavilion::nav {

struct ElasticBandOptions {
  double robot_radius_m = 0.4;       // the circle planned for, m, (0, 2]
  double clearance_margin_m = 0.05;  // the band keeps robot_radius_m + this clearance, m, [0, 1]
  double repulsion_range_m = 0.2;    // repulsion acts below min clearance + this, m, (0, 2]
  double contraction_gain = 1.0;     // weight of the tension (sum of unit vectors), (0, 10]
  // Weight of the repulsion per m of intrusion, 1/m, (0, 1000]; with
  // step_gain * gain * (margin + range) < 1 the repulsion step never
  // overshoots the intrusion (bubbles there are at most margin + range big).
  double repulsion_gain_per_m = 4.0;
  double step_gain = 0.5;            // displacement per unit force, in bubble radii, (0, 1]
  int iterations = 4;                // relaxation sweeps per Update, [1, 100]
  double max_bubble_radius_m = 1.0;  // bubble radii are capped here, m, (0, 5]
  // Radius floor for spacing and steps: bubbles at the robot radius still
  // connect, the segment between them then clears it to within this, m, (0, 0.5].
  double min_bubble_radius_m = 0.025;
  // Neighbours connect when their centres are at most this fraction of their
  // radii's sum apart (Q&K's overlap), (0, 1).
  double overlap_fraction = 0.7;
  // A bubble is deleted when its two neighbours are this close, (0, overlap_fraction).
  double redundant_fraction = 0.35;
  int max_bubbles = 200;  // a band needing more snaps, [3, 100000]

  double min_clearance_m() const { return robot_radius_m + clearance_margin_m; }
  void Validate() const;  // throws std::invalid_argument naming the field
};

struct Bubble {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();  // world frame
  double radius_m = 0.0;  // clearance_m - robot radius, capped at max_bubble_radius_m (< 0 inside)
  double clearance_m = 0.0;  // distance to the nearest obstacle point (capped by the field)
};

class ElasticBand {
 public:
  explicit ElasticBand(const ElasticBandOptions& options = {});

  // Starts a band on `initial_path` (world frame, robot first, goal last, at
  // least two points; fewer leave the band empty). The first Update places
  // the bubbles along it.
  void Reset(std::vector<Eigen::Vector2d> initial_path);

  // One update (5 Hz): the first bubble moves to the robot, bubbles the robot
  // has passed are dropped, `iterations` relaxation sweeps move the internal
  // bubbles, then bubbles are inserted and deleted; the goal stays fixed.
  // False when the band snaps: an internal bubble's clearance is below the
  // robot radius, a gap cannot be bridged (the bubble inserted there would be
  // below it), more than max_bubbles would be needed, or the band is empty.
  // The robot's and the goal's bubbles are exempt from the clearance test (the
  // robot may already graze; NF1's goal cell clears to within half a cell).
  // After a snap the bubbles are left as they were; Reset to go on.
  // The field's cap must exceed min clearance + repulsion range.
  bool Update(const Eigen::Vector2d& robot_position, const DistanceField& field);

  const std::vector<Bubble>& bubbles() const { return bubbles_; }
  std::vector<Eigen::Vector2d> path() const;
  double length_m() const;
  // The point `distance_m` along the band from its first bubble (the robot);
  // the goal beyond the end; zero for an empty band.
  Eigen::Vector2d TargetAhead(double distance_m) const;

  const ElasticBandOptions& options() const { return options_; }

 private:
  Bubble MakeBubble(const Eigen::Vector2d& center, const DistanceField& field) const;
  // Radius used for spacing and steps (floored at min_bubble_radius_m).
  double SpacingRadius(const Bubble& bubble) const;
  bool Connected(const Bubble& a, const Bubble& b, double fraction) const;
  // Bubbles along the initial path, spaced so neighbours connect.
  void PlaceAlongPath(const DistanceField& field);
  void DropPassed();
  void Relax(const DistanceField& field);
  void MoveBubble(std::size_t i, const DistanceField& field);
  // Inserts bubbles into gaps, then deletes redundant ones; false on snap.
  bool Maintain(const DistanceField& field);

  ElasticBandOptions options_;
  std::vector<Eigen::Vector2d> initial_path_;  // pending until the first Update
  std::vector<Bubble> bubbles_;
  std::vector<Bubble> scratch_;  // reused by Maintain
  std::vector<Bubble> pending_;  // reused by Maintain
};

}  // namespace pavilion::nav
