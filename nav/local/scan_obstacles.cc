#include "nav/local/scan_obstacles.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "core/geometry/polygon.h"
#include "core/geometry/segment2.h"
#include "nav/reactive/swept_polygon.h"

namespace pavilion::nav {
namespace {

// Covered()'s cone test decides a point without atan2 only this far from the
// field of view's edges (rad), where the two cannot disagree; the cone's two
// cosine thresholds must then lie at least kConeCosineGap apart.
constexpr double kConeMarginRad = 1e-6;
constexpr double kConeCosineGap = 1e-9;
// Blind-zone memory: one scan per laser this often (s), points this near (m).
constexpr double kMemoryPeriodS = 0.1;
constexpr double kMemoryReachM = 3.0;
// Between two scans the robot moved when its odometry pose changed by more
// than this (m, rad).
constexpr double kStillM = 1e-3;
constexpr double kStillRad = 1e-3;

}  // namespace

std::vector<Eigen::Vector2d> GhostPositions(const core::RobotMap& map) {
  std::vector<Eigen::Vector2d> ghosts;
  ghosts.reserve(map.ghost_points.size());
  for (const core::MapGhostPoint& g : map.ghost_points) ghosts.push_back(g.position_m);
  return ghosts;
}

void GhostBarrier::Validate() const {
  if (!(link_m >= 0.0 && link_m <= 2.0)) {
    throw std::invalid_argument("GhostBarrier.link_m must be in [0, 2] m");
  }
  if (!(fill_m >= 0.005 && fill_m <= 1.0)) {
    throw std::invalid_argument("GhostBarrier.fill_m must be in [0.005, 1] m");
  }
  if (!(clearance_m >= 0.0 && clearance_m <= 0.2)) {
    throw std::invalid_argument("GhostBarrier.clearance_m must be in [0, 0.2] m");
  }
}

std::vector<Eigen::Vector2d> FillGhostBarriers(std::span<const Eigen::Vector2d> ghosts,
                                               const GhostBarrier& barrier) {
  barrier.Validate();
  std::vector<Eigen::Vector2d> filled(ghosts.begin(), ghosts.end());
  const double c = barrier.clearance_m;
  if (c > 0.0) {
    for (const Eigen::Vector2d& g : ghosts) {
      for (int k = 0; k < kGhostRingPoints; ++k) {
        const double a = 2.0 * std::numbers::pi * k / kGhostRingPoints;
        filled.push_back(g + c * Eigen::Vector2d(std::cos(a), std::sin(a)));
      }
    }
  }
  const double link2 = barrier.link_m * barrier.link_m;
  for (std::size_t i = 0; i < ghosts.size(); ++i) {
    for (std::size_t j = i + 1; j < ghosts.size(); ++j) {
      const Eigen::Vector2d d = ghosts[j] - ghosts[i];
      if (d.squaredNorm() >= link2 || d.squaredNorm() == 0.0) continue;
      const int n = static_cast<int>(std::ceil(d.norm() / barrier.fill_m));
      const Eigen::Vector2d side = c * Eigen::Vector2d(-d.y(), d.x()).normalized();
      for (int k = 0; k <= n; ++k) {
        const Eigen::Vector2d on = ghosts[i] + (double(k) / n) * d;
        // The two rows beside the join bound it; the join itself is needed
        // only without them.
        if (c > 0.0) {
          filled.insert(filled.end(), {on + side, on - side});
        } else if (k > 0 && k < n) {
          filled.push_back(on);
        }
      }
    }
  }
  return filled;
}

ScanObstacles::Buckets::Buckets(std::span<const Eigen::Vector2d> points) {
  if (points.empty()) return;
  Eigen::Vector2d lo = points.front(), hi = points.front();
  for (const Eigen::Vector2d& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  origin = lo;
  size = ((hi - lo) / kBucketM).array().floor().cast<int>() + 1;
  cells.resize(static_cast<std::size_t>(size.x()) * size.y());
  for (const Eigen::Vector2d& p : points) {
    const Eigen::Vector2i cell = ((p - lo) / kBucketM).array().floor().cast<int>();
    cells[static_cast<std::size_t>(cell.y()) * size.x() + cell.x()].push_back(p);
  }
}

template <typename Visit>
void ScanObstacles::Buckets::ForEachNear(const Eigen::Vector2d& centre, double reach_m,
                                         Visit&& visit) const {
  if (cells.empty()) return;
  const double reach2 = reach_m * reach_m;
  const Eigen::Vector2d lo = (centre.array() - reach_m - origin.array()) / kBucketM;
  const Eigen::Vector2d hi = (centre.array() + reach_m - origin.array()) / kBucketM;
  const int x0 = std::max(0, static_cast<int>(std::floor(lo.x())));
  const int y0 = std::max(0, static_cast<int>(std::floor(lo.y())));
  const int x1 = std::min(size.x() - 1, static_cast<int>(std::floor(hi.x())));
  const int y1 = std::min(size.y() - 1, static_cast<int>(std::floor(hi.y())));
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      for (const Eigen::Vector2d& p : cells[static_cast<std::size_t>(y) * size.x() + x]) {
        if ((p - centre).squaredNorm() <= reach2) visit(p);
      }
    }
  }
}

