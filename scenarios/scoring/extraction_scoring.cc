#include "scenarios/scoring/extraction_scoring.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/types/pose2.h"

namespace pavilion::scenarios {
namespace {

void Require(bool ok, const char* field) {
  if (!ok) throw std::invalid_argument(std::string("ExtractionScoringOptions: invalid ") + field);
}

// The line through a and b with r >= 0 (sensor frame).
core::Line LineThrough(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = (b - a).normalized();
  Eigen::Vector2d n(d.y(), -d.x());
  double r = n.dot(a);
  if (r < 0.0) {
    n = -n;
    r = -r;
  }
  core::Line line;
  line.alpha_rad = std::atan2(n.y(), n.x());
  line.r_m = r;
  return line;
}

// Coordinate along the line's direction (-sin alpha, cos alpha).
double AlongLine(const core::Line& line, const Eigen::Vector2d& p) {
  return -std::sin(line.alpha_rad) * p.x() + std::cos(line.alpha_rad) * p.y();
}

double DistanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                         const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

// Length of [lo, hi] inside the intervals.
double Overlap(const std::vector<Eigen::Vector2d>& intervals, double lo, double hi) {
  double overlap = 0.0;
  for (const Eigen::Vector2d& iv : intervals) {
    overlap += std::max(0.0, std::min(hi, iv.y()) - std::max(lo, iv.x()));
  }
  return overlap;
}

// A run of consecutive readings on one group of collinear faces.
struct Run {
  int group = -1;
  double lo = 0.0;
  double hi = 0.0;
  int readings = 0;
  bool in_range = false;  // a run of readings within max_distance_m (subset of a full run)
};

}  // namespace

void ExtractionScoringOptions::Validate() const {
  Require(max_alpha_error_rad > 0.0 && max_alpha_error_rad < std::numbers::pi,
          "max_alpha_error_rad");
  Require(max_r_error_m > 0.0, "max_r_error_m");
  Require(min_overlap_fraction >= 0.0 && min_overlap_fraction <= 1.0, "min_overlap_fraction");
  Require(min_visible_length_m >= 0.0, "min_visible_length_m");
  Require(max_distance_m > 0.0, "max_distance_m");
  Require(on_face_tolerance_m > 0.0, "on_face_tolerance_m");
  Require(max_gap_m >= 0.0, "max_gap_m");
  Require(collinear_alpha_rad >= 0.0, "collinear_alpha_rad");
  Require(collinear_r_m >= 0.0, "collinear_r_m");
  Require(gate > 0.0, "gate");
}

ExtractionScore ScoreExtraction(const core::LaserScan& scan, const core::LaserScanTruth& truth,
                                const core::PlanarSection& section,
                                const std::vector<core::Segment>& segments,
                                const ExtractionScoringOptions& options) {
  options.Validate();
  const std::size_t n = scan.readings.size();
  if (truth.world_from_sensor.size() != n || truth.true_range_m.size() != n ||
      truth.element.size() != n) {
    throw std::invalid_argument("ScoreExtraction: truth and scan sizes differ");
  }
  ExtractionScore score;
  score.extracted = static_cast<int>(segments.size());
  score.wall_of_segment.assign(segments.size(), -1);
  if (n == 0) {
    score.false_positives = score.extracted;
    return score;
  }
  const core::Pose2 sensor_from_world = truth.world_from_sensor[0].Inverse();

  // Faces in the sensor frame, grouped into infinite lines.
  const std::size_t faces = section.segments.size();
  std::vector<Eigen::Vector2d> fa(faces), fb(faces);
  std::vector<int> group_of_face(faces, -1);
  std::vector<core::Line> group_lines;
  std::vector<std::vector<int>> group_faces;
  for (std::size_t f = 0; f < faces; ++f) {
    fa[f] = sensor_from_world * section.segments[f].a_m;
    fb[f] = sensor_from_world * section.segments[f].b_m;
    if ((fb[f] - fa[f]).norm() < 1e-9) continue;
    const core::Line line = LineThrough(fa[f], fb[f]);
    int g = -1;
    for (std::size_t k = 0; k < group_lines.size() && g < 0; ++k) {
      if (std::abs(core::NormalizeAngle(line.alpha_rad - group_lines[k].alpha_rad)) <=
              options.collinear_alpha_rad &&
          std::abs(line.r_m - group_lines[k].r_m) <= options.collinear_r_m) {
        g = static_cast<int>(k);
      }
    }
    if (g < 0) {
      g = static_cast<int>(group_lines.size());
      group_lines.push_back(line);
      group_faces.emplace_back();
    }
    group_of_face[f] = g;
    group_faces[g].push_back(static_cast<int>(f));
  }

  // Runs of consecutive readings on one group: all, and within max_distance_m.
  std::vector<Run> runs;
  Run current, current_in_range;
  auto close = [&runs](Run* run) {
    if (run->group >= 0) runs.push_back(*run);
    *run = Run{};
  };
  auto extend = [](Run* run, int group, double t, bool in_range) {
    if (run->group != group) {
      *run = Run{group, t, t, 0, in_range};
    }
    run->lo = std::min(run->lo, t);
    run->hi = std::max(run->hi, t);
    ++run->readings;
  };
  for (std::size_t i = 0; i < n; ++i) {
    const int element = truth.element[i];
    const double range = truth.true_range_m[i];
    int group = -1;
    double t = 0.0;
    if (element >= 0 && range < scan.max_range_m) {
      const double bearing = scan.readings[i].bearing_rad;
      const Eigen::Vector2d in_sensor(range * std::cos(bearing), range * std::sin(bearing));
      const Eigen::Vector2d p = sensor_from_world * (truth.world_from_sensor[i] * in_sensor);
      double best = options.on_face_tolerance_m;
      for (std::size_t f = 0; f < faces; ++f) {
        if (section.segments[f].element != element || group_of_face[f] < 0) continue;
        const double d = DistanceToSegment(p, fa[f], fb[f]);
        if (d <= best) {
          best = d;
          group = group_of_face[f];
        }
      }
      if (group >= 0) t = AlongLine(group_lines[group], p);
    }
    if (group != current.group) close(&current);
    if (group >= 0) extend(&current, group, t, false);
    const bool in_range = group >= 0 && range <= options.max_distance_m;
    if (!in_range || group != current_in_range.group) close(&current_in_range);
    if (in_range) extend(&current_in_range, group, t, true);
  }
  close(&current);
  close(&current_in_range);

  // Walls: per group, the runs' intervals merged across gaps <= max_gap_m.
  for (std::size_t g = 0; g < group_lines.size(); ++g) {
    std::vector<Run> full, near;
    for (const Run& run : runs) {
      if (run.group != static_cast<int>(g)) continue;
      (run.in_range ? near : full).push_back(run);
    }
    if (full.empty()) continue;
    std::sort(full.begin(), full.end(), [](const Run& a, const Run& b) { return a.lo < b.lo; });
    std::size_t k = 0;
    while (k < full.size()) {
      TrueWall wall;
      wall.faces = group_faces[g];
      wall.group = static_cast<int>(g);
      wall.line = group_lines[g];
      double hi = full[k].hi;
      std::size_t j = k;
      for (; j < full.size() && (j == k || full[j].lo - hi <= options.max_gap_m); ++j) {
        wall.visible_t_m.emplace_back(full[j].lo, full[j].hi);
        wall.visible_length_m += full[j].hi - full[j].lo;
        wall.readings += full[j].readings;
        hi = std::max(hi, full[j].hi);
      }
      const double lo = full[k].lo;
      for (const Run& run : near) {
        if (run.lo >= lo && run.hi <= hi) wall.visible_length_in_range_m += run.hi - run.lo;
      }
      wall.in_view = wall.visible_length_in_range_m >= options.min_visible_length_m;
      wall.modelled_surface = std::all_of(wall.faces.begin(), wall.faces.end(), [&](int f) {
        const core::LaserResponse r = section.elements[section.segments[f].element].laser;
        return r == core::LaserResponse::kNormal || r == core::LaserResponse::kRetroReflective;
      });
      if (wall.in_view) ++score.walls_in_view;
      if (wall.in_view && wall.modelled_surface) ++score.modelled_walls_in_view;
      score.walls.push_back(std::move(wall));
      k = j;
    }
  }

  // Matching against infinite lines: the visible parts of all walls on one line.
  std::vector<std::vector<int>> walls_of_group(group_lines.size());
  for (std::size_t w = 0; w < score.walls.size(); ++w) {
    walls_of_group[score.walls[w].group].push_back(static_cast<int>(w));
  }
  std::vector<std::vector<Eigen::Vector2d>> covered(score.walls.size());
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const core::Segment& seg = segments[s];
    ExtractionMatch best;
    double best_m2 = std::numeric_limits<double>::infinity();
    double best_norm = std::numeric_limits<double>::infinity();
    double best_lo = 0.0, best_hi = 0.0;
    for (std::size_t g = 0; g < group_lines.size(); ++g) {
      if (walls_of_group[g].empty()) continue;
      const core::Line& line = group_lines[g];
      const double da = core::NormalizeAngle(seg.line.alpha_rad - line.alpha_rad);
      const double dr = seg.line.r_m - line.r_m;
      if (std::abs(da) > options.max_alpha_error_rad || std::abs(dr) > options.max_r_error_m) {
        continue;
      }
      const double t0 = AlongLine(line, seg.first_endpoint.position_m);
      const double t1 = AlongLine(line, seg.last_endpoint.position_m);
      const double lo = std::min(t0, t1), hi = std::max(t0, t1);
      double overlap = 0.0, wall_overlap = -1.0;
      bool touches = false;
      int wall = -1;
      double hull_lo = std::numeric_limits<double>::infinity(), hull_hi = -hull_lo;
      for (int w : walls_of_group[g]) {
        const double o = Overlap(score.walls[w].visible_t_m, lo, hi);
        overlap += o;
        for (const Eigen::Vector2d& iv : score.walls[w].visible_t_m) {
          hull_lo = std::min(hull_lo, iv.x());
          hull_hi = std::max(hull_hi, iv.y());
        }
        for (const Eigen::Vector2d& iv : score.walls[w].visible_t_m) {
          touches = touches || (lo <= iv.y() && hi >= iv.x());
        }
        if (o > wall_overlap) {
          wall_overlap = o;
          wall = w;
        }
      }
      if (options.bridge_gaps)
        overlap = std::max(0.0, std::min(hi, hull_hi) - std::max(lo, hull_lo));
      const double fraction = hi - lo > 1e-9 ? overlap / (hi - lo) : (touches ? 1.0 : 0.0);
      if (fraction < options.min_overlap_fraction) continue;
      const Eigen::Vector2d e(da, dr);
      double m2 = std::numeric_limits<double>::infinity();
      const Eigen::Matrix2d& c = seg.line.covariance;
      if (c.determinant() > 0.0) m2 = e.dot(c.inverse() * e);
      const double norm =
          std::abs(da) / options.max_alpha_error_rad + std::abs(dr) / options.max_r_error_m;
      if (m2 < best_m2 || (m2 == best_m2 && norm < best_norm)) {
        best_m2 = m2;
        best_norm = norm;
        best.segment = static_cast<int>(s);
        best.wall = wall;
        best.delta_alpha_rad = da;
        best.delta_r_m = dr;
        best.mahalanobis2 = m2;
        best.in_gate = m2 <= options.gate;
        best.overlap_fraction = fraction;
        best_lo = lo;
        best_hi = hi;
      }
    }
    if (best.wall < 0) {
      ++score.false_positives;
      continue;
    }
    score.wall_of_segment[s] = best.wall;
    for (int w : walls_of_group[score.walls[best.wall].group]) {
      ++score.walls[w].matched_segments;
      covered[w].emplace_back(best_lo, best_hi);
    }
    score.matches.push_back(best);
  }

