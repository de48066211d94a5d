#include "core/localization/free_space_constraint.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace pavilion::core {
namespace {

using Vec2 = Eigen::Vector2d;

// sqrt of the largest eigenvalue of a 2x2 covariance: the position sigma along
// its worst direction.
double LargestSigma(const Eigen::Matrix3d& p) {
  const double a = p(0, 0), b = p(0, 1), c = p(1, 1);
  const double half_difference = 0.5 * (a - c);
  return std::sqrt(std::max(0.0, 0.5 * (a + c) + std::hypot(half_difference, b)));
}

// The runs of consecutive beams that each end at one mapped element (a wall
// or a column), for FreeSpaceCheck::wall_run_m: the longest stretch of an
// element that a run of at least `min_beams` reached.
class WallRuns {
 public:
  explicit WallRuns(int min_beams) : min_beams_(min_beams) {}
  // A beam that ended at `element`, meeting it at `hit`.
  void Reached(std::size_t element, const Vec2& hit) {
    if (beams_ > 0 && element != element_) Break();
    if (beams_ == 0) {
      element_ = element;
      first_ = hit;
    }
    last_ = hit;
    ++beams_;
  }
  // A beam that did not (short of the map, beyond it, or no return).
  void Break() {
    if (beams_ >= min_beams_) longest_m_ = std::max(longest_m_, (last_ - first_).norm());
    beams_ = 0;
  }
  double longest_m() const { return longest_m_; }

 private:
  int min_beams_;
  std::size_t element_ = 0;
  int beams_ = 0;
  Vec2 first_ = Vec2::Zero();
  Vec2 last_ = Vec2::Zero();
  double longest_m_ = 0.0;
};

}  // namespace

void FreeSpaceOptions::Validate() const {
  if (!(margin_m >= 0.0)) throw std::invalid_argument("FreeSpaceOptions.margin_m must be >= 0");
  if (!(end_clearance_m >= 0.0)) {
    throw std::invalid_argument("FreeSpaceOptions.end_clearance_m must be >= 0");
  }
  if (!(max_incidence_rad > 0.0 && max_incidence_rad < 0.5 * std::numbers::pi)) {
    throw std::invalid_argument("FreeSpaceOptions.max_incidence_rad must be in (0, pi/2)");
  }
  if (!(sigma_factor >= 0.0)) {
    throw std::invalid_argument("FreeSpaceOptions.sigma_factor must be >= 0");
  }
  if (beam_stride < 1) throw std::invalid_argument("FreeSpaceOptions.beam_stride must be >= 1");
  if (max_see_through < 0) {
    throw std::invalid_argument("FreeSpaceOptions.max_see_through must be >= 0");
  }
  if (!(max_see_through_ratio >= 0.0 && max_see_through_ratio <= 1.0)) {
    throw std::invalid_argument("FreeSpaceOptions.max_see_through_ratio must be in [0, 1]");
  }
  if (min_wall_run_beams < 2) {
    throw std::invalid_argument("FreeSpaceOptions.min_wall_run_beams must be >= 2");
  }
}

namespace {
const FreeSpaceOptions& Validated(const FreeSpaceOptions& options) {
  options.Validate();
  return options;
}
}  // namespace

FreeSpaceConstraint::FreeSpaceConstraint(const RobotMap& map, const FreeSpaceOptions& options)
    : options_(Validated(options)), geometry_(CollectMapGeometry(map, InfiniteLines::kOmit)) {}

