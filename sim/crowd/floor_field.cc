#include "sim/crowd/floor_field.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/geometry/segment2.h"

namespace pavilion::sim::crowd {
namespace {

constexpr double kMaxCellM = 2.0;
constexpr double kMaxClearanceM = 2.0;
// Cells per grid: 2^24 is 820 m x 820 m at 0.2 m (64 MB of kinds, 80 MB per field).
constexpr double kMaxCells = 16777216.0;
// A side that is a whole number of cells up to rounding gets no extra column.
constexpr double kCellCountTolerance = 1e-9;
// Walking cost in clearance cells relative to free floor. The escape potential
// then rises steeply into the clearance, so that a clearance cell's lowest
// neighbour lies outwards rather than along the wall (the continuous descent
// would leave the clearance at acos(1 / 3) = 71 deg from the wall).
constexpr double kEscapeSlowness = 3.0;
// The second-order one-sided difference (3u - 4u1 + u2) / 2h is 3/2h (u - T)
// with T = (4u1 - u2) / 3: its term in the eikonal equation carries (3/2)^2
// (Sethian 1999).
constexpr double kSecondOrderWeight = 2.25;
// Cell squares are grown by this much (m) for the touch test, so that a wall
// along a cell boundary touches the cells on both sides despite rounding
// (else its cells might be clearance only, and the escape potential cross it).
constexpr double kTouchToleranceM = 1e-9;
// Padding around a field's cells: the second-order stencil reaches two cells.
constexpr int kPad = 2;
// Below this slope (m/m; the field's slope is 1 wherever it is smooth) the
// interpolated gradient gives no direction.
constexpr double kMinSlope = 1e-3;

constexpr float kInfinity = std::numeric_limits<float>::infinity();
constexpr std::uint8_t kFreeFlag = 1;
constexpr std::uint8_t kClearanceFlag = 2;
constexpr std::uint8_t kGoalFlag = 4;

void Require(bool ok, const std::string& what, const char* expected) {
  if (!ok) throw std::invalid_argument(what + " must be " + expected);
}

// True when segment a-b touches the closed axis-aligned square of half side
// `half` around `center`: their boxes overlap and the square's corners do not
// all lie strictly on one side of the segment's line (separating axes).
bool SegmentTouchesSquare(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                          const Eigen::Vector2d& center, double half) {
  const Eigen::Vector2d lo = center.array() - half;
  const Eigen::Vector2d hi = center.array() + half;
  if ((a.cwiseMax(b).array() < lo.array()).any() || (a.cwiseMin(b).array() > hi.array()).any()) {
    return false;
  }
  const Eigen::Vector2d ab = b - a;
  int above = 0;
  int below = 0;
  for (const Eigen::Vector2d& corner :
       {lo, hi, Eigen::Vector2d(lo.x(), hi.y()), Eigen::Vector2d(hi.x(), lo.y())}) {
    const double side = core::Cross(ab, corner - a);
    above += side > 0.0;
    below += side < 0.0;
  }
  return above < 4 && below < 4;
}

// The cells [col0, col1] x [row0, row1] of a grid (origin min_m, side cell_m,
// cols x rows) whose squares overlap the box [lo, hi]; empty when col1 < col0
// or row1 < row0.
struct CellBox {
  int col0 = 0;
  int row0 = 0;
  int col1 = -1;
  int row1 = -1;
};

CellBox CellsOverlapping(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                         const Eigen::Vector2d& min_m, double cell_m, int cols, int rows) {
  const Eigen::Vector2d a = (lo - min_m) / cell_m;
  const Eigen::Vector2d b = (hi - min_m) / cell_m;
  if (!(b.x() >= 0.0 && b.y() >= 0.0 && a.x() < cols && a.y() < rows)) return {};
  // Clamped before the conversion, so that far-off coordinates cannot overflow.
  return {static_cast<int>(std::floor(std::max(a.x(), 0.0))),
          static_cast<int>(std::floor(std::max(a.y(), 0.0))),
          static_cast<int>(std::floor(std::min(b.x(), cols - 1.0))),
          static_cast<int>(std::floor(std::min(b.y(), rows - 1.0)))};
}

// One axis's term c (u - T)^2 of the discrete eikonal equation; c = 0 when
// no neighbour along the axis is known.
struct AxisTerm {
  double weight = 0.0;
  double upwind = std::numeric_limits<double>::infinity();
};

// The larger root u of sum c_i (u - T_i)^2 = step^2 over the axis terms, using
// only the smaller T when the larger one lies above the one-term solution
// (the upwind condition u >= T_i of Sethian 1996).
double SolveEikonal(AxisTerm a, AxisTerm b, double step) {
  if (a.upwind > b.upwind) std::swap(a, b);
  const double one_term = a.upwind + step / std::sqrt(a.weight);
  if (!(b.upwind < one_term)) return one_term;  // also when b is unknown (+inf)
  // (a_w + b_w) u^2 - 2 (a_w a_T + b_w b_T) u + a_w a_T^2 + b_w b_T^2 - step^2 = 0;
  // at u = b_T the left side is negative, so the larger root exceeds b_T.
  const double qa = a.weight + b.weight;
  const double qb = a.weight * a.upwind + b.weight * b.upwind;
  const double qc = a.weight * a.upwind * a.upwind + b.weight * b.upwind * b.upwind - step * step;
  return (qb + std::sqrt(std::max(0.0, qb * qb - qa * qc))) / qa;
}

// How a phase of the march updates a trial cell.
struct Scheme {
  std::uint8_t allowed = 0;   // flags of the cells the phase reaches
  double step = 0.0;          // cost (m) of one cell side: cell side times slowness
  bool second_order = false;  // along the axes, where two known cells lie upwind
  // Also solve on the diagonal stencil (spacing step sqrt 2) and keep the
  // smaller value: the multi-stencil method of Hassouna & Farag 2007
  // ("Multistencils fast marching methods", IEEE PAMI 29:1563-1574), first
  // order. It carries the front along staircase boundaries, where the axis
  // stencil sees one known neighbour and would count Manhattan steps.
  bool diagonal = false;
};

// The trial cells of a march: a binary min-heap on (value, cell index), so
// that equal values pop in index order, with the heap position of every cell
// for decrease-key (the heap holds the front only, no stale entries).
class TrialHeap {
 public:
  explicit TrialHeap(std::size_t cells) : position_(cells, -1) {}

