#include "core/localization/mcl/likelihood_field.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace pavilion::core {
namespace {

using Vec2 = Eigen::Vector2d;

constexpr double kMaxResolutionM = 1.0;
constexpr double kMaxMarginM = 100.0;
constexpr double kMaxDistanceM = 100.0;
// Segments are sampled at this fraction of a cell, so that consecutive samples
// never skip a cell the segment crosses by more than a sliver.
constexpr double kSamplesPerCell = 4.0;
// 1-D squared Euclidean distance transform of f (Felzenszwalb & Huttenlocher
// 2012, algorithm DT): d[q] = min_p (q - p)^2 + f[p]. v and z are scratch.
void Transform1d(const std::vector<double>& f, std::vector<double>* d, std::vector<int>* v,
                 std::vector<double>* z) {
  const int n = static_cast<int>(f.size());
  int k = 0;
  (*v)[0] = 0;
  (*z)[0] = -std::numeric_limits<double>::infinity();
  (*z)[1] = std::numeric_limits<double>::infinity();
  const auto intersection = [&](int q, int p) {
    return ((f[q] + static_cast<double>(q) * q) - (f[p] + static_cast<double>(p) * p)) /
           (2.0 * q - 2.0 * p);
  };
  for (int q = 1; q < n; ++q) {
    double s = intersection(q, (*v)[k]);
    while (s <= (*z)[k]) {
      --k;
      s = intersection(q, (*v)[k]);
    }
    ++k;
    (*v)[k] = q;
    (*z)[k] = s;
    (*z)[k + 1] = std::numeric_limits<double>::infinity();
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while ((*z)[k + 1] < q) ++k;
    const double offset = q - (*v)[k];
    (*d)[q] = offset * offset + f[(*v)[k]];
  }
}

}  // namespace

void LikelihoodFieldOptions::Validate() const {
  if (!(resolution_m > 0.0 && resolution_m <= kMaxResolutionM)) {
    throw std::invalid_argument("LikelihoodFieldOptions.resolution_m must be in (0, 1] m");
  }
  if (!(margin_m >= 0.0 && margin_m <= kMaxMarginM)) {
    throw std::invalid_argument("LikelihoodFieldOptions.margin_m must be in [0, 100] m");
  }
  if (!(max_distance_m > 0.0 && max_distance_m <= kMaxDistanceM)) {
    throw std::invalid_argument("LikelihoodFieldOptions.max_distance_m must be in (0, 100] m");
  }
}

LikelihoodField::LikelihoodField(const RobotMap& map, const LikelihoodFieldOptions& options)
    : options_(options) {
  options_.Validate();
  const MapGeometry geometry = CollectMapGeometry(map);
  bounds_ = geometry.bounds;
  if (bounds_.lo.x() > bounds_.hi.x()) return;
  const double res = options_.resolution_m;
  origin_m_ = bounds_.lo - Vec2::Constant(options_.margin_m);
  const Vec2 extent = bounds_.hi - bounds_.lo + Vec2::Constant(2.0 * options_.margin_m);
  width_ = static_cast<int>(std::ceil(extent.x() / res)) + 1;
  height_ = static_cast<int>(std::ceil(extent.y() / res)) + 1;
  std::vector<char> occupied(static_cast<std::size_t>(cell_count()), 0);
  Rasterize(geometry, &occupied);
  Transform(occupied);
}

long LikelihoodField::CellIndex(const Vec2& point_in_map) const {
  const Vec2 cell = (point_in_map - origin_m_) / options_.resolution_m;
  if (!(cell.x() >= 0.0 && cell.y() >= 0.0 && cell.x() < width_ && cell.y() < height_)) return -1;
  return static_cast<long>(cell.y()) * width_ + static_cast<long>(cell.x());
}

Vec2 LikelihoodField::CellCenter(long index) const {
  const long x = index % width_;
  const long y = index / width_;
  return origin_m_ +
         options_.resolution_m * Vec2(static_cast<double>(x) + 0.5, static_cast<double>(y) + 0.5);
}

double LikelihoodField::DistanceM(const Vec2& point_in_map) const {
  const long i = CellIndex(point_in_map);
  return i < 0 ? options_.max_distance_m : CellDistanceM(i);
}

void LikelihoodField::Rasterize(const MapGeometry& geometry, std::vector<char>* occupied) const {
  const double res = options_.resolution_m;
  const auto mark = [&](const Vec2& p) {
    const long i = CellIndex(p);
    if (i >= 0) (*occupied)[static_cast<std::size_t>(i)] = 1;
  };
  for (const auto& [a, b] : geometry.segments) {
    const int n = static_cast<int>(std::ceil((b - a).norm() * kSamplesPerCell / res));
    for (int i = 0; i <= n; ++i) mark(n == 0 ? a : Vec2(a + (b - a) * (double(i) / n)));
  }
  for (const auto& [centre, radius_m] : geometry.discs) {
    mark(centre);
    const long lo = CellIndex(centre - Vec2(radius_m, radius_m));
    const long hi = CellIndex(centre + Vec2(radius_m, radius_m));
    if (lo < 0 || hi < 0) continue;
    for (long y = lo / width_; y <= hi / width_; ++y) {
      for (long x = lo % width_; x <= hi % width_; ++x) {
        const long i = y * width_ + x;
        if ((CellCenter(i) - centre).norm() <= radius_m)
          (*occupied)[static_cast<std::size_t>(i)] = 1;
      }
    }
    // The rim, so that discs thinner than a cell still leave a closed ring.
    const int n =
        static_cast<int>(std::ceil(2.0 * std::numbers::pi * radius_m * kSamplesPerCell / res));
    for (int i = 0; i < n; ++i) {
      const double angle = 2.0 * std::numbers::pi * i / n;
      mark(centre + radius_m * Vec2(std::cos(angle), std::sin(angle)));
    }
  }
}

void LikelihoodField::Transform(const std::vector<char>& occupied) {
  // "Infinity" above every squared distance on the grid but small enough that
  // the parabola intersections keep their precision.
  const double far =
      static_cast<double>(width_) * width_ + static_cast<double>(height_) * height_ + 1.0;
  const int n_max = std::max(width_, height_);
  std::vector<double> squared(occupied.size());
  std::vector<double> f(static_cast<std::size_t>(height_)), d(static_cast<std::size_t>(n_max));
  std::vector<int> v(static_cast<std::size_t>(n_max));
  std::vector<double> z(static_cast<std::size_t>(n_max) + 1);
  for (int x = 0; x < width_; ++x) {  // columns
    for (int y = 0; y < height_; ++y) f[y] = occupied[std::size_t(y) * width_ + x] ? 0.0 : far;
    d.resize(f.size());
    Transform1d(f, &d, &v, &z);
    for (int y = 0; y < height_; ++y) squared[std::size_t(y) * width_ + x] = d[y];
  }
  f.resize(static_cast<std::size_t>(width_));
  d.resize(f.size());
  distance_m_.resize(occupied.size());
  for (int y = 0; y < height_; ++y) {  // rows
    const std::size_t row = std::size_t(y) * width_;
    for (int x = 0; x < width_; ++x) f[x] = squared[row + x];
    Transform1d(f, &d, &v, &z);
    for (int x = 0; x < width_; ++x) {
      distance_m_[row + x] = static_cast<float>(
          std::min(std::sqrt(d[x]) * options_.resolution_m, options_.max_distance_m));
    }
  }
}

}  // namespace pavilion::core
