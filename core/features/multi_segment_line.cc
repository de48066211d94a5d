#include "core/features/multi_segment_line.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "core/math/chi_square.h"
#include "core/types/pose2.h"

namespace pavilion::core {
namespace {

constexpr double kPi = std::numbers::pi;

// The same geometric line as `line` with the other parameterization
// (alpha + pi, -r); the Jacobian diag(1, -1) flips the cross-covariance.
Line Flipped(const Line& line) {
  Line flipped;
  flipped.alpha_rad = NormalizeAngle(line.alpha_rad + kPi);
  flipped.r_m = -line.r_m;
  flipped.covariance = line.covariance;
  flipped.covariance(0, 1) = -line.covariance(0, 1);
  flipped.covariance(1, 0) = -line.covariance(1, 0);
  return flipped;
}

// Eq. 3.16 for one fixed parameterization of both lines.
double Mahalanobis2Fixed(const Line& a, const Line& b) {
  const Eigen::Vector2d diff(NormalizeAngle(a.alpha_rad - b.alpha_rad), a.r_m - b.r_m);
  const Eigen::Matrix2d sum = a.covariance + b.covariance;
  const double det = sum.determinant();
  if (!(std::abs(det) > 0.0) || !std::isfinite(det)) {
    return std::numeric_limits<double>::infinity();
  }
  return diff.dot(sum.inverse() * diff);
}

// `line` in the parameterization closest (eq. 3.16) to `reference`.
Line AlignedTo(const Line& line, const Line& reference) {
  const Line flipped = Flipped(line);
  return Mahalanobis2Fixed(flipped, reference) < Mahalanobis2Fixed(line, reference) ? flipped
                                                                                    : line;
}

}  // namespace

void MultiSegmentLineOptions::Validate() const {
  if (!(significance > 0.0 && significance < 1.0)) {
    throw std::invalid_argument("MultiSegmentLineOptions.significance must be in (0, 1)");
  }
  if (min_segments < 1) {
    throw std::invalid_argument("MultiSegmentLineOptions.min_segments must be >= 1");
  }
}

double LineMahalanobis2(const Line& a, const Line& b) {
  return std::min(Mahalanobis2Fixed(a, b), Mahalanobis2Fixed(Flipped(a), b));
}

Line FuseLines(const std::vector<Line>& lines) {
  if (lines.empty()) throw std::invalid_argument("FuseLines: no lines");
  const Line& reference = lines.front();
  // Eq. 3.14: C_w^{-1} = sum C_i^{-1}; eq. 3.13: x_w = C_w sum C_i^{-1} x_i, with
  // x_i = (alpha_i - alpha_ref, r_i) so the angles are averaged without wrap.
  Eigen::Matrix2d information = Eigen::Matrix2d::Zero();
  Eigen::Vector2d information_vector = Eigen::Vector2d::Zero();
  for (const Line& raw : lines) {
    const Line line = AlignedTo(raw, reference);
    const double det = line.covariance.determinant();
    if (!(std::abs(det) > 0.0) || !std::isfinite(det)) {
      throw std::invalid_argument("FuseLines: singular line covariance");
    }
    const Eigen::Matrix2d inverse = line.covariance.inverse();
    const Eigen::Vector2d x(NormalizeAngle(line.alpha_rad - reference.alpha_rad), line.r_m);
    information += inverse;
    information_vector += inverse * x;
  }
  Line fused;
  fused.covariance = information.inverse();
  fused.covariance = 0.5 * (fused.covariance + fused.covariance.transpose()).eval();
  const Eigen::Vector2d x = fused.covariance * information_vector;
  fused.alpha_rad = NormalizeAngle(reference.alpha_rad + x(0));
  fused.r_m = x(1);
  // Keep the sensor-frame convention r >= 0 of the inputs when they all had it.
  if (fused.r_m < 0.0 && reference.r_m >= 0.0) fused = Flipped(fused);
  return fused;
}

std::vector<MultiSegmentLine> GroupMultiSegmentLines(const std::vector<Segment>& segments,
                                                     const MultiSegmentLineOptions& options) {
  options.Validate();
  const double gate = ChiSquare2Quantile(options.significance);

  struct Cluster {
    std::vector<int> members;
    Line line;
  };
  std::vector<Cluster> clusters;
  clusters.reserve(segments.size());
  for (int i = 0; i < static_cast<int>(segments.size()); ++i) {
    clusters.push_back({{i}, segments[static_cast<size_t>(i)].line});
  }

  // Nearest-neighbour agglomeration (§3.2.3): merge the closest pair under the
  // chi^2 gate of eq. 3.16, fuse by eqs. 3.13-3.14, repeat.
  while (clusters.size() > 1) {
    double best = std::numeric_limits<double>::infinity();
    size_t best_a = 0;
    size_t best_b = 0;
    for (size_t a = 0; a < clusters.size(); ++a) {
      for (size_t b = a + 1; b < clusters.size(); ++b) {
        const double d2 = LineMahalanobis2(clusters[a].line, clusters[b].line);
        if (d2 < best) {
          best = d2;
          best_a = a;
          best_b = b;
        }
      }
    }
    if (!(best <= gate)) break;
    Cluster& target = clusters[best_a];
    target.members.insert(target.members.end(), clusters[best_b].members.begin(),
                          clusters[best_b].members.end());
    std::vector<Line> member_lines;
    member_lines.reserve(target.members.size());
    // Fuse the original lines of all members at once: the information filter
    // is linear, so this equals iterated fusion but keeps one reference angle.
    std::sort(target.members.begin(), target.members.end());
    for (int m : target.members) member_lines.push_back(segments[static_cast<size_t>(m)].line);
    target.line = FuseLines(member_lines);
    clusters.erase(clusters.begin() + static_cast<std::ptrdiff_t>(best_b));
  }

  std::vector<MultiSegmentLine> result;
  for (Cluster& cluster : clusters) {
    if (static_cast<int>(cluster.members.size()) < options.min_segments) continue;
    std::sort(cluster.members.begin(), cluster.members.end(), [&](int a, int b) {
      const Segment& sa = segments[static_cast<size_t>(a)];
      const Segment& sb = segments[static_cast<size_t>(b)];
      return sa.first_index != sb.first_index ? sa.first_index < sb.first_index : a < b;
    });
    MultiSegmentLine ms;
    ms.line = cluster.line;
    ms.segment_indices = cluster.members;
    for (int m : cluster.members) ms.segments.push_back(segments[static_cast<size_t>(m)]);
    result.push_back(std::move(ms));
  }
  std::sort(result.begin(), result.end(), [](const MultiSegmentLine& a, const MultiSegmentLine& b) {
    return a.segments.front().first_index < b.segments.front().first_index;
  });
  return result;
}

}  // namespace pavilion::core
