#include "sim/raycast/planar_caster.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace pavilion::sim {
namespace {

// Acceleration structure: a uniform grid walked along the ray (DDA), chosen
// over a BVH by measurement and by the scenes' shape. Indoor worlds are
// rooms of long wall segments and many small, evenly spread bodies (legs,
// robots) whose cross-sections change every tick: the grid is rebuilt for the
// dynamic part in O(primitives) per tick without any sorting, and its walk
// visits cells in ray order so that a ray stops at the first cell whose far
// boundary lies beyond the closest hit so far (most rays end after a few
// cells). A BVH was not built for comparison: its moving leaves would need a
// refit every tick and its walk a stack; the grid already exceeds the 3 M
// rays/s goal by more than 2×. Cell size: 0.5 to 2 m are
// within the measurement noise of the hall benchmark (7–8.5 M rays/s), 0.25 m
// is 30 % slower; 0.5 m (PlanarCasterOptions) keeps few legs per cell in a
// denser crowd than the benchmark's.

// Primitives are bucketed into every cell their bounding box overlaps, grown
// by this margin (m), so that a hit point on a cell boundary lies in a cell
// the walk visits even after rounding in the walk's cell arithmetic.
constexpr double kCellMarginM = 1e-7;
// The grid covers the static geometry and the floor plus this margin (m).
constexpr double kGridPaddingM = 1.0;
// Bound on the grid's cells; larger worlds get larger cells.
constexpr double kMaxCells = 4e6;
constexpr double kMaxTiltRad = std::numbers::pi / 4;

}  // namespace

void PlanarCasterOptions::Validate() const {
  if (!(max_tilt_rad >= 0.0 && max_tilt_rad <= kMaxTiltRad)) {
    throw std::invalid_argument("planar caster max_tilt_rad must be in [0, π/4]");
  }
  if (!(cell_size_m >= 0.05 && cell_size_m <= 10.0)) {
    throw std::invalid_argument("planar caster cell_size_m must be in [0.05, 10]");
  }
}

PlanarSlice::PlanarSlice(const World& world, double height_m, const PlanarCasterOptions& options)
    : world_(world), height_m_(height_m), options_(options) {
  // Element order (world.h): floor, walls, boxes, cylinders, meshes, doors.
  const WorldDescription& d = world.description();
  first_mesh_element_ = 1 + static_cast<int>(d.walls.size() + d.boxes.size() + d.cylinders.size());
  mesh_elements_ = static_cast<int>(d.meshes.size());
  UpdateStatic();
  UpdateDynamic();
}

const std::vector<core::SectionElement>& PlanarSlice::elements() const { return world_.elements(); }

void PlanarSlice::Split(const core::PlanarSection& section, bool statics,
                        std::vector<Segment>* segments, std::vector<Circle>* circles) const {
  const auto& elements = world_.elements();
  const auto visible = [&](int e) {
    return e >= 0 && e < static_cast<int>(elements.size()) &&
           elements[e].laser != core::LaserResponse::kTransparent;
  };
  for (const core::SectionSegment& s : section.segments) {
    if (!visible(s.element) || s.a_m == s.b_m) continue;
    const bool mesh = statics && s.element >= first_mesh_element_ &&
                      s.element < first_mesh_element_ + mesh_elements_;
    segments->push_back({s.a_m, s.b_m - s.a_m, s.element, elements[s.element].group, mesh});
  }
  for (const core::SectionCircle& c : section.circles) {
    if (!visible(c.element) || !(c.radius_m > 0.0)) continue;
    circles->push_back({c.center_m, c.radius_m, c.radius_m * c.radius_m, c.element,
                        elements[c.element].group, c.major_axis, c.squash});
  }
}

void PlanarSlice::SetUpGrid(const core::PlanarSection& statics) {
  const Floor& floor = world_.description().floor;
  Eigen::Vector2d lo = floor.min_m.cwiseMin(floor.max_m);
  Eigen::Vector2d hi = floor.min_m.cwiseMax(floor.max_m);
  Eigen::Vector2d slo, shi;
  if (statics.Bounds(&slo, &shi)) {
    lo = lo.cwiseMin(slo);
    hi = hi.cwiseMax(shi);
  }
  lo.array() -= kGridPaddingM;
  hi.array() += kGridPaddingM;
  cell_m_ = options_.cell_size_m;
  const Eigen::Vector2d size = hi - lo;
  while ((size.x() / cell_m_ + 1) * (size.y() / cell_m_ + 1) > kMaxCells) cell_m_ *= 2.0;
  inv_cell_ = 1.0 / cell_m_;
  origin_m_ = lo;
  nx_ = std::max(1, static_cast<int>(std::ceil(size.x() * inv_cell_)));
  ny_ = std::max(1, static_cast<int>(std::ceil(size.y() * inv_cell_)));
}

