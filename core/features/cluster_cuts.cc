#include "core/features/cluster_cuts.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pavilion::core {

bool SharePoints(const std::vector<int>& a, const std::vector<int>& b) {
  if (a.empty() || b.empty() || a.back() < b.front() || b.back() < a.front()) return false;
  auto ia = a.begin();
  auto ib = b.begin();
  while (ia != a.end() && ib != b.end()) {
    if (*ia == *ib) return true;
    if (*ia < *ib) {
      ++ia;
    } else {
      ++ib;
    }
  }
  return false;
}

int BestTwoLineCut(const std::vector<FitPoint>& prepared, const std::vector<int>& members) {
  struct Moments {
    double w = 0, x = 0, y = 0, xx = 0, yy = 0, xy = 0;
    void Add(const FitPoint& p) {
      const double px = p.range_m * p.cos_bearing;
      const double py = p.range_m * p.sin_bearing;
      w += p.weight;
      x += p.weight * px;
      y += p.weight * py;
      xx += p.weight * px * px;
      yy += p.weight * py * py;
      xy += p.weight * px * py;
    }
    double MinResidual() const {
      if (!(w > 0.0)) return 0.0;
      const double a = xx - x * x / w;
      const double c = yy - y * y / w;
      const double b = xy - x * y / w;
      return std::max(0.0, 0.5 * (a + c) - std::hypot(0.5 * (a - c), b));
    }
  };
  const int n = static_cast<int>(members.size());
  std::vector<double> suffix(n + 1, 0.0);
  Moments m;
  for (int k = n - 1; k >= 0; --k) {
    m.Add(prepared[members[k]]);
    suffix[k] = m.MinResidual();
  }
  Moments prefix;
  int best = 1;
  double best_sum = std::numeric_limits<double>::infinity();
  for (int k = 1; k < n; ++k) {
    prefix.Add(prepared[members[k - 1]]);
    const double sum = prefix.MinResidual() + suffix[k];
    if (sum < best_sum) {
      best_sum = sum;
      best = k;
    }
  }
  return best;
}

int CornerCut(const std::vector<FitPoint>& prepared, const std::vector<int>& shared, const Line& a,
              const Line& b) {
  const int m = static_cast<int>(shared.size());
  const Eigen::Vector2d normal_a = a.normal();
  const Eigen::Vector2d normal_b = b.normal();
  std::vector<double> to_a(m);
  std::vector<double> to_b(m);
  for (int k = 0; k < m; ++k) {
    const FitPoint& q = prepared[shared[k]];
    const Eigen::Vector2d p = q.range_m * Eigen::Vector2d(q.cos_bearing, q.sin_bearing);
    to_a[k] = std::pow(normal_a.dot(p) - a.r_m, 2);  // Line::SignedDistance
    to_b[k] = std::pow(normal_b.dot(p) - b.r_m, 2);
  }
  double cost = 0.0;
  for (double v : to_b) cost += v;
  double best_cost = cost;
  int best_cut = 0;
  for (int cut = 1; cut <= m; ++cut) {
    cost += to_a[cut - 1] - to_b[cut - 1];
    if (cost < best_cost) {
      best_cost = cost;
      best_cut = cut;
    }
  }
  return best_cut;
}

}  // namespace pavilion::core
