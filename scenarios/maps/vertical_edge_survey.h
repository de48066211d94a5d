#pragma once

// Vertical edges for the a-priori map (thesis §4.2, Fig. 4.2: "crosses
// indicate vertical edges"; §B.2 point features): the vertical corners of the
// world's static solids that a camera sees as vertical edges (§3.4) — wall
// corners and ends (door frames among them), the corners of pillars, exhibits
// and furniture — taken from the world's geometry as truth.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "sim/world/world.h"

namespace pavilion::scenarios {

struct VerticalEdgeSurveyOptions {
  // A corner is a vertical edge when the solid's outline turns there by at
  // least this angle (a face meeting another of a different orientation,
  // which light shades differently), rad, (0, pi).
  double min_turn_rad = 0.35;  // 20 deg
  // ... and when it is a corner of the same element at both heights: the
  // edge spans at least [low_m, high_m], the band a camera at about 0.6 m
  // sees over the ranges the edges are extracted at (Pygmalion's camera:
  // 0.62 m, robots/pygmalion/robot.urdf). m, 0 < low_m < high_m <= 10.
  double low_m = 0.3;
  double high_m = 1.2;
  // Probe distance outside the corner: a corner with a solid this close
  // along its outward bisector is buried (a wall's end inside another wall),
  // m, (0, 0.5].
  double probe_m = 0.02;
  // Doors' leaves in the state the surveyor found them (an open door's leaf
  // stands beside its frame: its edges are the frame's closest neighbours in
  // an image, §4.5.2.1); false: frames only, as if every door could move.
  bool doors = true;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// A vertical edge found in the world: where it stands, the direction from
// which it is seen (the outward bisector of its corner, unit), and the
// element it belongs to.
struct SurveyedEdge {
  Eigen::Vector2d position_m;
  Eigen::Vector2d outward;
  std::string element;
};

// The vertical edges of the static solids (walls, boxes, meshes, doors'
// leaves as surveyed unless options.doors is false; no cylinders, whose
// silhouette moves with the viewer), in a deterministic
// order (by element, then along its outline). Laser-transparent elements
// count: a camera sees glass frames.
std::vector<SurveyedEdge> SurveyVerticalEdges(const sim::World& world,
                                              const VerticalEdgeSurveyOptions& options);

}  // namespace pavilion::scenarios