// Cells overlapped by the box [lo, hi] grown by the margin; false when it
// reaches beyond the grid (then the primitive is kept apart).
bool PlanarSlice::CellRange(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, int* x0, int* y0,
                            int* x1, int* y1) const {
  const double fx0 = std::floor((lo.x() - kCellMarginM - origin_m_.x()) * inv_cell_);
  const double fy0 = std::floor((lo.y() - kCellMarginM - origin_m_.y()) * inv_cell_);
  const double fx1 = std::floor((hi.x() + kCellMarginM - origin_m_.x()) * inv_cell_);
  const double fy1 = std::floor((hi.y() + kCellMarginM - origin_m_.y()) * inv_cell_);
  if (!(fx0 >= 0 && fy0 >= 0 && fx1 < nx_ && fy1 < ny_)) return false;
  *x0 = static_cast<int>(fx0);
  *y0 = static_cast<int>(fy0);
  *x1 = static_cast<int>(fx1);
  *y1 = static_cast<int>(fy1);
  return true;
}

void PlanarSlice::Buckets::Clear(int cell_count) {
  if (cells.size() != static_cast<std::size_t>(cell_count)) {
    cells.assign(cell_count, CellSpans{});
  } else {
    for (const int c : touched) cells[c] = CellSpans{};
  }
  touched.clear();
}

void PlanarSlice::Buckets::CountsToBegins() {
  int segment_count = 0;
  int circle_count = 0;
  for (const int c : touched) {
    CellSpans& span = cells[c];
    span.segment_begin = segment_count;
    segment_count += span.segment_end;
    span.segment_end = span.segment_begin;
    span.circle_begin = circle_count;
    circle_count += span.circle_end;
    span.circle_end = span.circle_begin;
  }
  segments.resize(segment_count);
  circles.resize(circle_count);
}

void PlanarSlice::Fill(const std::vector<Segment>& segments, const std::vector<Circle>& circles,
                       Buckets* buckets, std::vector<Segment>* outside_segments,
                       std::vector<Circle>* outside_circles) const {
  const int cells = nx_ * ny_;
  // A segment is bucketed into the cells of its bounding box that its line
  // passes within the margin of (the box's corners not all on one side).
  const auto touches = [&](const Segment& s, int ix, int iy) {
    const Eigen::Vector2d n(-s.edge_m.y(), s.edge_m.x());
    const double slack = kCellMarginM * n.norm();
    const double x0 = origin_m_.x() + ix * cell_m_, y0 = origin_m_.y() + iy * cell_m_;
    bool neg = false, pos = false;
    for (const double x : {x0, x0 + cell_m_}) {
      for (const double y : {y0, y0 + cell_m_}) {
        const double side = n.dot(Eigen::Vector2d(x, y) - s.a_m);
        neg = neg || side <= slack;
        pos = pos || side >= -slack;
      }
    }
    return neg && pos;
  };
  // Two passes (count, then place) over the same cell lists.
  const auto for_segment_cells = [&](const Segment& s, auto&& visit) {
    const Eigen::Vector2d b = s.a_m + s.edge_m;
    int x0, y0, x1, y1;
    if (!CellRange(s.a_m.cwiseMin(b), s.a_m.cwiseMax(b), &x0, &y0, &x1, &y1)) return false;
    for (int iy = y0; iy <= y1; ++iy) {
      for (int ix = x0; ix <= x1; ++ix) {
        if (touches(s, ix, iy)) visit(iy * nx_ + ix);
      }
    }
    return true;
  };
  const auto for_circle_cells = [&](const Circle& c, auto&& visit) {
    const Eigen::Vector2d r = Eigen::Vector2d::Constant(c.radius_m / c.squash);
    int x0, y0, x1, y1;
    if (!CellRange(c.center_m - r, c.center_m + r, &x0, &y0, &x1, &y1)) return false;
    for (int iy = y0; iy <= y1; ++iy) {
      for (int ix = x0; ix <= x1; ++ix) visit(iy * nx_ + ix);
    }
    return true;
  };
  // Count into the ends, turn the counts into begins, then place (each
  // placement moving its cell's end up to where the count left it). Only the
  // cells touched last time are cleared and only those touched now summed:
  // the dynamic bodies cover a few hundred of the grid's thousands of cells,
  // and the grid is refilled every tick.
  buckets->Clear(cells);
  const auto count = [&](int c, int CellSpans::*end) {
    CellSpans& span = buckets->cells[c];
    if (span.segment_end == 0 && span.circle_end == 0) buckets->touched.push_back(c);
    ++(span.*end);
  };
  for (const Segment& s : segments) {
    if (!for_segment_cells(s, [&](int c) { count(c, &CellSpans::segment_end); })) {
      outside_segments->push_back(s);
    }
  }
  for (const Circle& c : circles) {
    if (!for_circle_cells(c, [&](int cell) { count(cell, &CellSpans::circle_end); })) {
      outside_circles->push_back(c);
    }
  }
  buckets->CountsToBegins();
  for (const Segment& s : segments) {
    for_segment_cells(s, [&](int c) { buckets->segments[buckets->cells[c].segment_end++] = s; });
  }
  for (const Circle& circle : circles) {
    for_circle_cells(circle,
                     [&](int c) { buckets->circles[buckets->cells[c].circle_end++] = circle; });
  }
  // Each segment learns where the run of its group's segments in its cell
  // ends, so that a ray skips its own robot's outline in one step.
  for (const int c : buckets->touched) {
    const CellSpans& span = buckets->cells[c];
    for (int k = span.segment_end - 1; k >= span.segment_begin; --k) {
      Segment& segment = buckets->segments[k];
      const bool run_goes_on =
          k + 1 < span.segment_end && buckets->segments[k + 1].group == segment.group;
      segment.group_run_end = run_goes_on ? buckets->segments[k + 1].group_run_end : k + 1;
    }
  }
}