  bool empty() const { return entries_.empty(); }

  // Inserts cell k with `value`, or lowers its value to `value`.
  void Push(float value, std::int32_t k) {
    std::int32_t i = position_[k];
    if (i < 0) {
      i = static_cast<std::int32_t>(entries_.size());
      entries_.emplace_back(value, k);
    } else {
      entries_[i].first = value;
    }
    SiftUp(i);
  }

  // Removes the cell with the smallest (value, index) and returns it.
  std::int32_t Pop() {
    const std::int32_t top = entries_.front().second;
    position_[top] = -1;
    entries_.front() = entries_.back();
    entries_.pop_back();
    if (!entries_.empty()) SiftDown(0);
    return top;
  }

 private:
  void Place(std::int32_t i, const std::pair<float, std::int32_t>& entry) {
    entries_[i] = entry;
    position_[entry.second] = i;
  }
  void SiftUp(std::int32_t i) {
    const std::pair<float, std::int32_t> entry = entries_[i];
    while (i > 0 && entry < entries_[(i - 1) / 2]) {
      Place(i, entries_[(i - 1) / 2]);
      i = (i - 1) / 2;
    }
    Place(i, entry);
  }
  void SiftDown(std::int32_t i) {
    const std::pair<float, std::int32_t> entry = entries_[i];
    const std::int32_t n = static_cast<std::int32_t>(entries_.size());
    for (std::int32_t child = 2 * i + 1; child < n; child = 2 * i + 1) {
      if (child + 1 < n && entries_[child + 1] < entries_[child]) ++child;
      if (!(entries_[child] < entry)) break;
      Place(i, entries_[child]);
      i = child;
    }
    Place(i, entry);
  }

