#include "scenarios/metrics/social_navigation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/geometry/polygon.h"
#include "sim/crowd/social_force.h"

namespace pavilion::scenarios {
namespace {

// Slack on the bounds of a gap against rounding (m).
constexpr double kGapBoundSlackM = 1e-9;

void CheckStep(double dt_s, const char* who) {
  if (!std::isfinite(dt_s) || dt_s < 0.0) {
    throw std::invalid_argument(std::string(who) + ": dt_s must be finite and >= 0, got " +
                                std::to_string(dt_s));
  }
}

}  // namespace

SocialNavigationTracker::SocialNavigationTracker(std::vector<Eigen::Vector2d> footprint_in_robot_m)
    : footprint_in_robot_m_(std::move(footprint_in_robot_m)) {
  auto& hull = footprint_in_robot_m_;
  const std::size_t n = hull.size();
  if (n < 3) {
    throw std::invalid_argument(
        "social navigation: footprint_in_robot_m needs >= 3 vertices, got " + std::to_string(n));
  }
  for (const Eigen::Vector2d& v : hull) {
    if (!v.allFinite()) {
      throw std::invalid_argument(
          "social navigation: footprint_in_robot_m has a non-finite vertex");
    }
    circumradius_m_ = std::max(circumradius_m_, v.norm());
  }
  if (core::SignedArea(hull) < 0.0) std::reverse(hull.begin(), hull.end());
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d e1 = hull[(i + 1) % n] - hull[i];
    const Eigen::Vector2d e2 = hull[(i + 2) % n] - hull[(i + 1) % n];
    if (e1.x() * e2.y() - e1.y() * e2.x() < 0.0) {
      throw std::invalid_argument("social navigation: footprint_in_robot_m is not convex (vertex " +
                                  std::to_string((i + 1) % n) + ")");
    }
  }
  // Counter-clockwise: the origin's distance inside each edge's line.
  inradius_m_ = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d e = hull[(i + 1) % n] - hull[i];
    const double inside_m = (e.x() * -hull[i].y() - e.y() * -hull[i].x()) / e.norm();
    inradius_m_ = std::min(inradius_m_, inside_m);
  }
  inradius_m_ = std::max(inradius_m_, 0.0);
}

// The band of a gap among every threshold the figures use: two gaps in one
// band give the same zone and the same side of kDiscomfortGapM.
static_assert(kDiscomfortGapM < kIntimateZoneM && kIntimateZoneM < kPersonalZoneM &&
              kPersonalZoneM < kSocialZoneM);
int SocialNavigationTracker::BandOf(double gap_m) {
  return (gap_m < kDiscomfortGapM) + (gap_m < kIntimateZoneM) + (gap_m < kPersonalZoneM) +
         (gap_m < kSocialZoneM);
}

SocialNavigationTracker::Zone SocialNavigationTracker::ZoneOf(double gap_m) {
  if (gap_m < kIntimateZoneM) return kIntimate;
  if (gap_m < kPersonalZoneM) return kPersonal;
  if (gap_m < kSocialZoneM) return kSocial;
  return kOutside;
}

