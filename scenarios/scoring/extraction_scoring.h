#pragma once

// Scoring of extracted lines against simulation ground truth (docs/metrics.md,
// "Feature extraction"; the two rates of Nguyen et al., IROS 2005).
//
// Ground truth. Every segment of the world's section at beam height is a wall
// face; collinear faces (possibly of different elements) lie on one infinite
// line. A wall's visible part is what this scan actually saw: the
// runs of consecutive readings whose truth element is one of its faces'
// elements and whose true hit point lies on that face (within
// on_face_tolerance_m); runs of one infinite line separated by more than
// max_gap_m along it are separate walls. A wall is "in view" when its visible length, counting
// only readings within max_distance_m, is at least min_visible_length_m. Each
// wall is expressed as a line (alpha, r >= 0) in the sensor frame of the scan's
// first reading (the true pose; fine for a static robot).
//
// Matching. An extracted segment matches a line when |delta alpha| <=
// max_alpha_error_rad, |delta r| <= max_r_error_m and at least
// min_overlap_fraction of its length (its endpoints projected onto the true
// line) overlaps the visible part of that line, i.e. of all walls on it (the
// extractor fuses collinear pieces across doors and shadows into one segment).
// Segments are matched against every seen line, walls in view or not (a line
// on a short or distant wall is no false positive); of several candidates the
// smallest chi^2 distance wins. A wall is found when the segments matching its
// line cover min_overlap_fraction of its visible part. True-positive rate =
// walls in view found / walls in view; false-positive rate = segments matching
// nothing / segments. Errors (delta alpha, delta r) are extracted minus true,
// collected over all matches, with their squared Mahalanobis distance under the
// extracted line's covariance (inside the 95% gate when <= chi^2_2(0.95)).

#include <Eigen/Core>
#include <vector>

#include "core/features/uncertain_geometry.h"
#include "core/geometry/planar_section.h"
#include "core/types/sensor_data.h"

namespace pavilion::scenarios {

struct ExtractionScoringOptions {
  double max_alpha_error_rad = 0.034906585039886591;  // 2 deg
  double max_r_error_m = 0.05;
  double min_overlap_fraction = 0.5;
  double min_visible_length_m = 1.0;  // walls in view: visible length >= this ...
  double max_distance_m = 6.0;        // ... counting readings with true range <= this
  double on_face_tolerance_m = 0.03;  // true hit point within this of the face
  // Visible runs of one infinite line closer than this along it are one wall
  // (a shadow of a visitor near the wall); farther apart (door openings, long
  // shadows) they are separate walls.
  double max_gap_m = 0.5;
  // Faces lie on one infinite line when their lines differ by less than these.
  double collinear_alpha_rad = 0.0017453292519943296;  // 0.1 deg
  double collinear_r_m = 0.005;
  double gate = 5.991464547107979;  // chi^2_2(0.95)
  // Diagnostic, not metrics.md: true counts a segment's overlap with the whole
  // span of its line's visible parts, gaps (occlusions, doors) included.
  bool bridge_gaps = false;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// A true wall seen in one scan, in the sensor frame of the scan's first reading.
struct TrueWall {
  std::vector<int> faces;  // indices into PlanarSection::segments
  core::Line line;         // r >= 0, zero covariance
  // Visible part: intervals of the coordinate t along the wall's direction
  // (-sin alpha, cos alpha), t = 0 at the foot of the perpendicular.
  std::vector<Eigen::Vector2d> visible_t_m;
  double visible_length_m = 0.0;           // sum of the intervals
  double visible_length_in_range_m = 0.0;  // same, readings within max_distance_m only
  int readings = 0;                        // readings on the wall
  bool in_view = false;                    // counts in the true-positive rate
  // Every face answers as the sensor model of the extraction assumes (normal or
  // retro-reflective surface, range noise sigma_rho); false for dark and
  // specular surfaces, whose returns the thesis found outside its model
  // (§3.2.4, fig. 3.6: black velvet, "true standard deviation visibly greater").
  bool modelled_surface = true;
  int group = 0;                  // walls on one infinite line share a group
  int matched_segments = 0;       // segments matching this wall's line
  double covered_length_m = 0.0;  // visible part covered by matching segments
  bool found = false;             // covered_length_m >= min_overlap_fraction * visible
};

struct ExtractionMatch {
  int segment = -1;              // index into the extracted segments
  int wall = -1;                 // the wall on the matched line it overlaps most
  double delta_alpha_rad = 0.0;  // extracted - true, wrapped to (-pi, pi]
  double delta_r_m = 0.0;
  double mahalanobis2 = 0.0;  // e^T C^-1 e, C the extracted line's covariance
  bool in_gate = false;       // mahalanobis2 <= gate
  double overlap_fraction = 0.0;
};

// The score of one scan.
struct ExtractionScore {
  std::vector<TrueWall> walls;       // every wall seen, in view or not
  std::vector<int> wall_of_segment;  // per extracted segment, -1 when unmatched
  std::vector<ExtractionMatch> matches;
  int walls_in_view = 0;
  int walls_found = 0;             // in view and matched
  int modelled_walls_in_view = 0;  // the same, walls of modelled surfaces only
  int modelled_walls_found = 0;
  int extracted = 0;
  int false_positives = 0;
};

// Scores `segments` extracted from `scan` (sensor frame) against the section of
// the world at the beam height. Throws std::invalid_argument when truth and
// scan sizes differ or the options are invalid.
ExtractionScore ScoreExtraction(const core::LaserScan& scan, const core::LaserScanTruth& truth,
                                const core::PlanarSection& section,
                                const std::vector<core::Segment>& segments,
                                const ExtractionScoringOptions& options = {});

// Aggregate figures over scans (metrics.md).
struct ExtractionFigures {
  int scans = 0;
  int walls_in_view = 0;
  int walls_found = 0;
  int modelled_walls_in_view = 0;
  int modelled_walls_found = 0;
  int extracted = 0;
  int false_positives = 0;
  int matches = 0;
  int matches_in_gate = 0;
  double true_positive_rate = 0.0;           // walls_found / walls_in_view (0 when none)
  double modelled_true_positive_rate = 0.0;  // the same over walls of modelled surfaces
  double false_positive_rate = 0.0;          // false_positives / extracted (0 when none)
  double mean_delta_alpha_rad = 0.0;
  double mean_delta_r_m = 0.0;
  double sigma_delta_alpha_rad = 0.0;  // standard deviation over matches
  double sigma_delta_r_m = 0.0;
  double in_gate_fraction = 0.0;  // matches_in_gate / matches (0 when none)
};

class ExtractionScoreAccumulator {
 public:
  void Add(const ExtractionScore& score);
  ExtractionFigures Figures() const;

 private:
  ExtractionFigures totals_;
  double sum_alpha_ = 0.0, sum_alpha2_ = 0.0, sum_r_ = 0.0, sum_r2_ = 0.0;
};

}  // namespace pavilion::scenarios