void PlanarSlice::UpdateStatic() {
  const core::PlanarSection section = world_.StaticSectionAt(height_m_);
  SetUpGrid(section);
  std::vector<Segment> segments;
  std::vector<Circle> circles;
  Split(section, true, &segments, &circles);
  std::vector<Segment> outside_segments;
  std::vector<Circle> outside_circles;
  Fill(segments, circles, &static_, &outside_segments, &outside_circles);
  // The grid covers the static geometry, so nothing is left outside.
  UpdateDynamic();
}

void PlanarSlice::UpdateDynamic() {
  core::PlanarSection section;
  section.height_m = height_m_;
  uncut_.clear();
  world_.AppendDynamicSection(height_m_, options_.max_tilt_rad, &section, &uncut_);
  std::vector<Segment> segments;
  std::vector<Circle> circles;
  Split(section, false, &segments, &circles);
  outside_segments_.clear();
  outside_circles_.clear();
  Fill(segments, circles, &dynamic_, &outside_segments_, &outside_circles_);
}

bool PlanarSlice::Covers(const Eigen::Vector2d& center_m, double radius_m, int ignore_group) const {
  const auto& elements = world_.elements();
  for (const UncutElement& u : uncut_) {
    if (ignore_group >= 0 && elements[u.element].group == ignore_group) continue;
    if (elements[u.element].laser == core::LaserResponse::kTransparent) continue;
    if ((u.center_m - center_m).norm() < radius_m + u.radius_m) return false;
  }
  return true;
}

Eigen::Vector2d PlanarSlice::Unsquash(const Circle& c, const Eigen::Vector2d& v) {
  return v - (1.0 - c.squash) * c.major_axis.dot(v) * c.major_axis;
}

// The closest hit of a ray so far. Tests are written so that most rejections
// need no division.
struct PlanarSlice::Best {
  Eigen::Vector2d o;
  Eigen::Vector2d d;
  double t;  // the closest hit so far, or the ray's length
  int ignore_group;
  const Segment* segment = nullptr;
  const Circle* circle = nullptr;