  std::vector<std::pair<float, std::int32_t>> entries_;
  std::vector<std::int32_t> position_;  // per cell: its index in entries_, -1 when not queued
};

// The fast marching method over a padded field (Sethian 1996): the trial cell
// lowest in value (ties: lowest index, so the order is reproducible) becomes
// known and updates its unknown neighbours, until no trial cell is left.
class FastMarch {
 public:
  FastMarch(std::vector<float>* potential, const std::vector<std::uint8_t>& flags, int stride)
      : potential_(*potential),
        flags_(flags),
        stride_(stride),
        known_(flags.size(), 0),
        heap_(flags.size()) {}

  bool known(std::int32_t k) const { return known_[k] != 0; }
  void SetKnown(std::int32_t k) { known_[k] = 1; }

  // Updates the unknown neighbours the scheme reaches of the known cell k.
  void UpdateNeighbours(std::int32_t k, const Scheme& scheme) {
    const std::int32_t edge[4] = {1, -1, stride_, -stride_};
    const std::int32_t corner[4] = {stride_ + 1, stride_ - 1, -stride_ + 1, -stride_ - 1};
    for (const std::int32_t d : edge) Update(k + d, scheme);
    if (!scheme.diagonal) return;
    for (const std::int32_t d : corner) Update(k + d, scheme);
  }

  // Pops trial cells until none is left.
  void Run(const Scheme& scheme) {
    while (!heap_.empty()) {
      const std::int32_t k = heap_.Pop();
      SetKnown(k);
      UpdateNeighbours(k, scheme);
    }
  }

 private:
  // Recomputes cell k, if unknown and reached by the scheme, from its known
  // neighbours, and queues it when its value drops.
  void Update(std::int32_t k, const Scheme& scheme) {
    if (known(k) || (flags_[k] & scheme.allowed) == 0) return;
    double u = SolveEikonal(Term(k, 1, scheme.second_order), Term(k, stride_, scheme.second_order),
                            scheme.step);
    if (scheme.diagonal) {
      u = std::min(u, SolveEikonal(Term(k, stride_ + 1, false), Term(k, stride_ - 1, false),
                                   std::numbers::sqrt2 * scheme.step));
    }
    if (u < potential_[k]) {
      potential_[k] = static_cast<float>(u);
      heap_.Push(potential_[k], k);
    }
  }

  // The term along the direction with index step d: the known neighbour with
  // the smaller value, second order when the cell beyond it is known and not
  // higher (Sethian 1999).
  AxisTerm Term(std::int32_t k, std::int32_t d, bool second_order) const {
    const double forward = known(k + d) ? potential_[k + d] : kInfinity;
    const double backward = known(k - d) ? potential_[k - d] : kInfinity;
    const std::int32_t s = forward <= backward ? d : -d;
    const double u1 = std::min(forward, backward);
    if (!std::isfinite(u1)) return {};
    if (second_order && known(k + 2 * s) && potential_[k + 2 * s] <= u1) {
      return {kSecondOrderWeight, (4.0 * u1 - potential_[k + 2 * s]) / 3.0};
    }
    return {1.0, u1};
  }

