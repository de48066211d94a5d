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
// Below this |component| a clipped line runs parallel to that axis.
constexpr double kParallelEpsilon = 1e-12;

// The part of the infinite line inside `box` as a segment; false when it misses.
bool ClipLineToBox(const Line& line, const Box2& box, Vec2* a, Vec2* b) {
  const Vec2 normal = line.normal();
  const Vec2 foot = line.r_m * normal;
  const Vec2 direction(-normal.y(), normal.x());
  double t_lo = -std::numeric_limits<double>::infinity();
  double t_hi = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 2; ++k) {
    if (std::abs(direction[k]) < kParallelEpsilon) {
      if (foot[k] < box.lo[k] || foot[k] > box.hi[k]) return false;
      continue;
    }
    const double t0 = (box.lo[k] - foot[k]) / direction[k];
    const double t1 = (box.hi[k] - foot[k]) / direction[k];
    t_lo = std::max(t_lo, std::min(t0, t1));
    t_hi = std::min(t_hi, std::max(t0, t1));
  }
  if (!(t_lo <= t_hi)) return false;
  *a = foot + t_lo * direction;
  *b = foot + t_hi * direction;
  return true;
}

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

MapGeometry CollectMapGeometry(const RobotMap& map) {
  MapGeometry g;
  const auto add_segment = [&g](const Vec2& a, const Vec2& b) {
    g.segments.emplace_back(a, b);
    g.bounds.Add(a);
    g.bounds.Add(b);
  };
  const auto add_disc = [&g](const Vec2& centre, double radius_m) {
    g.discs.emplace_back(centre, radius_m);
    g.bounds.Add(centre - Vec2(radius_m, radius_m));
    g.bounds.Add(centre + Vec2(radius_m, radius_m));
  };
  for (const MapSegment& s : map.segments) {
    add_segment(s.first_endpoint.position_m, s.second_endpoint.position_m);
  }
  for (const MapMultiSegmentLine& m : map.multi_segment_lines) {
    for (const auto& [a, b] : m.segments) add_segment(a.position_m, b.position_m);
  }
  for (const MapPoint& p : map.points) add_disc(p.point.position_m, p.radius_m);
  for (const MapBeacon& b : map.beacons) add_disc(b.point.position_m, 0.0);
  if (g.bounds.lo.x() > g.bounds.hi.x()) return g;  // no finite geometry: lines are skipped
  for (const MapLine& l : map.lines) {
    Vec2 a, b;
    if (ClipLineToBox(l.line, g.bounds, &a, &b)) g.segments.emplace_back(a, b);
  }
  return g;
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