std::vector<Eigen::Vector2d> MapOutline(const core::RobotMap& map, double spacing_m,
                                        double clearance_m) {
  if (!(spacing_m > 0.0)) throw std::invalid_argument("MapOutline: spacing_m must be > 0");
  if (!(clearance_m >= 0.0 && clearance_m <= 0.2)) {
    throw std::invalid_argument("MapOutline: clearance_m must be in [0, 0.2] m");
  }
  std::vector<Eigen::Vector2d> outline;
  const auto sample_circle = [&](const Eigen::Vector2d& centre, double radius_m) {
    const int n =
        std::max(kGhostRingPoints,
                 static_cast<int>(std::ceil(2.0 * std::numbers::pi * radius_m / spacing_m)));
    for (int k = 0; k < n; ++k) {
      const double a = 2.0 * std::numbers::pi * k / n;
      outline.push_back(centre + radius_m * Eigen::Vector2d(std::cos(a), std::sin(a)));
    }
  };
  // A face moved clearance_m towards the side it is seen from (eq. B.4: the
  // points p with n(alpha) . p < r), its two ends rounded off.
  const auto sample_face = [&](const core::Line& line, const Eigen::Vector2d& a,
                               const Eigen::Vector2d& b) {
    const Eigen::Vector2d off =
        -clearance_m * Eigen::Vector2d(std::cos(line.alpha_rad), std::sin(line.alpha_rad));
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / spacing_m)));
    for (int k = 0; k <= n; ++k) outline.push_back(a + (double(k) / n) * (b - a) + off);
    if (clearance_m > 0.0) {
      sample_circle(a, clearance_m);
      sample_circle(b, clearance_m);
    }
  };
  for (const core::MapSegment& s : map.segments) {
    sample_face(s.line, s.first_endpoint.position_m, s.second_endpoint.position_m);
  }
  for (const core::MapMultiSegmentLine& line : map.multi_segment_lines) {
    for (const auto& [first, second] : line.segments) {
      sample_face(line.line, first.position_m, second.position_m);
    }
  }
  for (const core::MapPoint& p : map.points) {
    if (p.radius_m > 0.0) sample_circle(p.point.position_m, p.radius_m + clearance_m);
  }
  for (const core::MapBeacon& b : map.beacons) {
    if (b.radius_m > 0.0) sample_circle(b.point.position_m, b.radius_m + clearance_m);
  }
  return outline;
}

ScanObstacles::ScanObstacles(std::vector<Eigen::Vector2d> footprint_in_robot,
                             std::vector<Eigen::Vector2d> ghosts_in_world, double blind_memory_s,
                             const GhostBarrier& barrier)
    : footprint_(std::move(footprint_in_robot)),
      ghosts_in_world_(std::move(ghosts_in_world)),
      barriers_(FillGhostBarriers(ghosts_in_world_, barrier)),
      blind_memory_s_(blind_memory_s) {
  footprint_convex_ = IsConvexCounterClockwise(footprint_);
  footprint_radius_m_ = Circumradius(footprint_);
}

void ScanObstacles::SetMapOutline(std::span<const Eigen::Vector2d> outline_in_world) {
  outline_ = Buckets(outline_in_world);
}