  std::vector<float>& potential_;
  const std::vector<std::uint8_t>& flags_;
  std::int32_t stride_;
  std::vector<std::uint8_t> known_;
  TrialHeap heap_;
};

}  // namespace

// ---------------------------------------------------------------- WalkableGrid

void WalkableGridOptions::Validate() const {
  Require(cell_m > 0.0 && cell_m <= kMaxCellM, "WalkableGridOptions.cell_m", "in (0, 2] m");
  Require(clearance_m >= 0.0 && clearance_m <= kMaxClearanceM, "WalkableGridOptions.clearance_m",
          "in [0, 2] m");
}

WalkableGrid::WalkableGrid(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m,
                           const std::vector<ObstacleSegment>& segments,
                           const std::vector<ObstacleCircle>& circles,
                           const WalkableGridOptions& options)
    : options_(options), min_m_(min_m), max_m_(max_m) {
  options_.Validate();
  Require(min_m.allFinite() && max_m.allFinite(), "WalkableGrid: min_m and max_m", "finite");
  Require(max_m.x() > min_m.x() && max_m.y() > min_m.y(), "WalkableGrid: max_m",
          "above min_m in x and y");
  const Eigen::Vector2d sides = (max_m - min_m) / options_.cell_m;
  Require(std::ceil(sides.x()) * std::ceil(sides.y()) <= kMaxCells, "WalkableGrid: the floor",
          "at most 2^24 cells (raise cell_m or shrink min_m..max_m)");
  cols_ = std::max(1, static_cast<int>(std::ceil(sides.x() - kCellCountTolerance)));
  rows_ = std::max(1, static_cast<int>(std::ceil(sides.y() - kCellCountTolerance)));
  kinds_.assign(static_cast<std::size_t>(cols_) * static_cast<std::size_t>(rows_), CellKind::kFree);
  // The last column and row stick out past max_m; where a centre does, the cell is off the floor.
  for (int row = 0; row < rows_; ++row) {
    for (int col = 0; col < cols_; ++col) {
      const Eigen::Vector2d c = CellCenter({col, row});
      if (c.x() > max_m_.x() || c.y() > max_m_.y()) Mark({col, row}, CellKind::kObstacle);
    }
  }
  std::vector<std::pair<std::int32_t, std::int32_t>> touches;  // (cell, obstacle id)
  for (std::size_t i = 0; i < segments.size(); ++i) {
    Require(segments[i].a_m.allFinite() && segments[i].b_m.allFinite(),
            "WalkableGrid: segments[" + std::to_string(i) + "]", "finite");
    MarkSegment(segments[i], static_cast<std::int32_t>(i), &touches);
  }
  for (std::size_t i = 0; i < circles.size(); ++i) {
    const ObstacleCircle& c = circles[i];
    Require(c.center_m.allFinite() && std::isfinite(c.radius_m) && c.radius_m >= 0.0,
            "WalkableGrid: circles[" + std::to_string(i) + "]", "finite with radius_m >= 0");
    MarkCircle(c, -1 - static_cast<std::int32_t>(i), &touches);
  }
  auto obstacles = std::make_shared<CellObstacles>();
  obstacles->segments = segments;
  obstacles->circles = circles;
  std::sort(touches.begin(), touches.end());
  obstacles->start.assign(kinds_.size() + 1, 0);
  for (const auto& [cell, id] : touches) ++obstacles->start[cell + 1];
  for (std::size_t c = 0; c < kinds_.size(); ++c) obstacles->start[c + 1] += obstacles->start[c];
  for (const auto& [cell, id] : touches) obstacles->ids.push_back(id);
  obstacles_ = std::move(obstacles);
}

bool CellObstacles::Blocks(std::size_t c, const Eigen::Vector2d& a_m,
                           const Eigen::Vector2d& b_m) const {
  for (std::int32_t i = start[c]; i < start[c + 1]; ++i) {
    const std::int32_t id = ids[i];
    if (id >= 0) {
      if (core::SegmentsCross(a_m, b_m, segments[id].a_m, segments[id].b_m)) return true;
      continue;
    }
    const ObstacleCircle& circle = circles[-1 - id];
    if ((a_m - circle.center_m).norm() >= circle.radius_m &&
        core::PointSegmentDistance(circle.center_m, a_m, b_m) < circle.radius_m) {
      return true;
    }
  }
  return false;
}

bool WalkableGrid::Contains(const Eigen::Vector2d& p_m) const {
  return p_m.x() >= min_m_.x() && p_m.x() <= max_m_.x() && p_m.y() >= min_m_.y() &&
         p_m.y() <= max_m_.y();
}

std::optional<FloorCell> WalkableGrid::CellAt(const Eigen::Vector2d& p_m) const {
  if (!Contains(p_m)) return std::nullopt;
  const Eigen::Vector2d q = (p_m - min_m_) / options_.cell_m;
  return FloorCell(std::min(static_cast<int>(q.x()), cols_ - 1),
                   std::min(static_cast<int>(q.y()), rows_ - 1));
}

bool WalkableGrid::IsFree(const Eigen::Vector2d& p_m) const {
  const std::optional<FloorCell> cell = CellAt(p_m);
  return cell && kind(*cell) == CellKind::kFree;
}

void WalkableGrid::MarkSegment(const ObstacleSegment& segment, std::int32_t id,
                               std::vector<std::pair<std::int32_t, std::int32_t>>* touches) {
  const double half = 0.5 * options_.cell_m + kTouchToleranceM;
  const double reach = std::max(options_.clearance_m, half);
  const CellBox box = CellsOverlapping(segment.a_m.cwiseMin(segment.b_m).array() - reach,
                                       segment.a_m.cwiseMax(segment.b_m).array() + reach, min_m_,
                                       options_.cell_m, cols_, rows_);
  for (int row = box.row0; row <= box.row1; ++row) {
    for (int col = box.col0; col <= box.col1; ++col) {
      const Eigen::Vector2d c = CellCenter({col, row});
      if (SegmentTouchesSquare(segment.a_m, segment.b_m, c, half)) {
        Mark({col, row}, CellKind::kObstacle);
        touches->emplace_back(static_cast<std::int32_t>(Index({col, row})), id);
      } else if (core::PointSegmentDistance(c, segment.a_m, segment.b_m) < options_.clearance_m) {
        Mark({col, row}, CellKind::kClearance);
      }
    }
  }
}

void WalkableGrid::MarkCircle(const ObstacleCircle& circle, std::int32_t id,
                              std::vector<std::pair<std::int32_t, std::int32_t>>* touches) {
  const double half = 0.5 * options_.cell_m + kTouchToleranceM;
  const double reach = circle.radius_m + std::max(options_.clearance_m, half);
  const CellBox box =
      CellsOverlapping(circle.center_m.array() - reach, circle.center_m.array() + reach, min_m_,
                       options_.cell_m, cols_, rows_);
  for (int row = box.row0; row <= box.row1; ++row) {
    for (int col = box.col0; col <= box.col1; ++col) {
      const Eigen::Vector2d c = CellCenter({col, row});
      // The point of the closed cell square nearest to the circle's centre.
      const Eigen::Vector2d nearest = circle.center_m.cwiseMax(c - Eigen::Vector2d::Constant(half))
                                          .cwiseMin(c + Eigen::Vector2d::Constant(half));
      if ((nearest - circle.center_m).norm() <= circle.radius_m) {
        Mark({col, row}, CellKind::kObstacle);
        touches->emplace_back(static_cast<std::int32_t>(Index({col, row})), id);
      } else if ((c - circle.center_m).norm() < circle.radius_m + options_.clearance_m) {
        Mark({col, row}, CellKind::kClearance);
      }
    }
  }
}

void WalkableGrid::Mark(const FloorCell& cell, CellKind kind) {
  CellKind& k = kinds_[Index(cell)];
  k = std::max(k, kind);
}

// --------------------------------------------------------------- DistanceField

struct DistanceField::GoalShape {
  Eigen::Vector2d lo_m;  // a box holding the goal
  Eigen::Vector2d hi_m;
  // Signed Euclidean distance from a point to the goal's boundary (m):
  // negative inside, 0 on the boundary, positive outside.
  std::function<double(const Eigen::Vector2d&)> signed_distance_m;
};

struct DistanceField::Patch {
  double value = 0.0;                                  // m
  Eigen::Vector2d gradient = Eigen::Vector2d::Zero();  // m/m
};

DistanceField::DistanceField(const WalkableGrid& grid)
    : min_m_(grid.min_m()),
      max_m_(grid.max_m()),
      cell_m_(grid.cell_m()),
      cols_(grid.cols()),
      rows_(grid.rows()),
      stride_(grid.cols() + 2 * kPad),
      obstacles_(grid.obstacles()) {
  const std::size_t padded =
      static_cast<std::size_t>(stride_) * static_cast<std::size_t>(rows_ + 2 * kPad);
  potential_.assign(padded, kInfinity);
  flags_.assign(padded, 0);
  for (int row = 0; row < rows_; ++row) {
    for (int col = 0; col < cols_; ++col) {
      const CellKind kind = grid.kind({col, row});
      flags_[PaddedIndex(col, row)] = kind == CellKind::kFree        ? kFreeFlag
                                      : kind == CellKind::kClearance ? kClearanceFlag
                                                                     : 0;
    }
  }
}

DistanceField DistanceField::ToDisc(const WalkableGrid& grid, const Eigen::Vector2d& center_m,
                                    double radius_m) {
  Require(center_m.allFinite(), "DistanceField::ToDisc: center_m", "finite");
  Require(std::isfinite(radius_m) && radius_m >= 0.0, "DistanceField::ToDisc: radius_m",
          "finite and >= 0 m");
  DistanceField field(grid);
  field.Compute({center_m.array() - radius_m, center_m.array() + radius_m,
                 [center_m, radius_m](const Eigen::Vector2d& p) {
                   return (p - center_m).norm() - radius_m;
                 }});
  return field;
}

DistanceField DistanceField::ToArea(const WalkableGrid& grid, const core::Polygon2& area) {
  Require(area.size() >= 3, "DistanceField::ToArea: area", "a polygon of >= 3 vertices");
  GoalShape goal{area.front(), area.front(), nullptr};
  for (const Eigen::Vector2d& v : area) {
    Require(v.allFinite(), "DistanceField::ToArea: area", "finite");
    goal.lo_m = goal.lo_m.cwiseMin(v);
    goal.hi_m = goal.hi_m.cwiseMax(v);
  }
  Require(core::IsSimple(area), "DistanceField::ToArea: area", "a simple polygon");
  goal.signed_distance_m = [&area](const Eigen::Vector2d& p) {
    double d = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < area.size(); ++i) {
      d = std::min(d, core::PointSegmentDistance(p, area[i], area[(i + 1) % area.size()]));
    }
    return core::Contains(area, p) ? -d : d;
  };
  DistanceField field(grid);
  field.Compute(goal);
  return field;
}

