#include "nav/reactive/collision_table.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <string>
#include <tuple>

namespace pavilion::nav {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kQuantumMax = std::numeric_limits<std::uint16_t>::max();

}  // namespace

void CollisionTableOptions::Validate() const {
  auto fail = [](const std::string& message) { throw std::invalid_argument(message); };
  if (!(lookahead_m > 0.0 && lookahead_m <= 10.0)) fail("lookahead_m must be in (0, 10] m");
  if (!(cell_m >= 0.005 && cell_m <= 0.2)) fail("cell_m must be in [0.005, 0.2] m");
  if (direction_bins < 8 || direction_bins > 1024 || direction_bins % 4 != 0) {
    fail("direction_bins must be a multiple of 4 in [8, 1024]");
  }
  if (!(safety_margin_m >= 0.0 && safety_margin_m <= 0.5)) {
    fail("safety_margin_m must be in [0, 0.5] m");
  }
}

CollisionTable::CollisionTable(const CollisionTableOptions& options,
                               const core::Polygon2& robot_polygon)
    : options_(options) {
  options_.Validate();
  if (!IsConvexCounterClockwise(robot_polygon)) {
    throw std::invalid_argument("robot_polygon must be convex and counter-clockwise");
  }
  reference_radius_m_ = Circumradius(robot_polygon);
  const double half_diagonal_m = std::sqrt(0.5) * options_.cell_m;
  table_polygon_ = InflateConvexPolygon(robot_polygon, options_.safety_margin_m + half_diagonal_m);
  reach_m_ = options_.lookahead_m + Circumradius(table_polygon_);
  cells_per_side_ = static_cast<int>(std::ceil(2.0 * reach_m_ / options_.cell_m));
  bin_rad_ = kTwoPi / options_.direction_bins;
  arc_.assign(static_cast<std::size_t>(bins()) * cells(), 0);
  for (int bin = 0; bin < bins(); ++bin) Fill(bin);
}

void CollisionTable::Fill(int bin) {
  const BodyTwist direction = BinDirection(bin);
  const double origin_m = -0.5 * cells_per_side_ * options_.cell_m;
  std::uint16_t* row = arc_.data() + static_cast<std::size_t>(bin) * cells();
  for (int iy = 0; iy < cells_per_side_; ++iy) {
    for (int ix = 0; ix < cells_per_side_; ++ix) {
      const Eigen::Vector2d centre(origin_m + (ix + 0.5) * options_.cell_m,
                                   origin_m + (iy + 0.5) * options_.cell_m);
      const double arc_m = ExactTimeToCollision(table_polygon_, direction, centre);
      const double quanta = std::floor(std::min(arc_m / options_.lookahead_m, 1.0) * kQuantumMax);
      row[iy * cells_per_side_ + ix] = static_cast<std::uint16_t>(quanta);
    }
  }
}

double CollisionTable::GeneralizedSpeed(const BodyTwist& twist) const {
  return std::hypot(twist.v_mps, reference_radius_m_ * twist.omega_radps);
}

int CollisionTable::BinOf(const BodyTwist& twist) const {
  const double gamma_rad = std::atan2(reference_radius_m_ * twist.omega_radps, twist.v_mps);
  const int bin = static_cast<int>(std::lround(gamma_rad / bin_rad_));
  return (bin % bins() + bins()) % bins();
}

BodyTwist CollisionTable::BinDirection(int bin) const {
  const double gamma_rad = bin * bin_rad_;
  return {std::cos(gamma_rad), std::sin(gamma_rad) / reference_radius_m_};
}

int CollisionTable::CellOf(const Eigen::Vector2d& point_in_robot) const {
  const double half_m = 0.5 * cells_per_side_ * options_.cell_m;
  const double fx = std::floor((point_in_robot.x() + half_m) / options_.cell_m);
  const double fy = std::floor((point_in_robot.y() + half_m) / options_.cell_m);
  if (!(fx >= 0.0 && fy >= 0.0 && fx < cells_per_side_ && fy < cells_per_side_)) return -1;
  return static_cast<int>(fy) * cells_per_side_ + static_cast<int>(fx);
}

double CollisionTable::ArcToCollision(int bin, int cell) const {
  const std::uint16_t q = arc_[static_cast<std::size_t>(bin) * cells() + cell];
  return q * (options_.lookahead_m / kQuantumMax);
}

double CollisionTable::MinArcToCollision(int bin, std::span<const int> cell_list) const {
  const std::uint16_t* row = arc_.data() + static_cast<std::size_t>(bin) * cells();
  std::uint16_t q = std::numeric_limits<std::uint16_t>::max();
  for (int cell : cell_list) q = std::min(q, row[cell]);
  return q * (options_.lookahead_m / kQuantumMax);
}

std::shared_ptr<const CollisionTable> SharedCollisionTable(const CollisionTableOptions& options,
                                                           const core::Polygon2& robot_polygon) {
  // The inputs, compared exactly (doubles compare by value; -0.0 == 0.0 and
  // both give the same table).
  using Key = std::tuple<double, double, int, double, std::vector<double>>;
  std::vector<double> vertices;
  vertices.reserve(2 * robot_polygon.size());
  for (const Eigen::Vector2d& v : robot_polygon) {
    vertices.push_back(v.x());
    vertices.push_back(v.y());
  }
  Key key{options.lookahead_m, options.cell_m, options.direction_bins, options.safety_margin_m,
          std::move(vertices)};
  // Weak entries: a table lives as long as a user holds it, and a long-lived
  // process (pavilion test, sweeps) does not keep the tables of finished runs.
  static std::mutex mutex;
  static std::map<Key, std::weak_ptr<const CollisionTable>> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  std::weak_ptr<const CollisionTable>& entry = cache[key];
  if (std::shared_ptr<const CollisionTable> table = entry.lock()) return table;
  auto table = std::make_shared<const CollisionTable>(options, robot_polygon);
  entry = table;
  return table;
}

}  // namespace pavilion::nav
