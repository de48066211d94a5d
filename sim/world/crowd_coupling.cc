#include "sim/world/crowd_coupling.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace pavilion::sim {
namespace {

// The torso's depth as a fraction of its width (chosen: a chest about
// 0.25 m deep for 0.45 m across the shoulders), and its outline's corners.
constexpr double kTorsoDepthRatio = 0.6;
constexpr int kTorsoCorners = 8;

// Distance along a 2D ray (origin o, unit direction u) to a circle, or +inf.
double RayCircle(const Eigen::Vector2d& o, const Eigen::Vector2d& u, const Eigen::Vector2d& c,
                 double r) {
  const Eigen::Vector2d oc = o - c;
  const double b = oc.dot(u);
  const double q = oc.squaredNorm() - r * r;
  const double disc = b * b - q;
  if (disc < 0.0) return std::numeric_limits<double>::infinity();
  const double root = std::sqrt(disc);
  const double t = q > 0.0 ? -b - root : -b + root;  // from outside: the near side
  return t >= 0.0 ? t : std::numeric_limits<double>::infinity();
}

std::vector<Eigen::Vector2d> TorsoOutline(const crowd::PersonState& p) {
  std::vector<Eigen::Vector2d> outline;
  const Eigen::Vector2d forward(std::cos(p.heading_rad), std::sin(p.heading_rad));
  const Eigen::Vector2d left(-forward.y(), forward.x());
  for (int k = 0; k < kTorsoCorners; ++k) {
    const double a = 2.0 * std::numbers::pi * k / kTorsoCorners;
    outline.push_back(p.position_m + kTorsoDepthRatio * p.shape.radius_m * std::cos(a) * forward +
                      p.shape.radius_m * std::sin(a) * left);
  }
  return outline;  // counter-clockwise: forward, then left
}

}  // namespace

CrowdCoupling::CrowdCoupling(std::unique_ptr<crowd::Crowd> crowd, std::vector<int> person_elements)
    : crowd_(std::move(crowd)), person_elements_(std::move(person_elements)) {}

void CrowdCoupling::CollectWalls(const core::PlanarSection& low, const core::PlanarSection& body,
                                 std::vector<crowd::WallSegment>* walls,
                                 std::vector<crowd::WallCircle>* pillars) {
  std::vector<bool> in_low(low.elements.size(), false);
  for (const core::SectionSegment& s : low.segments) in_low[s.element] = true;
  for (const core::SectionCircle& c : low.circles) in_low[c.element] = true;
  for (const core::PlanarSection* section : {&low, &body}) {
    const bool first = section == &low;
    for (const core::SectionSegment& s : section->segments) {
      if (first || !in_low[s.element]) walls->push_back({s.a_m, s.b_m, s.element});
    }
    for (const core::SectionCircle& c : section->circles) {
      if (first || !in_low[c.element]) pillars->push_back({c.center_m, c.radius_m});
    }
  }
}

void CrowdCoupling::AppendSection(double z_m, core::PlanarSection* out) const {
  const std::vector<crowd::PersonState>& people = crowd_->people();
  for (std::size_t i = 0; i < people.size(); ++i) {
    const crowd::PersonState& p = people[i];
    if (!p.present || z_m < 0.0 || z_m > p.shape.height_m) continue;
    const int element = person_elements_[i];
    if (z_m < p.shape.hip_height_m) {
      for (const Eigen::Vector2d& c : p.LegCentres(z_m)) {
        out->circles.push_back({c, p.shape.leg_radius_m, element});
      }
    } else {
      const std::vector<Eigen::Vector2d> outline = TorsoOutline(p);
      for (std::size_t k = 0; k < outline.size(); ++k) {
        out->segments.push_back({outline[k], outline[(k + 1) % outline.size()], element});
      }
    }
  }
}

void CrowdCoupling::CastRay(const Eigen::Vector3d& from_m, const Eigen::Vector3d& to_m,
                            RayHit* best) const {
  const Eigen::Vector3d d = to_m - from_m;
  const double length = d.norm();
  const double planar = d.head<2>().norm();
  if (length <= 0.0 || planar <= 0.0) return;
  const Eigen::Vector2d o = from_m.head<2>();
  const Eigen::Vector2d u = d.head<2>() / planar;
  const double z = 0.5 * (from_m.z() + to_m.z());
  double nearest = best->hit ? best->distance_m * planar / length : planar;
  int hit_person = -1;
  Eigen::Vector2d hit_center{0, 0};
  double hit_radius = 0.0;
  const std::vector<crowd::PersonState>& people = crowd_->people();
  for (std::size_t i = 0; i < people.size(); ++i) {
    const crowd::PersonState& p = people[i];
    if (!p.present || z < 0.0 || z > p.shape.height_m) continue;
    // Quick rejection: the person's disc against the ray.
    if (RayCircle(o, u, p.position_m, p.shape.radius_m + 0.2) >= nearest) continue;
    if (z < p.shape.hip_height_m) {
      for (const Eigen::Vector2d& c : p.LegCentres(z)) {
        const double t = RayCircle(o, u, c, p.shape.leg_radius_m);
        if (t < nearest) {
          nearest = t;
          hit_person = static_cast<int>(i);
          hit_center = c;
          hit_radius = p.shape.leg_radius_m;
        }
      }
    } else {
      // The torso as its width's circle (rays at torso height are rare).
      const double t = RayCircle(o, u, p.position_m, p.shape.radius_m);
      if (t < nearest) {
        nearest = t;
        hit_person = static_cast<int>(i);
        hit_center = p.position_m;
        hit_radius = p.shape.radius_m;
      }
    }
  }
  if (hit_person < 0) return;
  best->hit = true;
  best->distance_m = nearest * length / planar;
  best->point_m = from_m + d * (nearest / planar);
  const Eigen::Vector2d n = (best->point_m.head<2>() - hit_center) / hit_radius;
  best->normal = Eigen::Vector3d(n.x(), n.y(), 0.0).normalized();
  best->element = person_elements_[hit_person];
}

void CrowdCoupling::UpdateContacts(const std::map<std::pair<int, int>, ContactChange>& touching,
                                   std::vector<ContactChange>* out) {
  // A person touches a robot by pressing on it: the episode's begin is its touch.
  for (const auto& [key, change] : touching) {
    if (touching_.contains(key)) continue;
    ContactChange begin = change;
    begin.phase = ContactPhase::kBegin;
    out->push_back(begin);
    ContactChange touch = change;
    touch.phase = ContactPhase::kTouch;
    touch.touched = true;
    out->push_back(touch);
  }
  for (const auto& key : touching_) {
    if (!touching.contains(key)) {
      ContactChange end;
      end.phase = ContactPhase::kEnd;
      end.a = key.first;
      end.b = key.second;
      end.touched = true;
      out->push_back(end);
    }
  }
  touching_.clear();
  for (const auto& [key, change] : touching) touching_.insert(key);
}

}  // namespace pavilion::sim