  void Test(const Segment& s) {
    // The casting robot's own outline lies in the cells round every ray's
    // origin: rejected before any arithmetic.
    if (s.group >= 0 && s.group == ignore_group) return;
    // o + t·d = a + u·e: t = (ao × e)/(d × e), u = (ao × d)/(d × e). d × e is
    // d·n for the outward normal n = e rotated by −90°: < 0 entering the solid.
    double den = d.x() * s.edge_m.y() - d.y() * s.edge_m.x();
    const Eigen::Vector2d ao = s.a_m - o;
    double tn = ao.x() * s.edge_m.y() - ao.y() * s.edge_m.x();
    double un = ao.x() * d.y() - ao.y() * d.x();
    if (den < 0.0) {
      den = -den;
      tn = -tn;
      un = -un;
    } else if (!(den > 0.0 && s.two_sided)) {
      return;  // parallel, or leaving a solid
    }
    if (!(tn > 0.0) || !(tn < t * den) || un < 0.0 || un > den) return;
    t = tn / den;
    segment = &s;
    circle = nullptr;
  }

  void Test(const Circle& c) {
    if (c.group >= 0 && c.group == ignore_group) return;
    if (c.squash != 1.0) return TestEllipse(c);
    const Eigen::Vector2d oc = o - c.center_m;
    const double b = oc.dot(d);
    if (b >= 0.0) return;  // moving away from the centre (or inside): no hit ahead
    const double cc = oc.squaredNorm() - c.radius_sq;
    if (cc <= 0.0) return;             // starts inside
    if (-b - c.radius_m >= t) return;  // t >= -b - r: no closer than the best
    const double disc = b * b - cc;
    if (disc < 0.0) return;
    // -b - √disc without cancellation: cc / (-b + √disc).
    Take(c, cc / (-b + std::sqrt(disc)));
  }

  // The ellipse scaled by its squash along the major axis is the circle of
  // radius r (Unsquash); the ray's parameter t is the same in both.
  void TestEllipse(const Circle& c) {
    const Eigen::Vector2d oc = Unsquash(c, o - c.center_m);
    const Eigen::Vector2d dc = Unsquash(c, d);
    const double b = oc.dot(dc);
    if (b >= 0.0) return;
    const double cc = oc.squaredNorm() - c.radius_sq;
    if (cc <= 0.0) return;
    const double disc = b * b - dc.squaredNorm() * cc;
    if (disc < 0.0) return;
    Take(c, cc / (-b + std::sqrt(disc)));
  }

  // The circle's or ellipse's hit at hit_t, if ahead and closer than the best.
  void Take(const Circle& c, double hit_t) {
    if (!(hit_t > 0.0 && hit_t < t)) return;
    t = hit_t;
    circle = &c;
    segment = nullptr;
  }
};

// Inlined into Cast, the caster's hot path (called once per ray).
[[gnu::always_inline]] inline RayHit PlanarSlice::ToHit(const Best& best, double z_m) {
  const Eigen::Vector2d& o = best.o;
  const Eigen::Vector2d& d = best.d;
  RayHit hit;
  if (best.segment == nullptr && best.circle == nullptr) return hit;
  hit.hit = true;
  hit.distance_m = best.t;
  const Eigen::Vector2d point = o + best.t * d;
  hit.point_m = {point.x(), point.y(), z_m};
  Eigen::Vector2d n;
  if (best.segment != nullptr) {
    const Eigen::Vector2d& e = best.segment->edge_m;
    n = Eigen::Vector2d(e.y(), -e.x()).normalized();
    if (n.dot(d) > 0.0) n = -n;  // a two-sided mesh cut met from behind
    hit.element = best.segment->element;
  } else {
    const Circle& c = *best.circle;
    // The gradient of |Unsquash(p - centre)|^2.
    n = c.squash == 1.0 ? (point - c.center_m).normalized()
                        : Unsquash(c, Unsquash(c, point - c.center_m)).normalized();
    hit.element = c.element;
  }
  hit.normal = {n.x(), n.y(), 0.0};
  return hit;
}

