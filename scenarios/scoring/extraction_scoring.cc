#include "scenarios/scoring/extraction_scoring.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/geometry/segment2.h"
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

// The section's faces in the sensor frame, grouped into infinite lines.
struct FaceGroups {
  std::vector<Eigen::Vector2d> fa, fb;  // face endpoints, sensor frame
  std::vector<int> group_of_face;       // -1 for degenerate faces
  std::vector<core::Line> lines;        // per group
  std::vector<std::vector<int>> faces;  // per group
};

FaceGroups GroupFaces(const core::PlanarSection& section, const core::Pose2& sensor_from_world,
                      const ExtractionScoringOptions& options) {
  const std::size_t faces = section.segments.size();
  FaceGroups groups;
  groups.fa.resize(faces);
  groups.fb.resize(faces);
  groups.group_of_face.assign(faces, -1);
  for (std::size_t f = 0; f < faces; ++f) {
    groups.fa[f] = sensor_from_world * section.segments[f].a_m;
    groups.fb[f] = sensor_from_world * section.segments[f].b_m;
    if ((groups.fb[f] - groups.fa[f]).norm() < 1e-9) continue;
    const core::Line line = LineThrough(groups.fa[f], groups.fb[f]);
    int g = -1;
    for (std::size_t k = 0; k < groups.lines.size() && g < 0; ++k) {
      if (std::abs(core::NormalizeAngle(line.alpha_rad - groups.lines[k].alpha_rad)) <=
              options.collinear_alpha_rad &&
          std::abs(line.r_m - groups.lines[k].r_m) <= options.collinear_r_m) {
        g = static_cast<int>(k);
      }
    }
    if (g < 0) {
      g = static_cast<int>(groups.lines.size());
      groups.lines.push_back(line);
      groups.faces.emplace_back();
    }
    groups.group_of_face[f] = g;
    groups.faces[g].push_back(static_cast<int>(f));
  }
  return groups;
}

// The group of the face that reading i truly hit (within on_face_tolerance_m)
// and the hit's coordinate along the group's line; group -1 for none.
std::pair<int, double> GroupOfReading(const core::LaserScan& scan,
                                      const core::LaserScanTruth& truth,
                                      const core::PlanarSection& section, const FaceGroups& groups,
                                      const core::Pose2& sensor_from_world,
                                      const ExtractionScoringOptions& options, std::size_t i) {
  const int element = truth.element[i];
  const double range = truth.true_range_m[i];
  int group = -1;
  double t = 0.0;
  if (element >= 0 && range < scan.max_range_m) {
    const double bearing = scan.readings[i].bearing_rad;
    const Eigen::Vector2d in_sensor(range * std::cos(bearing), range * std::sin(bearing));
    const Eigen::Vector2d p = sensor_from_world * (truth.world_from_sensor[i] * in_sensor);
    double best = options.on_face_tolerance_m;
    for (std::size_t f = 0; f < section.segments.size(); ++f) {
      if (section.segments[f].element != element || groups.group_of_face[f] < 0) continue;
      const double d = core::PointSegmentDistance(p, groups.fa[f], groups.fb[f]);
      if (d <= best) {
        best = d;
        group = groups.group_of_face[f];
      }
    }
    if (group >= 0) t = AlongLine(groups.lines[group], p);
  }
  return {group, t};
}

// Runs of consecutive readings on one group: all, and within max_distance_m.
std::vector<Run> ReadingRuns(const core::LaserScan& scan, const core::LaserScanTruth& truth,
                             const core::PlanarSection& section, const FaceGroups& groups,
                             const core::Pose2& sensor_from_world,
                             const ExtractionScoringOptions& options) {
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
  for (std::size_t i = 0; i < scan.readings.size(); ++i) {
    const auto [group, t] =
        GroupOfReading(scan, truth, section, groups, sensor_from_world, options, i);
    const double range = truth.true_range_m[i];
    if (group != current.group) close(&current);
    if (group >= 0) extend(&current, group, t, false);
    const bool in_range = group >= 0 && range <= options.max_distance_m;
    if (!in_range || group != current_in_range.group) close(&current_in_range);
    if (in_range) extend(&current_in_range, group, t, true);
  }
  close(&current);
  close(&current_in_range);
  return runs;
}

// Walls: per group, the runs' intervals merged across gaps <= max_gap_m.
void AddWalls(const std::vector<Run>& runs, const FaceGroups& groups,
              const core::PlanarSection& section, const ExtractionScoringOptions& options,
              ExtractionScore* score) {
  for (std::size_t g = 0; g < groups.lines.size(); ++g) {
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
      wall.faces = groups.faces[g];
      wall.group = static_cast<int>(g);
      wall.line = groups.lines[g];
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
      if (wall.in_view) ++score->walls_in_view;
      if (wall.in_view && wall.modelled_surface) ++score->modelled_walls_in_view;
      score->walls.push_back(std::move(wall));
      k = j;
    }
  }
}

// A segment's match against one group's line, before the best is chosen.
struct Candidate {
  ExtractionMatch match;
  double norm = 0.0;  // |da| / max_alpha_error + |dr| / max_r_error
  double lo = 0.0;    // the segment's interval along the line
  double hi = 0.0;
};

