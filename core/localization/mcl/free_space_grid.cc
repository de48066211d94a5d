#include "core/localization/mcl/free_space_grid.h"

#include <algorithm>
#include <deque>
#include <stdexcept>

namespace pavilion::core {
namespace {

constexpr double kMaxResolutionM = 1.0;
constexpr double kMaxRobotRadiusM = 10.0;
// robot_radius_m must be at least this many cells (see MapFreeSpaceOptions).
constexpr double kMinRadiusCells = 2.0;

LikelihoodFieldOptions ClearanceFieldOptions(const MapFreeSpaceOptions& options) {
  LikelihoodFieldOptions field;
  field.resolution_m = options.resolution_m;
  field.margin_m = options.resolution_m;  // free cells lie inside the bounds anyway
  field.max_distance_m = options.robot_radius_m + options.resolution_m;
  return field;
}

}  // namespace

void MapFreeSpaceOptions::Validate() const {
  if (!(resolution_m > 0.0 && resolution_m <= kMaxResolutionM)) {
    throw std::invalid_argument("MapFreeSpaceOptions.resolution_m must be in (0, 1] m");
  }
  if (!(robot_radius_m >= kMinRadiusCells * resolution_m && robot_radius_m <= kMaxRobotRadiusM)) {
    throw std::invalid_argument(
        "MapFreeSpaceOptions.robot_radius_m must be in [2 resolution_m, 10] m");
  }
}

MapFreeSpace::MapFreeSpace(const RobotMap& map, const MapFreeSpaceOptions& options)
    : options_((options.Validate(), options)), field_(map, ClearanceFieldOptions(options)) {
  const long n = field_.cell_count();
  std::vector<char> passable(static_cast<std::size_t>(n), 0);
  const Box2& box = field_.geometry_bounds();
  for (long i = 0; i < n; ++i) {
    const Eigen::Vector2d c = field_.CellCenter(i);
    const bool inside =
        c.x() >= box.lo.x() && c.x() <= box.hi.x() && c.y() >= box.lo.y() && c.y() <= box.hi.y();
    passable[static_cast<std::size_t>(i)] =
        inside && field_.CellDistanceM(i) >= options_.robot_radius_m;
  }
  is_free_.assign(passable.size(), 0);
  if (map.nodes.empty()) {
    is_free_ = passable;
  } else {
    Flood(map, passable);
  }
  for (long i = 0; i < n; ++i) {
    if (is_free_[static_cast<std::size_t>(i)]) free_.push_back(i);
  }
}

void MapFreeSpace::Flood(const RobotMap& map, const std::vector<char>& passable) {
  std::deque<long> queue;
  const auto visit = [&](long i) {
    const auto k = static_cast<std::size_t>(i);
    if (i < 0 || !passable[k] || is_free_[k]) return;
    is_free_[k] = 1;
    queue.push_back(i);
  };
  for (const MapNode& node : map.nodes) visit(field_.CellIndex(node.pose.translation()));
  const long width = field_.width();
  while (!queue.empty()) {
    const long i = queue.front();
    queue.pop_front();
    const long x = i % width;
    if (x > 0) visit(i - 1);
    if (x + 1 < width) visit(i + 1);
    if (i >= width) visit(i - width);
    if (i + width < field_.cell_count()) visit(i + width);
  }
}

Eigen::Vector2d MapFreeSpace::Sample(RandomStream& random) const {
  if (free_.empty()) throw std::logic_error("MapFreeSpace::Sample: the map has no free cell");
  const long cell = free_[static_cast<std::size_t>(
      random.UniformInt(0, static_cast<std::int64_t>(free_.size()) - 1))];
  const double half = 0.5 * field_.resolution_m();
  const double dx = random.Uniform(-half, half);
  const double dy = random.Uniform(-half, half);
  return field_.CellCenter(cell) + Eigen::Vector2d(dx, dy);
}

bool MapFreeSpace::IsFree(const Eigen::Vector2d& point_in_map) const {
  const long i = field_.CellIndex(point_in_map);
  return i >= 0 && is_free_[static_cast<std::size_t>(i)] != 0;
}

}  // namespace pavilion::core
