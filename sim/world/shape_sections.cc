#include "sim/world/shape_sections.h"

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/world/bullet_conversions.h"

namespace pavilion::sim {
namespace {

// A shape whose z axis has a vertical component below this lies too flat for
// its side edges to meet a horizontal plane at a usable angle (cos 89.4°).
constexpr double kMinAxisZ = 0.01;

// A bound of an element that could not be cut, for the planar caster's fallback
// test: the horizontal distance of its points from the centre is at most the radius.
void AddUncut(const btVector3& centre, double radius, int element,
              std::vector<UncutElement>* uncut) {
  uncut->push_back({element, {centre.x(), centre.y()}, radius});
}

}  // namespace

void CutSphere(const btVector3& centre, double radius, double h, int element,
               core::PlanarSection* out) {
  const double dz = h - centre.z();
  if (std::abs(dz) < radius) {
    out->circles.push_back(
        {{centre.x(), centre.y()}, std::sqrt(radius * radius - dz * dz), element});
  }
}

void CutPrism(const btTransform& t, const std::vector<Eigen::Vector2d>& polygon, double z0,
              double z1, double h, int element, core::PlanarSection* out,
              std::vector<UncutElement>* uncut) {
  const btVector3 axis = t.getBasis().getColumn(2);
  std::vector<Eigen::Vector2d> cut;
  cut.reserve(polygon.size());
  std::size_t below = 0, above = 0;
  for (const Eigen::Vector2d& p : polygon) {
    const btVector3 foot = t * btVector3(p.x(), p.y(), 0.0);
    // Shape-frame height at which this side edge meets the plane.
    const double s = axis.z() > kMinAxisZ ? (h - foot.z()) / axis.z() : 0.0;
    if (s < z0) ++below;
    if (s >= z1) ++above;
    cut.emplace_back(foot.x() + s * axis.x(), foot.y() + s * axis.y());
  }
  const std::size_t n = polygon.size();
  if (axis.z() > kMinAxisZ && (below == n || above == n)) return;  // not cut
  if (axis.z() > kMinAxisZ && below == 0 && above == 0) {
    for (std::size_t i = 0; i < n; ++i)
      out->segments.push_back({cut[i], cut[(i + 1) % n], element});
    return;
  }
  if (uncut != nullptr) {
    // Lying down or cut through a cap: only if the plane reaches the prism at all.
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Eigen::Vector2d& p : polygon) {
      for (const double zz : {z0, z1}) {
        const double vz = (t * btVector3(p.x(), p.y(), zz)).z();
        lo = std::min(lo, vz);
        hi = std::max(hi, vz);
      }
    }
    if (h < lo || h > hi) return;
    double reach = 0.0;  // horizontal bound of the prism around its origin
    for (const Eigen::Vector2d& p : polygon) {
      for (const double zz : {z0, z1}) {
        const btVector3 v = t * btVector3(p.x(), p.y(), zz) - t.getOrigin();
        reach = std::max(reach, std::hypot(v.x(), v.y()));
      }
    }
    AddUncut(t.getOrigin(), reach, element, uncut);
    return;
  }
  // Upright extrusion at the planar pose (as the section did before tilts were cut).
  const btVector3 o = t.getOrigin();
  const double dz = h - o.z();
  if (dz < z0 || dz >= z1) return;
  const core::Pose2 pose{o.x(), o.y(), YawOf(t)};
  for (std::size_t i = 0; i < n; ++i) {
    out->segments.push_back({pose * polygon[i], pose * polygon[(i + 1) % n], element});
  }
}

void CutCylinder(const btTransform& t, double radius, double half_height, double h,
                 double max_tilt_rad, int element, core::PlanarSection* out,
                 std::vector<UncutElement>* uncut) {
  const btVector3 axis = t.getBasis().getColumn(2);
  const btVector3& c = t.getOrigin();
  const double bound = std::hypot(radius, half_height);
  if (std::abs(h - c.z()) >= bound) return;  // out of reach of the plane
  if (axis.z() > kMinAxisZ) {
    const double s = (h - c.z()) / axis.z();  // axial coordinate of the axis' crossing
    const double spread = radius * std::sqrt(std::max(0.0, 1.0 - axis.z() * axis.z())) / axis.z();
    if (s + spread < -half_height || s - spread >= half_height) return;  // not cut
    const bool sides_only = s - spread >= -half_height && s + spread < half_height;
    core::SectionCircle cut{{c.x() + s * axis.x(), c.y() + s * axis.y()}, radius, element};
    const double horizontal = std::hypot(axis.x(), axis.y());
    if (sides_only && axis.z() < std::cos(max_tilt_rad) && horizontal > 0.0) {  // the ellipse
      cut.major_axis = {axis.x() / horizontal, axis.y() / horizontal};
      cut.squash = axis.z();
      out->circles.push_back(cut);
      return;
    }
    if (sides_only || uncut == nullptr) {
      out->circles.push_back(cut);
      return;
    }
  } else if (uncut == nullptr) {
    return;  // lying flat: no meaningful circle for the picture
  }
  AddUncut(c, bound, element, uncut);
}

}  // namespace pavilion::sim