// The segment against the walls of one group (line `line`); nullopt when its
// line is too far off or it overlaps their visible parts too little.
std::optional<Candidate> MatchGroup(const core::Segment& seg, const core::Line& line,
                                    const std::vector<int>& walls,
                                    const std::vector<TrueWall>& all_walls,
                                    const ExtractionScoringOptions& options) {
  const double da = core::NormalizeAngle(seg.line.alpha_rad - line.alpha_rad);
  const double dr = seg.line.r_m - line.r_m;
  if (std::abs(da) > options.max_alpha_error_rad || std::abs(dr) > options.max_r_error_m) {
    return std::nullopt;
  }
  const double t0 = AlongLine(line, seg.first_endpoint.position_m);
  const double t1 = AlongLine(line, seg.last_endpoint.position_m);
  const double lo = std::min(t0, t1), hi = std::max(t0, t1);
  double overlap = 0.0, wall_overlap = -1.0;
  bool touches = false;
  int wall = -1;
  double hull_lo = std::numeric_limits<double>::infinity(), hull_hi = -hull_lo;
  for (int w : walls) {
    const double o = Overlap(all_walls[w].visible_t_m, lo, hi);
    overlap += o;
    for (const Eigen::Vector2d& iv : all_walls[w].visible_t_m) {
      hull_lo = std::min(hull_lo, iv.x());
      hull_hi = std::max(hull_hi, iv.y());
    }
    for (const Eigen::Vector2d& iv : all_walls[w].visible_t_m) {
      touches = touches || (lo <= iv.y() && hi >= iv.x());
    }
    if (o > wall_overlap) {
      wall_overlap = o;
      wall = w;
    }
  }
  if (options.bridge_gaps) overlap = std::max(0.0, std::min(hi, hull_hi) - std::max(lo, hull_lo));
  const double fraction = hi - lo > 1e-9 ? overlap / (hi - lo) : (touches ? 1.0 : 0.0);
  if (fraction < options.min_overlap_fraction) return std::nullopt;
  const Eigen::Vector2d e(da, dr);
  double m2 = std::numeric_limits<double>::infinity();
  const Eigen::Matrix2d& c = seg.line.covariance;
  if (c.determinant() > 0.0) m2 = e.dot(c.inverse() * e);
  Candidate candidate;
  candidate.norm =
      std::abs(da) / options.max_alpha_error_rad + std::abs(dr) / options.max_r_error_m;
  candidate.match.wall = wall;
  candidate.match.delta_alpha_rad = da;
  candidate.match.delta_r_m = dr;
  candidate.match.mahalanobis2 = m2;
  candidate.match.in_gate = m2 <= options.gate;
  candidate.match.overlap_fraction = fraction;
  candidate.lo = lo;
  candidate.hi = hi;
  return candidate;
}

// Matching against infinite lines: the visible parts of all walls on one
// line. Sets the matches, false positives and matched segments of `score`;
// `covered` receives each wall's intervals covered by matching segments.
void MatchSegments(const std::vector<core::Segment>& segments, const FaceGroups& groups,
                   const ExtractionScoringOptions& options, ExtractionScore* score,
                   std::vector<std::vector<Eigen::Vector2d>>* covered) {
  std::vector<std::vector<int>> walls_of_group(groups.lines.size());
  for (std::size_t w = 0; w < score->walls.size(); ++w) {
    walls_of_group[score->walls[w].group].push_back(static_cast<int>(w));
  }
  covered->assign(score->walls.size(), {});
  for (std::size_t s = 0; s < segments.size(); ++s) {
    Candidate best;
    double best_m2 = std::numeric_limits<double>::infinity();
    double best_norm = std::numeric_limits<double>::infinity();
    for (std::size_t g = 0; g < groups.lines.size(); ++g) {
      if (walls_of_group[g].empty()) continue;
      const std::optional<Candidate> c =
          MatchGroup(segments[s], groups.lines[g], walls_of_group[g], score->walls, options);
      if (!c) continue;
      const double m2 = c->match.mahalanobis2;
      if (m2 < best_m2 || (m2 == best_m2 && c->norm < best_norm)) {
        best_m2 = m2;
        best_norm = c->norm;
        best = *c;
        best.match.segment = static_cast<int>(s);
      }
    }
    if (best.match.wall < 0) {
      ++score->false_positives;
      continue;
    }
    score->wall_of_segment[s] = best.match.wall;
    for (int w : walls_of_group[score->walls[best.match.wall].group]) {
      ++score->walls[w].matched_segments;
      (*covered)[w].emplace_back(best.lo, best.hi);
    }
    score->matches.push_back(best.match);
  }
}

// A wall is found when the matching segments cover min_overlap_fraction of its
// visible part.
void MarkFoundWalls(const ExtractionScoringOptions& options,
                    std::vector<std::vector<Eigen::Vector2d>>& covered, ExtractionScore* score) {
  for (std::size_t w = 0; w < score->walls.size(); ++w) {
    TrueWall& wall = score->walls[w];
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
    if (wall.found && wall.in_view) ++score->walls_found;
    if (wall.found && wall.in_view && wall.modelled_surface) ++score->modelled_walls_found;
  }
}

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
  const FaceGroups groups = GroupFaces(section, sensor_from_world, options);
  AddWalls(ReadingRuns(scan, truth, section, groups, sensor_from_world, options), groups, section,
           options, &score);
  std::vector<std::vector<Eigen::Vector2d>> covered;
  MatchSegments(segments, groups, options, &score, &covered);
  MarkFoundWalls(options, covered, &score);
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