  // A wall is found when the matching segments cover min_overlap_fraction of its
  // visible part.
  for (std::size_t w = 0; w < score.walls.size(); ++w) {
    TrueWall& wall = score.walls[w];
    std::vector<Eigen::Vector2d>& c = covered[w];
    std::sort(c.begin(), c.end(),
              [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() < b.x(); });
    std::vector<Eigen::Vector2d> merged;
    for (const Eigen::Vector2d& iv : c) {
      if (!merged.empty() && iv.x() <= merged.back().y()) {
        merged.back().y() = std::max(merged.back().y(), iv.y());
      } else {
        merged.push_back(iv);
      }
    }
    for (const Eigen::Vector2d& iv : merged) {
      wall.covered_length_m += Overlap(wall.visible_t_m, iv.x(), iv.y());
    }
    wall.found = wall.visible_length_m > 0.0
                     ? wall.covered_length_m >= options.min_overlap_fraction * wall.visible_length_m
                     : wall.matched_segments > 0;
    if (wall.found && wall.in_view) ++score.walls_found;
    if (wall.found && wall.in_view && wall.modelled_surface) ++score.modelled_walls_found;
  }
  return score;
}

void ExtractionScoreAccumulator::Add(const ExtractionScore& score) {
  ++totals_.scans;
  totals_.walls_in_view += score.walls_in_view;
  totals_.walls_found += score.walls_found;
  totals_.modelled_walls_in_view += score.modelled_walls_in_view;
  totals_.modelled_walls_found += score.modelled_walls_found;
  totals_.extracted += score.extracted;
  totals_.false_positives += score.false_positives;
  for (const ExtractionMatch& m : score.matches) {
    ++totals_.matches;
    if (m.in_gate) ++totals_.matches_in_gate;
    sum_alpha_ += m.delta_alpha_rad;
    sum_alpha2_ += m.delta_alpha_rad * m.delta_alpha_rad;
    sum_r_ += m.delta_r_m;
    sum_r2_ += m.delta_r_m * m.delta_r_m;
  }
}

