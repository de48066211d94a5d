#include "core/features/split_and_merge.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/features/line_fit.h"
#include "core/features/segment_builder.h"

namespace pavilion::core {
namespace {

void Require(bool ok, const char* field, const std::string& expected) {
  if (!ok) {
    throw std::invalid_argument(std::string("SplitAndMergeOptions.") + field + ": expected " +
                                expected);
  }
}

// A segment in the making: sorted indices into the valid points, and its line
// once fitted.
struct Piece {
  std::vector<int> points;
  Line line;
};

class SplitMerger {
 public:
  SplitMerger(const LaserScan& scan, const SplitAndMergeOptions& options)
      : scan_(scan), options_(options) {
    floor_ << options.alpha_sigma_floor_rad * options.alpha_sigma_floor_rad, 0.0, 0.0,
        options.r_sigma_floor_m * options.r_sigma_floor_m;
    for (int i = 0; i < static_cast<int>(scan.readings.size()); ++i) {
      const LaserReading& reading = scan.readings[i];
      if (!reading.valid || !std::isfinite(reading.range_m) || !(reading.range_m > 0.0) ||
          !std::isfinite(reading.bearing_rad)) {
        continue;
      }
      points_.push_back({reading.range_m, reading.bearing_rad, options.range_sigma_m});
      xy_.push_back(reading.range_m *
                    Eigen::Vector2d(std::cos(reading.bearing_rad), std::sin(reading.bearing_rad)));
      reading_index_.push_back(i);
    }
  }

  std::vector<Segment> Run() {
    std::vector<Piece> pieces;
    const int n = static_cast<int>(points_.size());
    int begin = 0;
    for (int k = 1; k <= n; ++k) {
      if (k < n && !IsGap(k - 1, k)) continue;
      Split(begin, k - 1, &pieces);
      begin = k;
    }
    std::erase_if(pieces, [&](Piece& p) {
      if (static_cast<int>(p.points.size()) < options_.min_points) return true;
      std::optional<Line> line = Fit(p.points);
      if (!line) return true;
      p.line = *line;
      return false;
    });
    if (options_.merge) Merge(pieces);
    return ToSegments(pieces);
  }

 private:
  std::optional<Line> Fit(const std::vector<int>& indices) const {
    subset_.clear();
    for (int k : indices) subset_.push_back(points_[k]);
    std::optional<Line> line = FitLine(subset_);  // eqs. 3.4-3.10
    if (line) line->covariance += floor_;
    return line;
  }

  // Adaptive breakpoint between consecutive valid points a < b.
  bool IsGap(int a, int b) const {
    if (!options_.split_at_gaps) return false;
    const double dphi = std::abs(points_[b].bearing_rad - points_[a].bearing_rad);
    if (dphi >= options_.gap_lambda_rad) return true;
    const double limit =
        points_[a].range_m * std::sin(dphi) / std::sin(options_.gap_lambda_rad - dphi) +
        options_.gap_min_m;
    return (xy_[b] - xy_[a]).norm() > limit;
  }

  // Iterative end-point fit on the points [first, last]: the pieces are
  // appended in scan order. A breakpoint belongs to the piece whose other
  // points' line it is nearer.
  void Split(int first, int last, std::vector<Piece>* pieces) const {
    if (last < first) return;
    std::vector<std::pair<int, int>> ranges;  // final ranges, in order, sharing breakpoints
    std::vector<std::pair<int, int>> stack = {{first, last}};
    while (!stack.empty()) {
      const auto [b, e] = stack.back();
      stack.pop_back();
      int farthest = -1;
      double farthest_d = options_.split_threshold_m;
      if (e - b >= 2) {
        const Eigen::Vector2d chord = xy_[e] - xy_[b];
        const double norm = chord.norm();
        for (int k = b + 1; k < e; ++k) {
          const Eigen::Vector2d v = xy_[k] - xy_[b];
          const double d =
              norm > 1e-12 ? std::abs(chord.x() * v.y() - chord.y() * v.x()) / norm : v.norm();
          if (d > farthest_d) {
            farthest_d = d;
            farthest = k;
          }
        }
      }
      if (farthest < 0) {
        ranges.emplace_back(b, e);
      } else {
        stack.emplace_back(farthest, e);  // popped after [b, farthest]: scan order
        stack.emplace_back(b, farthest);
      }
    }
    // Give each shared breakpoint to one side.
    for (std::size_t i = 0; i + 1 < ranges.size(); ++i) {
      auto& left = ranges[i];
      auto& right = ranges[i + 1];
      if (left.second != right.first) continue;
      const int k = left.second;
      const double to_left = DistanceToRun(k, left.first, k - 1);
      const double to_right = DistanceToRun(k, k + 1, right.second);
      if (to_left <= to_right) {
        ++right.first;
      } else {
        --left.second;
      }
    }
    for (const auto& [b, e] : ranges) {
      if (e < b) continue;
      Piece piece;
      for (int k = b; k <= e; ++k) piece.points.push_back(k);
      pieces->push_back(std::move(piece));
    }
  }