std::vector<std::int32_t> DistanceField::SeedGoal(const GoalShape& goal) {
  std::vector<std::int32_t> seeds;
  const CellBox box = CellsOverlapping(goal.lo_m, goal.hi_m, min_m_, cell_m_, cols_, rows_);
  for (int row = box.row0; row <= box.row1; ++row) {
    for (int col = box.col0; col <= box.col1; ++col) {
      const std::int32_t k = PaddedIndex(col, row);
      if ((flags_[k] & kFreeFlag) == 0) continue;
      const double d = goal.signed_distance_m(CenterOf(k));
      if (d > 0.0) continue;
      // Minus the centre's depth in the goal: the march then starts from the
      // goal's boundary, to within its own error, not from the cell centres.
      potential_[k] = static_cast<float>(d);
      flags_[k] |= kGoalFlag;
      seeds.push_back(k);
    }
  }
  if (!seeds.empty()) return seeds;
  // None is free: the free cell nearest to the goal stands in for it.
  double best = std::numeric_limits<double>::infinity();
  for (int row = 0; row < rows_; ++row) {
    for (int col = 0; col < cols_; ++col) {
      const std::int32_t k = PaddedIndex(col, row);
      if ((flags_[k] & kFreeFlag) == 0) continue;
      const double d = goal.signed_distance_m(CenterOf(k));
      if (d < best) {
        best = d;
        seeds.assign(1, k);
      }
    }
  }
  for (const std::int32_t k : seeds) {
    potential_[k] = 0.0f;
    flags_[k] |= kGoalFlag;
  }
  return seeds;
}

