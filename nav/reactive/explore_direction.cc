#include "nav/reactive/explore_direction.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/types/pose2.h"
#include "nav/reactive/swept_polygon.h"

namespace pavilion::nav {

namespace {

void Require(bool ok, const char* field, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("ExploreOptions.") + field + " must be " + what);
}

}  // namespace

void ExploreOptions::Validate() const {
  Require(bearings >= 4 && bearings <= 360, "bearings", "in [4, 360]");
  Require(reach_m > 0.0 && reach_m <= 20.0, "reach_m", "in (0, 20] m");
  Require(min_free_m > 0.0 && min_free_m <= 10.0, "min_free_m", "in (0, 10] m");
  Require(keep_free_m >= min_free_m && keep_free_m <= reach_m, "keep_free_m",
          "in [min_free_m, reach_m]");
  Require(speed_mps > 0.0 && speed_mps <= 2.0, "speed_mps", "in (0, 2] m/s");
  Require(settle_s >= 0.0 && settle_s <= 600.0, "settle_s", "in [0, 600] s");
  Require(contact_memory_s >= 0.0 && contact_memory_s <= 600.0, "contact_memory_s",
          "in [0, 600] s");
}

double FreeTravel(std::span<const Eigen::Vector2d> points_in_robot, double bearing_rad,
                  double half_width_m, double reach_m) {
  const Eigen::Vector2d along(std::cos(bearing_rad), std::sin(bearing_rad));
  double free_m = reach_m;
  for (const Eigen::Vector2d& p : points_in_robot) {
    const double s = p.dot(along);
    if (s <= 0.0) continue;
    const double lateral = std::abs(along.x() * p.y() - along.y() * p.x());
    if (lateral >= half_width_m) continue;
    // The corridor's round front (a disc of half_width_m swept along the
    // bearing) touches the point this far along.
    const double touch = s - std::sqrt(half_width_m * half_width_m - lateral * lateral);
    free_m = std::min(free_m, std::max(0.0, touch));
  }
  return free_m;
}

double StraightFreeTravel(std::span<const Eigen::Vector2d> points_in_robot,
                          std::span<const Eigen::Vector2d> footprint, bool reverse, double margin_m,
                          double reach_m) {
  const double sign = reverse ? -1.0 : 1.0;
  double half_width_m = 0.0;
  double extent_m = 0.0;  // of the outline along the direction of travel
  for (const Eigen::Vector2d& c : footprint) {
    half_width_m = std::max(half_width_m, std::abs(c.y()));
    extent_m = std::max(extent_m, sign * c.x());
  }
  half_width_m += margin_m;
  extent_m += margin_m;
  double free_m = reach_m;
  for (const Eigen::Vector2d& p : points_in_robot) {
    const double s = sign * p.x();
    if (s <= 0.0 || std::abs(p.y()) >= half_width_m) continue;
    free_m = std::min(free_m, std::max(0.0, s - extent_m));
  }
  return free_m;
}

namespace {

// The most a point at `p` inside the convex `polygon` (counter-clockwise) gets
// deeper than it is, m, as it moves along p + t (u, 0) for t in [0, until_m]:
// its depth, the least distance to an edge's line, is concave in t.
double DeepeningAlong(const core::Polygon2& polygon, const Eigen::Vector2d& p, double u,
                      double until_m) {
  const auto depth = [&](double t) {
    const Eigen::Vector2d q = p + Eigen::Vector2d(u * t, 0.0);
    double least = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const Eigen::Vector2d d = polygon[(i + 1) % polygon.size()] - polygon[i];
      const Eigen::Vector2d n = Eigen::Vector2d(d.y(), -d.x()).normalized();
      least = std::min(least, -n.dot(q - polygon[i]));
    }
    return least;
  };
  double lo = 0.0;
  double hi = until_m;
  for (int k = 0; k < 60; ++k) {  // ternary search of the concave maximum
    const double a = lo + (hi - lo) / 3.0;
    const double b = hi - (hi - lo) / 3.0;
    if (depth(a) < depth(b)) {
      lo = a;
    } else {
      hi = b;
    }
  }
  return std::max(0.0, depth(0.5 * (lo + hi)) - depth(0.0));
}

}  // namespace

double StraightPolygonTravel(std::span<const Eigen::Vector2d> points_in_robot,
                             std::span<const Eigen::Vector2d> footprint, bool reverse,
                             double margin_m, double reach_m, double contact_slack_m) {
  const core::Polygon2 grown =
      InflateConvexPolygon(core::Polygon2(footprint.begin(), footprint.end()), margin_m);
  // In the robot frame a point moves against the travel: p + t u, u = -+x.
  const double u = reverse ? 1.0 : -1.0;
  double free_m = reach_m;
  for (const Eigen::Vector2d& p : points_in_robot) {
    // Where the point's ray is inside every edge's half-plane (Cyrus-Beck).
    double enter = 0.0;
    double leave = reach_m;
    for (std::size_t i = 0; i < grown.size() && enter <= leave; ++i) {
      const Eigen::Vector2d d = grown[(i + 1) % grown.size()] - grown[i];
      const Eigen::Vector2d n(d.y(), -d.x());  // outward (counter-clockwise outline)
      const double outside = n.dot(p - grown[i]);
      const double rate = n.x() * u;
      if (rate == 0.0) {
        if (outside > 0.0) leave = -1.0;  // parallel and outside: never inside
      } else if (rate < 0.0) {
        enter = std::max(enter, -outside / rate);
      } else {
        leave = std::min(leave, -outside / rate);
      }
    }
    if (enter > leave) continue;
    // Inside now: it blocks unless the travel takes it out no more than
    // contact_slack_m deeper than it is.
    if (enter == 0.0 && contact_slack_m > 0.0 && leave > 0.0 &&
        DeepeningAlong(grown, p, u, leave) <= contact_slack_m) {
      continue;
    }
    free_m = std::min(free_m, enter);
  }
  return free_m;
}

std::optional<double> ExploreBearing(std::span<const Eigen::Vector2d> points_in_robot,
                                     std::optional<double> current, double half_width_m,
                                     const ExploreOptions& options) {
  if (current &&
      FreeTravel(points_in_robot, *current, half_width_m, options.reach_m) >= options.keep_free_m) {
    return current;
  }
  std::optional<double> best;
  double best_free = 0.0;
  // Ahead first, then alternately left and right, so that a tie goes to the
  // bearing that needs the least turning.
  for (int k = 0; k < options.bearings; ++k) {
    const int step = (k + 1) / 2;
    const int sign = (k % 2 == 1) ? 1 : -1;
    const double bearing =
        core::NormalizeAngle(sign * step * 2.0 * std::numbers::pi / options.bearings);
    const double free_m = FreeTravel(points_in_robot, bearing, half_width_m, options.reach_m);
    if (free_m > best_free + 1e-9) {
      best_free = free_m;
      best = bearing;
    }
  }
  if (best_free < options.min_free_m) return std::nullopt;
  return best;
}

}  // namespace pavilion::nav
