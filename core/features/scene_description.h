#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/features/beacon_extraction.h"
#include "core/features/uncertain_geometry.h"

namespace pavilion::core {

// Options of the scene description (thesis §3.5).
struct SceneOptions {
  // Scan direction of the sensor; the segments are given in scan order. s_i is
  // the line normal rotated by +pi/2 for counterclockwise, -pi/2 for clockwise
  // scanning (eq. 3.24).
  bool counterclockwise = true;
  // R_S, the perception radius of the sensor (eq. 3.33), m; > 0.
  double perception_radius_m = 8.0;
  // w_r, a constant reflecting the size of the robot (eqs. 3.31, 3.34), m; >= 0.
  double robot_size_m = 0.5;
  // alpha of the chi^2(2) test (eq. 3.16) deciding l_Si = l_Si+1 (eq. 3.31); in (0, 1).
  double significance = 0.99;
  // Also classify the pair (last segment, first segment): for a 360-degree scan
  // the string is cyclic (fig. 3.11, "HeccO" from five segments).
  bool closed = false;
  // Insert a 'B' for every beacon in angular order (an extension: the thesis'
  // alphabet has no beacon symbol, but "different features can naturally be
  // included since only angular landmark succession is important", §3.5).
  bool include_beacons = true;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// One symbol of the scene string.
struct SceneSymbol {
  // 'G' gap, 'H' hidden corner, 'O' opening, 'A' aperture, 'c' concave corner,
  // 'e' convex corner (eqs. 3.31-3.36); 'B' beacon (extension, see SceneOptions).
  char symbol = '?';
  // Determinant of the covariance that the weight rule selects: max(|C_li|,
  // |C_li+1|) (eq. 3.37), |C_li| for gaps (eq. 3.38), |C_b| (polar, eq. 3.22)
  // for beacons. A probability mass: larger means less confident.
  double determinant = 0.0;
  // w_i, the confidence used in eqs. 3.39-3.40: 1 / determinant (see the .cc
  // for this reading of eq. 3.37). Larger means more confident.
  double weight = 0.0;
  // v_i, unit vector from the sensor to the symbol: towards C_i,i+1 for
  // corners, towards the midpoint of E_i E_i+1 for G, H, O, A, towards the
  // beacon for B.
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();
  Eigen::Vector2d location_m = Eigen::Vector2d::Zero();  // the point v_i points to
  // Intersection C_i,i+1 of the supporting lines (eq. 3.26); not finite for
  // (anti)parallel lines and gaps.
  Eigen::Vector2d intersection_m = Eigen::Vector2d::Zero();
  double lambda_first = 0.0;   // lambda_Ei (eq. 3.24), 0 when not used
  double lambda_second = 0.0;  // lambda_Ei+1
  int first_segment = -1;      // S_i, index into the input segments
  int second_segment = -1;     // S_i+1
  int beacon = -1;             // index into the input beacons for 'B'
};

struct SceneDescription {
  std::string symbols;                // the string, one char per element
  std::vector<SceneSymbol> elements;  // same order as `symbols`
  // v_h = sum(w_i v_i) / sum(w_i) (eq. 3.39): towards the confident features.
  Eigen::Vector2d highest_confidence = Eigen::Vector2d::Zero();
  // v_l = sum(v_i / w_i) / sum(1 / w_i) (eq. 3.40): towards the uncertain ones.
  Eigen::Vector2d least_confidence = Eigen::Vector2d::Zero();

  // The string, then one line per symbol with its normalized weight
  // w_i / sum(w_j), bearing and determinant, then v_h and v_l.
  std::string ToString() const;
};

// The weighted symbol string of §3.5 from segments in scan order (as
// ExtractLines returns them, sensor frame) and beacons: every adjacent pair
// (S_i, S_i+1) is classified by eqs. 3.24-3.36, weighted by eqs. 3.37-3.38,
// and the vectors of highest and least confidence follow from 3.39-3.40.
SceneDescription DescribeScene(const std::vector<Segment>& segments,
                               const std::vector<Beacon>& beacons, const SceneOptions& options);

}  // namespace pavilion::core