void ScanObstacles::AddScan(const core::LaserScan& scan, const core::Pose2& odom_from_robot) {
  auto it = std::find_if(lasers_.begin(), lasers_.end(),
                         [&](const LaserPoints& l) { return l.sensor_id == scan.sensor_id; });
  if (it == lasers_.end()) {
    LaserPoints added;
    added.sensor_id = scan.sensor_id;
    lasers_.push_back(std::move(added));
    it = std::prev(lasers_.end());
  }
  // The blind-zone memory keeps a scan per laser every kMemoryPeriodS, and of
  // it only the points within kMemoryReachM of the robot: what the dynamic
  // window may need, at a tenth of the points to test each cycle.
  // The motion clock advances by the time since the last scan when the robot
  // moved meanwhile.
  if (last_scan_) {
    const auto& [last_s, last_pose] = *last_scan_;
    const bool moved =
        (odom_from_robot.translation() - last_pose.translation()).norm() > kStillM ||
        std::abs(core::NormalizeAngle(odom_from_robot.theta_rad - last_pose.theta_rad)) > kStillRad;
    if (moved && scan.stamp_s > last_s) motion_clock_s_ += scan.stamp_s - last_s;
  }
  last_scan_.emplace(scan.stamp_s, odom_from_robot);
  if (!it->in_odom.empty() && motion_clock_s_ - it->remembered_s >= kMemoryPeriodS) {
    Remembered kept{motion_clock_s_, it->stamp_s, {}};
    for (const Eigen::Vector2d& p : it->in_odom) {
      if ((p - odom_from_robot.translation()).squaredNorm() <= kMemoryReachM * kMemoryReachM) {
        kept.in_odom.push_back(p);
      }
    }
    memory_.push_back(std::move(kept));
    it->remembered_s = motion_clock_s_;
  }
  std::erase_if(memory_, [&](const Remembered& m) {
    return m.stamp_s < motion_clock_s_ - blind_memory_s_ ||
           m.taken_s < scan.stamp_s - kBlindMemoryCapS;
  });
  it->in_odom.clear();
  it->stamp_s = scan.stamp_s;
  it->sensor_from_robot = scan.robot_from_sensor.Inverse();
  it->sensor_from_robot_points = core::PointTransform(it->sensor_from_robot);
  it->max_range_m = scan.max_range_m;
  if (!scan.readings.empty()) {
    it->min_bearing_rad =
        std::min(scan.readings.front().bearing_rad, scan.readings.back().bearing_rad);
    it->max_bearing_rad =
        std::max(scan.readings.front().bearing_rad, scan.readings.back().bearing_rad);
  }
  SetCone(&*it);
  const core::PointTransform odom_from_sensor(odom_from_robot * scan.robot_from_sensor);
  const core::PointTransform robot_from_sensor(scan.robot_from_sensor);
  for (const core::LaserReading& r : scan.readings) {
    if (!r.valid) continue;
    const Eigen::Vector2d in_sensor(r.range_m * std::cos(r.bearing_rad),
                                    r.range_m * std::sin(r.bearing_rad));
    const Eigen::Vector2d in_robot = robot_from_sensor.Apply(in_sensor);
    if (!footprint_.empty() && core::Contains(footprint_, in_robot)) continue;
    it->in_odom.push_back(odom_from_sensor.Apply(in_sensor));
  }
}

void ScanObstacles::InRobot(const core::Pose2& odom_from_robot, const core::Pose2& world_from_robot,
                            double reach_m, std::vector<Eigen::Vector2d>* points_in_robot,
                            bool map_outline) const {
  points_in_robot->clear();
  // Every point of a cycle maps by the same two poses (PointTransform: the
  // cosine and sine once, not once per point; the same bits).
  const core::PointTransform robot_from_odom(odom_from_robot.Inverse());
  const double reach2 = reach_m * reach_m;
  for (const LaserPoints& l : lasers_) {
    for (const Eigen::Vector2d& p : l.in_odom) {
      const Eigen::Vector2d q = robot_from_odom.Apply(p);
      if (q.squaredNorm() <= reach2) points_in_robot->push_back(q);
    }
  }
  for (const Remembered& m : memory_) {
    for (const Eigen::Vector2d& p : m.in_odom) {
      const Eigen::Vector2d q = robot_from_odom.Apply(p);
      if (q.squaredNorm() <= reach2 && !Covered(q) && !UnderRobot(q)) {
        points_in_robot->push_back(q);
      }
    }
  }
  AppendGhostBarriers(world_from_robot, reach_m, points_in_robot);
  if (!map_outline) return;
  const core::PointTransform robot_from_world(world_from_robot.Inverse());
  outline_.ForEachNear(world_from_robot.translation(),
                       std::min(reach_m, footprint_radius_m_ + kOutlineReachM),
                       [&](const Eigen::Vector2d& w) {
                         const Eigen::Vector2d q = robot_from_world.Apply(w);
                         if (!Covered(q) && !UnderRobot(q)) points_in_robot->push_back(q);
                       });
}

void ScanObstacles::AppendGhostBarriers(const core::Pose2& world_from_robot, double reach_m,
                                        std::vector<Eigen::Vector2d>* points_in_robot) const {
  const core::PointTransform robot_from_world(world_from_robot.Inverse());
  barriers_.ForEachNear(world_from_robot.translation(), reach_m, [&](const Eigen::Vector2d& g) {
    const Eigen::Vector2d q = robot_from_world.Apply(g);
    if (!UnderRobot(q)) points_in_robot->push_back(q);
  });
}

