#include "nav/local/distance_field.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pavilion::nav {

void DistanceFieldOptions::Validate() const {
  auto fail = [](const std::string& message) { throw std::invalid_argument(message); };
  if (!(cap_m > 0.0 && cap_m <= 20.0)) fail("cap_m must be in (0, 20] m");
  if (!(bucket_m >= 0.02 && bucket_m <= 2.0)) fail("bucket_m must be in [0.02, 2] m");
}

DistanceField::DistanceField(const DistanceFieldOptions& options) : options_(options) {
  options_.Validate();
}

void DistanceField::Build(const LocalGrid& grid) {
  origin_ = grid.origin();
  side_m_ = grid.cells_per_side() * grid.cell_m();
  buckets_ = std::max(1, static_cast<int>(std::ceil(side_m_ / options_.bucket_m)));
  const int count = buckets_ * buckets_;
  const std::vector<Eigen::Vector2d>& points = grid.obstacles();

  // Counting sort of the points by bucket (CSR).
  bucket_start_.assign(static_cast<std::size_t>(count) + 1, 0);
  bucket_of_.resize(points.size());
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Eigen::Vector2d q = (points[k] - origin_) / options_.bucket_m;
    const int bx = std::clamp(static_cast<int>(std::floor(q.x())), 0, buckets_ - 1);
    const int by = std::clamp(static_cast<int>(std::floor(q.y())), 0, buckets_ - 1);
    bucket_of_[k] = by * buckets_ + bx;
    ++bucket_start_[bucket_of_[k] + 1];
  }
  for (int b = 0; b < count; ++b) bucket_start_[b + 1] += bucket_start_[b];
  xs_.resize(points.size());
  ys_.resize(points.size());
  for (std::size_t k = 0; k < points.size(); ++k) {
    const std::int32_t slot = bucket_start_[bucket_of_[k]]++;
    xs_[slot] = points[k].x();
    ys_[slot] = points[k].y();
  }
  for (int b = count; b > 0; --b) bucket_start_[b] = bucket_start_[b - 1];
  bucket_start_[0] = 0;

  // Chebyshev distance transform of the non-empty buckets (two exact passes).
  const std::int32_t none = 2 * buckets_ + 2;
  empty_rings_.resize(count);
  for (int b = 0; b < count; ++b) {
    empty_rings_[b] = bucket_start_[b + 1] > bucket_start_[b] ? 0 : none;
  }
  const auto relax = [&](int x, int y, int dx, int dy) {
    const int nx = x + dx;
    const int ny = y + dy;
    if (nx < 0 || ny < 0 || nx >= buckets_ || ny >= buckets_) return;
    std::int32_t& ring = empty_rings_[y * buckets_ + x];
    ring = std::min(ring, empty_rings_[ny * buckets_ + nx] + 1);
  };
  for (int y = 0; y < buckets_; ++y) {
    for (int x = 0; x < buckets_; ++x) {
      relax(x, y, -1, 0);
      relax(x, y, -1, -1);
      relax(x, y, 0, -1);
      relax(x, y, 1, -1);
    }
  }
  for (int y = buckets_ - 1; y >= 0; --y) {
    for (int x = buckets_ - 1; x >= 0; --x) {
      relax(x, y, 1, 0);
      relax(x, y, 1, 1);
      relax(x, y, 0, 1);
      relax(x, y, -1, 1);
    }
  }
}

void DistanceField::ScanRow(int by, int x0, int x1, const Eigen::Vector2d& p, double* best_d2,
                            std::int32_t* best) const {
  if (by < 0 || by >= buckets_) return;
  x0 = std::max(x0, 0);
  x1 = std::min(x1, buckets_ - 1);
  if (x0 > x1) return;
  // The buckets of one row are contiguous in the CSR order.
  const std::int32_t end = bucket_start_[by * buckets_ + x1 + 1];
  for (std::int32_t k = bucket_start_[by * buckets_ + x0]; k < end; ++k) {
    const double dx = xs_[k] - p.x();
    const double dy = ys_[k] - p.y();
    const double d2 = dx * dx + dy * dy;
    if (d2 < *best_d2) {
      *best_d2 = d2;
      *best = k;
    }
  }
}

DistanceField::Query DistanceField::Nearest(const Eigen::Vector2d& p_in_world) const {
  Query result;
  result.distance_m = options_.cap_m;
  if (buckets_ == 0 || !p_in_world.allFinite()) return result;
  const Eigen::Vector2d local = p_in_world - origin_;
  if (local.x() < 0.0 || local.y() < 0.0 || local.x() >= side_m_ || local.y() >= side_m_) {
    return result;
  }
  const double b = options_.bucket_m;
  const int bx = std::min(static_cast<int>(local.x() / b), buckets_ - 1);
  const int by = std::min(static_cast<int>(local.y() / b), buckets_ - 1);
  const int first_ring = empty_rings_[by * buckets_ + bx];
  if (first_ring > 2 * buckets_) return result;  // no points at all
  // A point in ring k >= 1 lies at least (k - 1) b + edge away.
  const double edge = std::max(0.0, std::min({local.x() - bx * b, (bx + 1) * b - local.x(),
                                              local.y() - by * b, (by + 1) * b - local.y()}));
  const double cap = options_.cap_m;
  if (first_ring >= 1 && (first_ring - 1) * b + edge >= cap) return result;

  double best_d2 = cap * cap;
  std::int32_t best = -1;
  for (int k = first_ring; k <= buckets_; ++k) {
    if (k == 0) {
      ScanRow(by, bx, bx, p_in_world, &best_d2, &best);
    } else {
      ScanRow(by - k, bx - k, bx + k, p_in_world, &best_d2, &best);
      ScanRow(by + k, bx - k, bx + k, p_in_world, &best_d2, &best);
      for (int y = by - k + 1; y <= by + k - 1; ++y) {
        ScanRow(y, bx - k, bx - k, p_in_world, &best_d2, &best);
        ScanRow(y, bx + k, bx + k, p_in_world, &best_d2, &best);
      }
    }
    const double beyond = k * b + edge;  // no unvisited point is nearer
    if (best_d2 <= beyond * beyond || beyond >= cap) break;
  }
  if (best < 0) return result;
  const double d = std::sqrt(best_d2);
  result.distance_m = d;
  if (d > 0.0) result.gradient = (p_in_world - Eigen::Vector2d(xs_[best], ys_[best])) / d;
  return result;
}

}  // namespace pavilion::nav