FreeSpaceCheck FreeSpaceConstraint::Check(const LaserScan& scan,
                                          const PoseWithCovariance& world_from_robot,
                                          bool count_short) const {
  FreeSpaceCheck check;
  const Pose2 world_from_sensor = world_from_robot.pose * scan.robot_from_sensor;
  const Vec2 origin = world_from_sensor.translation();
  const double k = options_.sigma_factor;
  // Where the sensor is: the robot's position sigma plus its heading sigma
  // over the mounting lever arm; each beam adds its heading sigma over its length.
  const double sigma_heading = std::sqrt(std::max(0.0, world_from_robot.covariance(2, 2)));
  const double sigma_origin = LargestSigma(world_from_robot.covariance) +
                              scan.robot_from_sensor.translation().norm() * sigma_heading;
  const double cos_max_incidence = std::cos(options_.max_incidence_rad);

  std::vector<std::size_t> near;
  std::vector<std::pair<Vec2, double>> cores;
  InReach(origin, scan.max_range_m, options_.end_clearance_m + k * sigma_origin, &near, &cores);
  WallRuns runs(options_.min_wall_run_beams);
  for (std::size_t j = 0; j < scan.readings.size();
       j += static_cast<std::size_t>(options_.beam_stride)) {
    const LaserReading& reading = scan.readings[j];
    if (!reading.valid || !(reading.range_m > 0.0)) {
      runs.Break();
      continue;
    }
    ++check.beams;
    const double heading = world_from_sensor.theta_rad + reading.bearing_rad;
    const Vec2 u(std::cos(heading), std::sin(heading));
    const double tolerance_m =
        options_.margin_m + k * (sigma_origin + reading.range_m * sigma_heading);
    if (count_short) {
      const MapCrossing map = FirstMapCrossing(origin, u, scan.max_range_m, near);
      if (std::isfinite(map.range_m)) {
        ++check.mapped;
        if (reading.range_m < map.range_m - tolerance_m) ++check.short_of_map;
      }
      if (std::isfinite(map.range_m) && std::abs(reading.range_m - map.range_m) <= tolerance_m) {
        runs.Reached(map.element, origin + map.range_m * u);
      } else {
        runs.Break();
      }
    }
    // Only the part of the beam that ends more than the margin before the
    // reading can contradict.
    const double reach = reading.range_m - tolerance_m;
    if (reach <= 0.0) continue;
    const Vec2 end = origin + reach * u;
    bool contradicts = false;
    for (const std::size_t i : near) {
      const auto& [a, b] = geometry_.segments[i];
      const double t = RaySegmentHit(origin, end, a, b);
      if (!std::isfinite(t)) continue;
      const Vec2 wall = b - a;
      const double length = wall.norm();
      if (length <= 0.0) continue;
      const Vec2 normal(-wall.y() / length, wall.x() / length);
      if (std::abs(u.dot(normal)) < cos_max_incidence) continue;  // grazing
      const Vec2 crossing = origin + t * reach * u;
      const double clearance =
          options_.end_clearance_m + k * (sigma_origin + t * reach * sigma_heading);
      if ((crossing - a).norm() < clearance || (crossing - b).norm() < clearance) continue;
      contradicts = true;
      break;
    }
    for (std::size_t d = 0; !contradicts && d < cores.size(); ++d) {
      const std::vector<double> hits = LineCircleHits(origin, end, cores[d].first, cores[d].second);
      contradicts = hits.size() == 2 && hits[1] >= 0.0 && hits[0] <= 1.0;
    }
    if (contradicts) ++check.see_through;
  }
  runs.Break();
  check.wall_run_m = runs.longest_m();
  return check;
}

void FreeSpaceConstraint::InReach(const Vec2& origin, double max_range_m, double clearance_m,
                                  std::vector<std::size_t>* near,
                                  std::vector<std::pair<Vec2, double>>* cores) const {
  for (std::size_t i = 0; i < geometry_.segments.size(); ++i) {
    const auto& [a, b] = geometry_.segments[i];
    if (PointSegmentDistance(origin, a, b) <= max_range_m) near->push_back(i);
  }
  for (const auto& [centre, radius] : geometry_.discs) {
    const double core = radius - clearance_m;
    if (core > 0.0 && (centre - origin).norm() - core <= max_range_m) {
      cores->emplace_back(centre, core);
    }
  }
}

FreeSpaceConstraint::MapCrossing FreeSpaceConstraint::FirstMapCrossing(
    const Vec2& origin, const Vec2& u, double max_range_m,
    const std::vector<std::size_t>& near) const {
  const Vec2 end = origin + max_range_m * u;
  double first = 1.0;  // along origin -> end
  std::size_t element = 0;
  for (const std::size_t i : near) {
    const auto& [a, b] = geometry_.segments[i];
    const double t = RaySegmentHit(origin, end, a, b);
    if (std::isfinite(t) && t < first) {
      first = t;
      element = i;
    }
  }
  for (std::size_t d = 0; d < geometry_.discs.size(); ++d) {
    const auto& [centre, radius] = geometry_.discs[d];
    const std::vector<double> hits = LineCircleHits(origin, end, centre, radius);
    if (hits.size() == 2 && hits[1] >= 0.0 && hits[0] <= first) {
      first = std::max(0.0, hits[0]);
      element = geometry_.segments.size() + d;
    }
  }
  if (first >= 1.0) return {std::numeric_limits<double>::infinity(), 0};
  return {first * max_range_m, element};
}

bool FreeSpaceConstraint::Satisfied(const FreeSpaceCheck& check) const {
  return check.see_through <= options_.max_see_through ||
         check.see_through <= options_.max_see_through_ratio * check.beams;
}

}  // namespace pavilion::core