void DistanceField::Compute(const GoalShape& goal) {
  const std::vector<std::int32_t> seeds = SeedGoal(goal);
  FastMarch march(&potential_, flags_, stride_);
  for (const std::int32_t k : seeds) march.SetKnown(k);
  // The free cells, at unit cost.
  const Scheme walk{kFreeFlag, cell_m_, true, true};
  for (const std::int32_t k : seeds) march.UpdateNeighbours(k, walk);
  march.Run(walk);
  // The clearance cells next to reached free cells, then on into the clearance
  // at kEscapeSlowness (first order: the slowness jumps at the boundary).
  const Scheme escape{kClearanceFlag, kEscapeSlowness * cell_m_, false, false};
  for (int row = 0; row < rows_; ++row) {
    for (int col = 0; col < cols_; ++col) {
      const std::int32_t k = PaddedIndex(col, row);
      if (march.known(k) && (flags_[k] & kFreeFlag) != 0) march.UpdateNeighbours(k, escape);
    }
  }
  march.Run(escape);
}

std::int32_t DistanceField::PaddedIndex(int col, int row) const {
  return (row + kPad) * stride_ + col + kPad;
}

Eigen::Vector2d DistanceField::CenterOf(std::int32_t k) const {
  const int col = k % stride_ - kPad;
  const int row = k / stride_ - kPad;
  return min_m_ + cell_m_ * Eigen::Vector2d(col + 0.5, row + 0.5);
}