  // Distance of point k to the line through the points [b, e]: their fit when
  // it exists, else the nearest of them.
  double DistanceToRun(int k, int b, int e) const {
    if (e < b) return std::numeric_limits<double>::infinity();
    if (e > b) {
      std::vector<int> run;
      for (int j = b; j <= e; ++j) run.push_back(j);
      if (std::optional<Line> line = Fit(run)) return std::abs(line->SignedDistance(xy_[k]));
    }
    return (xy_[k] - xy_[b]).norm();
  }

  double MaxDistance(const Line& line, const std::vector<int>& indices) const {
    double d = 0.0;
    for (int k : indices) d = std::max(d, std::abs(line.SignedDistance(xy_[k])));
    return d;
  }

  // Merges adjacent pieces while the line fitted to their union stays within
  // merge_threshold_m of all their points.
  void Merge(std::vector<Piece>& pieces) const {
    std::size_t i = 0;
    while (i + 1 < pieces.size()) {
      std::vector<int> joined;
      std::set_union(pieces[i].points.begin(), pieces[i].points.end(), pieces[i + 1].points.begin(),
                     pieces[i + 1].points.end(), std::back_inserter(joined));
      const std::optional<Line> line = Fit(joined);
      if (line && MaxDistance(*line, joined) <= options_.merge_threshold_m) {
        pieces[i].points = std::move(joined);
        pieces[i].line = *line;
        pieces.erase(pieces.begin() + static_cast<std::ptrdiff_t>(i) + 1);
        if (i > 0) --i;
      } else {
        ++i;
      }
    }
  }

  std::vector<Segment> ToSegments(const std::vector<Piece>& pieces) const {
    const double bearing_sigma = EndpointBearingSigma(scan_, options_.endpoint_bearing_sigma_rad);
    const SegmentFilter filter{options_.min_points, options_.min_length_m};
    std::vector<Segment> segments;
    for (const Piece& p : pieces) {
      if (auto s = BuildSegment(p.line, p.points, points_, reading_index_, bearing_sigma, filter)) {
        segments.push_back(*s);
      }
    }
    return segments;
  }

  const LaserScan& scan_;
  const SplitAndMergeOptions& options_;
  Eigen::Matrix2d floor_;
  std::vector<PolarPoint> points_;
  std::vector<Eigen::Vector2d> xy_;
  std::vector<int> reading_index_;
  mutable std::vector<PolarPoint> subset_;  // scratch of Fit
};

}  // namespace

void SplitAndMergeOptions::Validate() const {
  Require(std::isfinite(split_threshold_m) && split_threshold_m > 0.0, "split_threshold_m",
          "a finite value > 0");
  Require(std::isfinite(gap_min_m) && gap_min_m >= 0.0, "gap_min_m", "a finite value >= 0");
  Require(
      std::isfinite(gap_lambda_rad) && gap_lambda_rad > 0.0 && gap_lambda_rad <= 1.5707963267948966,
      "gap_lambda_rad", "a value in (0, pi/2]");
  Require(std::isfinite(merge_threshold_m) && merge_threshold_m > 0.0, "merge_threshold_m",
          "a finite value > 0");
  Require(std::isfinite(range_sigma_m) && range_sigma_m > 0.0, "range_sigma_m",
          "a finite value > 0");
  Require(min_points >= 2, "min_points", "an integer >= 2");
  Require(std::isfinite(min_length_m) && min_length_m >= 0.0, "min_length_m",
          "a finite value >= 0");
  Require(std::isfinite(alpha_sigma_floor_rad) && alpha_sigma_floor_rad >= 0.0,
          "alpha_sigma_floor_rad", "a finite value >= 0");
  Require(std::isfinite(r_sigma_floor_m) && r_sigma_floor_m >= 0.0, "r_sigma_floor_m",
          "a finite value >= 0");
  Require(std::isfinite(endpoint_bearing_sigma_rad) && endpoint_bearing_sigma_rad >= 0.0,
          "endpoint_bearing_sigma_rad", "a finite value >= 0");
}

SplitAndMergeOptions SplitAndMergeOptions::SickLms200() { return SplitAndMergeOptions{}; }

std::vector<Segment> SplitAndMerge(const LaserScan& scan, const SplitAndMergeOptions& options) {
  options.Validate();
  return SplitMerger(scan, options).Run();
}

}  // namespace pavilion::core