void SocialNavigationTracker::Update(double dt_s, const core::Pose2& world_from_robot,
                                     const std::vector<sim::crowd::PersonState>& people) {
  CheckStep(dt_s, "SocialNavigationTracker::Update");
  if (zone_.size() < people.size()) zone_.resize(people.size(), kOutside);
  const double c = std::cos(world_from_robot.theta_rad);
  const double s = std::sin(world_from_robot.theta_rad);
  const Eigen::Vector2d origin = world_from_robot.translation();
  SocialNavigationFigures& f = figures_;
  int closest_band = 0;  // BandOf the smallest gap of this step
  for (std::size_t i = 0; i < people.size(); ++i) {
    const sim::crowd::PersonState& person = people[i];
    Zone& zone = zone_[i];
    if (!person.present) {
      zone = kOutside;
      continue;
    }
    active_ = true;
    // The gap is at least the centre distance less both radii: a visitor
    // beyond `reach` is outside every zone and no closer than the smallest gap
    // so far (+inf until the first visitor: that one is measured).
    const Eigen::Vector2d d = person.position_m - origin;
    const double reach =
        std::max(kSocialZoneM, f.min_visitor_gap_m) + circumradius_m_ + person.shape.radius_m;
    if (d.squaredNorm() >= reach * reach) {
      zone = kOutside;
      continue;
    }
    // The gap lies within [centre − circumradius, centre − inradius] less the
    // person's radius: when both ends fall in one band and the low end cannot
    // be a new smallest gap, the band is the exact gap's, measured or not.
    const double centre_m = std::sqrt(d.squaredNorm());
    const double low_m = centre_m - circumradius_m_ - person.shape.radius_m - kGapBoundSlackM;
    const double high_m = centre_m - inradius_m_ - person.shape.radius_m + kGapBoundSlackM;
    Zone now;
    if (low_m > f.min_visitor_gap_m && BandOf(low_m) == BandOf(high_m)) {
      now = ZoneOf(low_m);
      closest_band = std::max(closest_band, BandOf(low_m));
    } else {
      const Eigen::Vector2d in_robot(c * d.x() + s * d.y(), -s * d.x() + c * d.y());
      Eigen::Vector2d normal, closest;
      const double gap_m =
          sim::crowd::SignedDistanceToConvex(footprint_in_robot_m_, in_robot, &normal, &closest) -
          person.shape.radius_m;
      f.min_visitor_gap_m = std::min(f.min_visitor_gap_m, gap_m);
      closest_band = std::max(closest_band, BandOf(gap_m));
      now = ZoneOf(gap_m);
    }
    // Crossing inwards counts for every zone edge crossed.
    if (now <= kIntimate && zone > kIntimate) ++f.intimate_intrusions;
    if (now <= kPersonal && zone > kPersonal) ++f.personal_intrusions;
    if (now <= kSocial && zone > kSocial) ++f.social_intrusions;
    zone = now;
  }
  // The closest visitor's band: 4 below kDiscomfortGapM, then intimate,
  // personal, social, 0 outside every zone (or no visitor).
  const Zone closest_zone = closest_band >= 3   ? kIntimate
                            : closest_band == 2 ? kPersonal
                            : closest_band == 1 ? kSocial
                                                : kOutside;
  switch (closest_zone) {
    case kIntimate:
      f.intimate_time_s += dt_s;
      break;
    case kPersonal:
      f.personal_time_s += dt_s;
      break;
    case kSocial:
      f.social_time_s += dt_s;
      break;
    case kOutside:
      break;
  }
  if (closest_band == 4) f.closer_than_0_2_m_time_s += dt_s;
}

void CrowdTracker::Update(double dt_s, const sim::crowd::Crowd& crowd) {
  CheckStep(dt_s, "CrowdTracker::Update");
  CrowdFigures& f = figures_;
  f.pool = crowd.size();
  f.arrivals = crowd.arrivals();
  f.departures = crowd.departures();
  f.pushes = crowd.pushes();
  const int present = crowd.present();
  f.max_present = std::max<std::int64_t>(f.max_present, present);
  time_s_ += dt_s;
  present_s_ += present * dt_s;
  f.max_overlap_m = std::max(f.max_overlap_m, crowd.max_overlap_m());
  const std::array<double, 3> by_kind = crowd.max_overlaps_m();
  f.max_overlap_people_m = std::max(f.max_overlap_people_m, by_kind[0]);
  f.max_overlap_walls_m = std::max(f.max_overlap_walls_m, by_kind[1]);
  f.max_overlap_robots_m = std::max(f.max_overlap_robots_m, by_kind[2]);
  f.episodes.clear();
  for (std::size_t b = 1; b < crowd.episodes().size(); ++b) {  // 0: ordinary visitors have none
    f.episodes.emplace_back(sim::crowd::ToString(static_cast<sim::crowd::Behaviour>(b)),
                            crowd.episodes()[b]);
  }
  int blocked = 0;
  for (int i = 0; i < crowd.size(); ++i) blocked += crowd.blocked_by_robot(i) ? 1 : 0;
  f.visitor_blocked_by_robot_s += blocked * dt_s;
}

CrowdFigures CrowdTracker::Figures() const {
  CrowdFigures f = figures_;
  f.mean_present = time_s_ > 0.0 ? present_s_ / time_s_ : 0.0;
  return f;
}

}  // namespace pavilion::scenarios