std::int32_t DistanceField::IndexAt(const Eigen::Vector2d& p_m) const {
  if (!(p_m.x() >= min_m_.x() && p_m.x() <= max_m_.x() && p_m.y() >= min_m_.y() &&
        p_m.y() <= max_m_.y())) {
    return -1;  // also NaN
  }
  const int col = std::min(static_cast<int>((p_m.x() - min_m_.x()) / cell_m_), cols_ - 1);
  const int row = std::min(static_cast<int>((p_m.y() - min_m_.y()) / cell_m_), rows_ - 1);
  return PaddedIndex(col, row);
}

bool DistanceField::Usable(std::int32_t k) const {
  return (flags_[k] & kFreeFlag) != 0 && std::isfinite(potential_[k]);
}

DistanceField::Patch DistanceField::Interpolate(const Eigen::Vector2d& p_m, std::int32_t k) const {
  // The four cell centres around p_m: corner c = x + 2 y, with x, y in {0, 1}.
  const double u = (p_m.x() - min_m_.x()) / cell_m_ - 0.5;
  const double v = (p_m.y() - min_m_.y()) / cell_m_ - 0.5;
  const int col = static_cast<int>(std::floor(u));
  const int row = static_cast<int>(std::floor(v));
  const double fx = u - col;
  const double fy = v - row;
  const std::int32_t base = PaddedIndex(col, row);
  const std::int32_t index[4] = {base, base + 1, base + stride_, base + stride_ + 1};
  double value[4];
  int missing = -1;
  int n_usable = 0;
  for (int c = 0; c < 4; ++c) {
    value[c] = potential_[index[c]];
    if (Usable(index[c])) {
      ++n_usable;
    } else {
      missing = c;
    }
  }
  Patch patch;
  if (n_usable >= 3) {
    // Bilinear, a missing corner on the plane of the other three.
    if (n_usable == 3) {
      value[missing] = value[missing ^ 1] + value[missing ^ 2] - value[missing ^ 3];
    }
    patch.value = (1 - fy) * ((1 - fx) * value[0] + fx * value[1]) +
                  fy * ((1 - fx) * value[2] + fx * value[3]);
    patch.gradient =
        Eigen::Vector2d((1 - fy) * (value[1] - value[0]) + fy * (value[3] - value[2]),
                        (1 - fx) * (value[2] - value[0]) + fx * (value[3] - value[1])) /
        cell_m_;
    return patch;
  }
  // Along a wall or in a gap one cell wide: differences over the usable edge
  // neighbours of p_m's own cell k, central where both are usable.
  auto slope = [&](std::int32_t d) {
    const bool forward = Usable(k + d);
    const bool backward = Usable(k - d);
    if (forward && backward) return (potential_[k + d] - potential_[k - d]) / (2.0 * cell_m_);
    if (forward) return (potential_[k + d] - potential_[k]) / cell_m_;
    if (backward) return (potential_[k] - potential_[k - d]) / cell_m_;
    return 0.0;
  };
  patch.gradient = Eigen::Vector2d(slope(1), slope(stride_));
  patch.value = potential_[k] + patch.gradient.dot(p_m - CenterOf(k));
  return patch;
}