ExtractionFigures ExtractionScoreAccumulator::Figures() const {
  ExtractionFigures f = totals_;
  if (f.walls_in_view > 0) f.true_positive_rate = 1.0 * f.walls_found / f.walls_in_view;
  if (f.modelled_walls_in_view > 0) {
    f.modelled_true_positive_rate = 1.0 * f.modelled_walls_found / f.modelled_walls_in_view;
  }
  if (f.extracted > 0) f.false_positive_rate = 1.0 * f.false_positives / f.extracted;
  if (f.matches > 0) {
    const double m = f.matches;
    f.in_gate_fraction = f.matches_in_gate / m;
    f.mean_delta_alpha_rad = sum_alpha_ / m;
    f.mean_delta_r_m = sum_r_ / m;
    if (f.matches > 1) {
      f.sigma_delta_alpha_rad = std::sqrt(std::max(
          0.0, (sum_alpha2_ - m * f.mean_delta_alpha_rad * f.mean_delta_alpha_rad) / (m - 1.0)));
      f.sigma_delta_r_m =
          std::sqrt(std::max(0.0, (sum_r2_ - m * f.mean_delta_r_m * f.mean_delta_r_m) / (m - 1.0)));
    }
  }
  return f;
}

}  // namespace pavilion::scenarios