// A map point deeper than kGhostInsideM in the polygon cannot be where the
// belief puts it; a remembered reading that deep is where the robot now
// stands, and what it saw there has gone.
bool ScanObstacles::UnderRobot(const Eigen::Vector2d& q) const {
  if (!footprint_convex_ || q.norm() >= footprint_radius_m_) return false;
  Eigen::Vector2d normal;
  return SignedDistance(footprint_, q, &normal) < -kGhostInsideM;
}

void ScanObstacles::ForgetBefore(double stamp_s) {
  std::erase_if(memory_, [&](const Remembered& m) { return m.taken_s < stamp_s; });
}

void ScanObstacles::SetCone(LaserPoints* l) {
  const double half_rad = 0.5 * (l->max_bearing_rad - l->min_bearing_rad);
  const double mid_rad = 0.5 * (l->max_bearing_rad + l->min_bearing_rad);
  l->cone_axis = {std::cos(mid_rad), std::sin(mid_rad)};
  l->cos_surely_inside = std::cos(half_rad - kConeMarginRad);
  l->cos_surely_outside = std::cos(half_rad + kConeMarginRad);
  // Within atan2's range, and the two thresholds well apart (the cone neither
  // a sliver nor a whole turn): a point's cosine, good to a few 1e-16, then
  // cannot be on the wrong side of either.
  l->cone = l->min_bearing_rad >= -std::numbers::pi && l->max_bearing_rad <= std::numbers::pi &&
            half_rad > kConeMarginRad &&
            l->cos_surely_inside - l->cos_surely_outside > kConeCosineGap;
}

// True when along / range > c, for range > 0, without the square root and
// the division (squares compared; the cone's margin absorbs their rounding).
static bool CosineAbove(double along, double range_sq, double c) {
  if (c >= 0.0) return along > 0.0 && along * along > c * c * range_sq;
  return along >= 0.0 || along * along < c * c * range_sq;
}

bool ScanObstacles::Covered(const Eigen::Vector2d& point_in_robot) const {
  for (const LaserPoints& l : lasers_) {
    const Eigen::Vector2d q = l.sensor_from_robot_points.Apply(point_in_robot);
    const double range_sq = q.squaredNorm();
    if (!(range_sq < l.max_range_m * l.max_range_m)) continue;
    if (l.cone && range_sq > 0.0) {
      const double along = l.cone_axis.dot(q);
      if (CosineAbove(along, range_sq, l.cos_surely_inside)) return true;
      if (!CosineAbove(along, range_sq, l.cos_surely_outside)) continue;
    }
    const double bearing = std::atan2(q.y(), q.x());
    if (bearing >= l.min_bearing_rad && bearing <= l.max_bearing_rad) return true;
  }
  return false;
}

void ScanObstacles::InWorld(const core::Pose2& odom_from_robot, const core::Pose2& world_from_robot,
                            double reach_m, std::vector<Eigen::Vector2d>* points_in_world) const {
  points_in_world->clear();
  const core::Pose2 world_from_odom = world_from_robot * odom_from_robot.Inverse();
  const Eigen::Vector2d center = world_from_robot.translation();
  const double reach2 = reach_m * reach_m;
  for (const LaserPoints& l : lasers_) {
    for (const Eigen::Vector2d& p : l.in_odom) {
      const Eigen::Vector2d q = world_from_odom * p;
      if ((q - center).squaredNorm() <= reach2) points_in_world->push_back(q);
    }
  }
  for (const Eigen::Vector2d& g : ghosts_in_world_) {
    if ((g - center).squaredNorm() <= reach2) points_in_world->push_back(g);
  }
}

std::size_t ScanObstacles::laser_points() const {
  std::size_t n = 0;
  for (const LaserPoints& l : lasers_) n += l.in_odom.size();
  return n;
}

double PolygonClearance(std::span<const Eigen::Vector2d> polygon,
                        std::span<const Eigen::Vector2d> points) {
  double best = std::numeric_limits<double>::infinity();
  const core::Polygon2 outline(polygon.begin(), polygon.end());
  const double radius_m = Circumradius(outline);
  for (const Eigen::Vector2d& p : points) {
    if (p.norm() - radius_m > best) continue;  // farther than the nearest so far
    if (core::Contains(outline, p)) return 0.0;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const Eigen::Vector2d& a = polygon[i];
      const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
      best = std::min(best, core::PointSegmentDistance(p, a, b));
    }
  }
  return best;
}

}  // namespace pavilion::nav