bool DistanceField::Blocks(std::int32_t k, const Eigen::Vector2d& a_m,
                           const Eigen::Vector2d& b_m) const {
  const int col = k % stride_ - kPad;
  const int row = k / stride_ - kPad;
  if (col < 0 || row < 0 || col >= cols_ || row >= rows_) return false;
  return obstacles_->Blocks(static_cast<std::size_t>(row) * cols_ + col, a_m, b_m);
}

Eigen::Vector2d DistanceField::TowardsBestNeighbour(const Eigen::Vector2d& p_m, std::int32_t k,
                                                    std::uint8_t allowed) const {
  float best = potential_[k];
  Eigen::Vector2d target = p_m;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const std::int32_t n = k + dy * stride_ + dx;
      if ((dx == 0 && dy == 0) || (flags_[n] & allowed) == 0 || !(potential_[n] < best)) continue;
      // The move crosses cell k, cell n (touched by nothing: it is free or
      // clearance) and, diagonally, possibly the two cells beside both.
      const Eigen::Vector2d c = CenterOf(n);
      if (Blocks(k, p_m, c) ||
          (dx != 0 && dy != 0 && (Blocks(k + dx, p_m, c) || Blocks(k + dy * stride_, p_m, c)))) {
        continue;
      }
      best = potential_[n];
      target = c;
    }
  }
  if (target == p_m) return Eigen::Vector2d::Zero();
  return (target - p_m).normalized();
}

double DistanceField::Distance(const Eigen::Vector2d& p_m) const {
  const std::int32_t k = IndexAt(p_m);
  if (k < 0 || (flags_[k] & kFreeFlag) == 0 || std::isinf(potential_[k])) {
    return std::numeric_limits<double>::infinity();
  }
  if ((flags_[k] & kGoalFlag) != 0) return 0.0;
  return std::max(0.0, Interpolate(p_m, k).value);
}

Eigen::Vector2d DistanceField::Direction(const Eigen::Vector2d& p_m) const {
  const std::int32_t k = IndexAt(p_m);
  if (k < 0 || (flags_[k] & kGoalFlag) != 0) return Eigen::Vector2d::Zero();
  if ((flags_[k] & kFreeFlag) == 0) {
    return TowardsBestNeighbour(p_m, k, kFreeFlag | kClearanceFlag);
  }
  if (std::isinf(potential_[k])) return Eigen::Vector2d::Zero();
  const Eigen::Vector2d gradient = Interpolate(p_m, k).gradient;
  const double slope = gradient.norm();
  if (slope > kMinSlope) return -gradient / slope;
  return TowardsBestNeighbour(p_m, k, kFreeFlag);
}

bool DistanceField::Reachable(const Eigen::Vector2d& p_m) const {
  const std::int32_t k = IndexAt(p_m);
  return k >= 0 && (flags_[k] & kFreeFlag) != 0 && std::isfinite(potential_[k]);
}

bool DistanceField::InGoal(const Eigen::Vector2d& p_m) const {
  const std::int32_t k = IndexAt(p_m);
  return k >= 0 && (flags_[k] & kGoalFlag) != 0;
}

}  // namespace pavilion::sim::crowd