RayHit PlanarSlice::Cast(const Eigen::Vector3d& origin_m, const Eigen::Vector2d& direction,
                         double max_range_m, int ignore_group) const {
  Best best{origin_m.head<2>(), direction, max_range_m, ignore_group};
  for (const Segment& s : outside_segments_) best.Test(s);
  for (const Circle& c : outside_circles_) best.Test(c);

  // The ray's part inside the grid.
  const Eigen::Vector2d& o = best.o;
  const Eigen::Vector2d& d = best.d;
  double t_in = 0.0;
  double t_out = max_range_m;
  const Eigen::Vector2d hi = origin_m_ + Eigen::Vector2d(nx_ * cell_m_, ny_ * cell_m_);
  for (int k = 0; k < 2; ++k) {
    if (d[k] == 0.0) {
      if (o[k] < origin_m_[k] || o[k] > hi[k]) t_out = -1.0;
      continue;
    }
    const double ta = (origin_m_[k] - o[k]) / d[k];
    const double tb = (hi[k] - o[k]) / d[k];
    t_in = std::max(t_in, std::min(ta, tb));
    t_out = std::min(t_out, std::max(ta, tb));
  }
  if (t_in <= t_out) {
    // Walk the cells from the entry point (DDA, Amanatides & Woo).
    const Eigen::Vector2d p = o + t_in * d;
    int ix =
        std::clamp(static_cast<int>(std::floor((p.x() - origin_m_.x()) * inv_cell_)), 0, nx_ - 1);
    int iy =
        std::clamp(static_cast<int>(std::floor((p.y() - origin_m_.y()) * inv_cell_)), 0, ny_ - 1);
    constexpr double kInf = std::numeric_limits<double>::infinity();
    const int step_x = d.x() > 0.0 ? 1 : -1;
    const int step_y = d.y() > 0.0 ? 1 : -1;
    const double dt_x = d.x() != 0.0 ? cell_m_ / std::abs(d.x()) : kInf;
    const double dt_y = d.y() != 0.0 ? cell_m_ / std::abs(d.y()) : kInf;
    double next_x = d.x() != 0.0
                        ? (origin_m_.x() + (ix + (d.x() > 0.0 ? 1 : 0)) * cell_m_ - o.x()) / d.x()
                        : kInf;
    double next_y = d.y() != 0.0
                        ? (origin_m_.y() + (iy + (d.y() > 0.0 ? 1 : 0)) * cell_m_ - o.y()) / d.y()
                        : kInf;
    for (;;) {
      const int cell = iy * nx_ + ix;
      const CellSpans& fixed = static_.cells[cell];
      const CellSpans& moving = dynamic_.cells[cell];
      for (int k = fixed.segment_begin; k < fixed.segment_end; ++k) best.Test(static_.segments[k]);
      for (int k = fixed.circle_begin; k < fixed.circle_end; ++k) best.Test(static_.circles[k]);
      for (int k = moving.segment_begin; k < moving.segment_end;) {
        const Segment& segment = dynamic_.segments[k];
        if (segment.group >= 0 && segment.group == ignore_group) {
          k = segment.group_run_end;  // the casting robot's own outline
          continue;
        }
        best.Test(segment);
        ++k;
      }
      for (int k = moving.circle_begin; k < moving.circle_end; ++k) best.Test(dynamic_.circles[k]);
      // Every hit closer than the best lies in a cell visited by now once the
      // best is no farther than this cell's exit (or the ray ends in it).
      const double exit_t = std::min(next_x, next_y);
      if (best.t <= exit_t || exit_t >= t_out) break;
      if (next_x < next_y) {
        ix += step_x;
        if (ix < 0 || ix >= nx_) break;
        next_x += dt_x;
      } else {
        iy += step_y;
        if (iy < 0 || iy >= ny_) break;
        next_y += dt_y;
      }
    }
  }
  return ToHit(best, origin_m.z());
}

PlanarCaster::PlanarCaster(const World* world, PlanarCasterOptions options)
    : world_(world), options_(options) {
  options_.Validate();
  tick_ = world_->tick();
  static_revision_ = world_->static_revision();
}

void PlanarCaster::Update() {
  if (world_->static_revision() != static_revision_) {
    static_revision_ = world_->static_revision();
    tick_ = world_->tick();
    for (auto& [height, slice] : slices_) slice->UpdateStatic();  // and the dynamic part
    return;
  }
  if (world_->tick() != tick_) Refresh();
}

void PlanarCaster::Refresh() {
  tick_ = world_->tick();
  for (auto& [height, slice] : slices_) slice->UpdateDynamic();
}

const PlanarSlice& PlanarCaster::SliceAt(double height_m) {
  Update();
  auto it = slices_.find(height_m);
  if (it == slices_.end()) {
    it =
        slices_.emplace(height_m, std::make_unique<PlanarSlice>(*world_, height_m, options_)).first;
  }
  return *it->second;
}

}  // namespace pavilion::sim
