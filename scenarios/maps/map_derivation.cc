#include "scenarios/maps/map_derivation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <set>
#include <stdexcept>
#include <utility>

#include "core/geometry/segment2.h"
#include "core/math/rounding.h"
#include "core/random/random_stream.h"
#include "core/types/pose2.h"
#include "nav/route/free_space_grid.h"
#include "nav/route/roadmap_builder.h"
#include "scenarios/maps/survey_line_fit.h"
#include "scenarios/maps/vertical_edge_survey.h"

namespace pavilion::scenarios {
namespace {

using Vec2 = Eigen::Vector2d;
using core::Box2;
using core::Cross;
using core::LineCircleHits;
using core::PointSegmentDistance;
using core::RaySegmentHit;
using core::SegmentBox;

// --- constants (docs/map_format.md, "Deriving a map") ---

// Recorded tape-measure sigma never drops below this, so covariances stay
// positive definite when the noise is off (m).
constexpr double kMinRecordedSigmaM = 0.001;
// Grid of the free-space model used only while deriving (m).
constexpr double kCellM = 0.05;
// Faces are tested for being inside another solid this far out (m).
constexpr double kClipOffsetM = 0.001;
// Pieces of faces shorter than this are dropped (m).
constexpr double kMinPieceM = 0.01;
// Visibility samples along a face (m) and the rays cast from each sample: up
// to 85° from the face's normal, so that a face a robot could see at all, even
// at a grazing angle, is mapped (a map errs towards including a face).
constexpr double kSampleStepM = 0.02;
constexpr double kMaxIncidenceRad = 85.0 * std::numbers::pi / 180.0;
constexpr double kIncidenceStepRad = 5.0 * std::numbers::pi / 180.0;
// Maximum range of the robots' SICK LMS 200 (robots/*/robot.yaml, thesis §2.2.2).
constexpr double kLaserRangeM = 8.0;
// A face or column is mapped when at least this much of it can be seen (m).
constexpr double kMinVisibleM = 0.05;
// Faces lie on one infinite line when their endpoints are this close to it (m).
constexpr double kCollinearM = 1e-5;
// Members of a multi-segment line closer than this along the line merge (m):
// a tape measure does not resolve such gaps.
constexpr double kMergeGapM = 0.05;
// Clearances above this are not told apart (m): enough to centre via nodes.
constexpr double kMaxClearanceM = 2.0;
// Lateral search for the sides of an opening (entrance, exit) (m).
constexpr double kOpeningSearchM = 5.0;
// Ghost points closer than this are one (m): a shared corner, not two places.
constexpr double kGhostMergeM = 0.005;
// Resolution of derived numbers: positions and radii, angles, covariances.
constexpr int kPositionDecimals = 6;  // 1 µm
constexpr int kAngleDecimals = 9;     // 1 nrad
constexpr int kCovarianceDigits = 6;  // significant digits

Vec2 RoundPosition(const Vec2& p) {
  return {core::RoundDecimals(p.x(), kPositionDecimals),
          core::RoundDecimals(p.y(), kPositionDecimals)};
}

// alpha in (-pi, pi] at kAngleDecimals; pi itself does not round inside the range.
double RoundAlpha(double alpha_rad) {
  const double a = core::RoundDecimals(core::NormalizeAngle(alpha_rad), kAngleDecimals);
  return std::abs(a) >= std::numbers::pi ? std::numbers::pi : a;
}

Eigen::Matrix2d RoundCovariance(const Eigen::Matrix2d& c) {
  Eigen::Matrix2d r;
  r(0, 0) = core::RoundSignificant(c(0, 0), kCovarianceDigits);
  r(1, 1) = core::RoundSignificant(c(1, 1), kCovarianceDigits);
  r(0, 1) = r(1, 0) = core::RoundSignificant(0.5 * (c(0, 1) + c(1, 0)), kCovarianceDigits);
  return core::IsPositiveDefinite(r) ? r : c;
}

// A solid of the beam section that the laser sees (its outline or circle).
struct Solid {
  int element = -1;
  std::vector<MapObstacles::Segment> outline;  // counter-clockwise around the solid
  std::vector<MapObstacles::Circle> circles;
  Box2 box;

  bool Contains(const Vec2& p) const {
    if (p.x() < box.lo.x() || p.x() > box.hi.x() || p.y() < box.lo.y() || p.y() > box.hi.y()) {
      return false;
    }
    for (const auto& c : circles) {
      if ((p - c.center_m).norm() < c.radius_m) return true;
    }
    int winding = 0;  // non-zero inside a closed counter-clockwise outline
    for (const auto& s : outline) {
      const double side = Cross(s.b_m - s.a_m, p - s.a_m);
      if (s.a_m.y() <= p.y()) {
        if (s.b_m.y() > p.y() && side > 0) ++winding;
      } else if (s.b_m.y() <= p.y() && side < 0) {
        --winding;
      }
    }
    return winding != 0;
  }
};

// The laser's view of the beam section: what occludes a ray.
class LaserView {
 public:
  explicit LaserView(const std::vector<Solid>& solids) : solids_(solids) {}

  // True when a laser at a reachable cell sees `point` along `dir` (unit, away
  // from the surface) within range, with nothing opaque in between.
  bool SeenAlong(const Vec2& point, const Vec2& dir, const nav::FreeSpaceGrid& free) const {
    const Vec2 origin = point + 1e-4 * dir;
    double reach = -1.0;
    for (double t = 0.5 * kCellM; t <= kLaserRangeM; t += 0.5 * kCellM) {
      std::size_t i;
      if (!free.CellOf(origin + t * dir, &i)) break;  // left the floor
      if (free.reachable(i)) {
        reach = t;
        break;
      }
    }
    if (reach < 0.0) return false;
    const Vec2 end = origin + reach * dir;
    const Box2 ray = SegmentBox(origin, end);
    for (const Solid& s : solids_) {
      if (!s.box.Overlaps(ray, 0.0)) continue;
      for (const auto& seg : s.outline) {
        if (RaySegmentHit(origin, end, seg.a_m, seg.b_m) <= 1.0) return false;
      }
      for (const auto& c : s.circles) {
        if (PointSegmentDistance(c.center_m, origin, end) < c.radius_m) return false;
      }
    }
    return true;
  }

  // Length of the samples (spaced `step`, with outward normals) that a laser
  // sees; stops counting at kMinVisibleM.
  double VisibleLength(const std::vector<std::pair<Vec2, Vec2>>& samples, double step,
                       const nav::FreeSpaceGrid& free) const {
    double seen = 0.0;
    for (const auto& [p, normal] : samples) {
      for (double k = 0.0; k * kIncidenceStepRad <= kMaxIncidenceRad + 1e-9; k += 1.0) {
        bool hit = false;
        for (const double sign : {1.0, -1.0}) {
          if (k == 0.0 && sign < 0.0) continue;
          const double a = sign * k * kIncidenceStepRad;
          const Vec2 dir(std::cos(a) * normal.x() - std::sin(a) * normal.y(),
                         std::sin(a) * normal.x() + std::cos(a) * normal.y());
          if (SeenAlong(p, dir, free)) {
            hit = true;
            break;
          }
        }
        if (hit) {
          seen += step;
          break;
        }
      }
      if (seen >= kMinVisibleM - 1e-12) return seen;
    }
    return seen;
  }

 private:
  const std::vector<Solid>& solids_;
};

// Pieces of collinear faces on one infinite line (inward normal n, n . p = r).
struct LineGroup {
  Vec2 normal;  // unit, pointing into the solids (eq. B.4: seen from n . p < r)
  double r = 0.0;
  std::vector<std::pair<double, double>> spans;  // along (-n_y, n_x)
};

Vec2 AlongDir(const Vec2& n) { return {-n.y(), n.x()}; }

std::string Numbered(const std::string& prefix, int k) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%03d", k);
  return prefix + buf;
}

bool IsOpening(const std::string& place) {
  return place == "entrance" || place == "exit" || place.starts_with("entrance_") ||
         place.starts_with("exit_");
}

bool IsStation(const std::string& name, const sim::Place& place) {
  return name.starts_with("station_") || name.starts_with("dock_") || place.station;
}

Vec2 AreaCentroid(const core::Polygon2& poly) {
  double area = 0.0;
  Vec2 c = Vec2::Zero();
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[(i + 1) % poly.size()];
    const double w = Cross(a, b);
    area += w;
    c += w * (a + b);
  }
  return std::abs(area) > 1e-12 ? Vec2(c / (3.0 * area)) : poly.front();
}

}  // namespace

void MapDerivationOptions::Validate() const {
  const auto check = [](bool ok, const char* field, const char* range) {
    if (!ok) throw std::invalid_argument(std::string(field) + " must be in " + range);
  };
  check(std::isfinite(beam_height_m) && beam_height_m > 0.0 && beam_height_m <= 10.0,
        "beam_height_m", "(0, 10] m");
  check(std::isfinite(low_height_m) && low_height_m > 0.0 && low_height_m < beam_height_m,
        "low_height_m", "(0, beam_height_m) m");
  check(std::isfinite(noise_sigma_m) && noise_sigma_m >= 0.0 && noise_sigma_m <= 0.1,
        "noise_sigma_m", "[0, 0.1] m");
  check(wall_offset_sigma_m >= 0.0 && wall_offset_sigma_m <= 0.1, "wall_offset_sigma_m",
        "[0, 0.1] m");
  check(std::isfinite(robot_radius_m) && robot_radius_m >= 0.05 && robot_radius_m <= 2.0,
        "robot_radius_m", "[0.05, 2] m");
  check(std::isfinite(via_spacing_m) && via_spacing_m >= 0.5 && via_spacing_m <= 20.0,
        "via_spacing_m", "[0.5, 20] m");
  check(std::isfinite(ghost_spacing_m) && ghost_spacing_m > 0.0 &&
            ghost_spacing_m < 2.0 * robot_radius_m,
        "ghost_spacing_m", "(0, 2 * robot_radius_m) m");
}

MapObstacles NavigationObstacles(const sim::World& world, double beam_height_m,
                                 double low_height_m) {
  MapObstacles out;
  for (const double z : {beam_height_m, low_height_m}) {
    const core::PlanarSection s = world.SectionAt(z);
    for (const auto& seg : s.segments) {
      if (!s.elements[seg.element].dynamic) out.segments.push_back({seg.a_m, seg.b_m});
    }
    for (const auto& c : s.circles) {
      if (!s.elements[c.element].dynamic) out.circles.push_back({c.center_m, c.radius_m});
    }
  }
  return out;
}

namespace {

// One derivation: the steps of docs/map_format.md ("Deriving a map") in order,
// sharing the sections, the solids, the free space and the noise stream.
class MapDeriver {
 public:
  MapDeriver(const sim::World& world, const MapDerivationOptions& options,
             std::vector<std::string>* warnings)
      : world_(world),
        d_(world.description()),
        options_(options),
        warn_(*warnings),
        radius_(options.robot_radius_m),
        sigma_(options.noise_sigma_m),
        recorded_sigma_(std::max(sigma_, kMinRecordedSigmaM)),
        point_cov_(recorded_sigma_ * recorded_sigma_ * Eigen::Matrix2d::Identity()),
        noise_(options.seed, core::RandomStream::StreamId("map_derive")),
        wall_offsets_(options.seed, core::RandomStream::StreamId("map_wall_offsets")),
        beam_(world.SectionAt(options.beam_height_m)),
        low_(world.SectionAt(options.low_height_m)),
        elements_(beam_.elements),
        obstacles_(NavigationObstacles(world, options.beam_height_m, options.low_height_m)) {}

  core::RobotMap Derive() {
    map_.name = d_.name;
    map_.beam_height_m = options_.beam_height_m;
    map_.description = Description();
    CollectSolids();
    AddGhostPoints();
    FindReachableFloor();
    MapFaces();
    MapColumnsAndBeacons();
    MapVerticalEdges();
    BuildTopology();
    try {
      core::ValidateRobotMap(map_);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error(std::string("derived map is invalid: ") + e.what());
    }
    return map_;
  }

 private:
  std::string Description() const {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "Derived by 'pavilion map derive' from world '%s': section at %g m, "
                  "tape-measure noise %g mm (seed %llu), robot radius %g m, via spacing %g m, "
                  "low cut %g m, ghost spacing %g m.",
                  d_.name.c_str(), options_.beam_height_m, sigma_ * 1000.0,
                  static_cast<unsigned long long>(options_.seed), radius_, options_.via_spacing_m,
                  options_.low_height_m, options_.ghost_spacing_m);
    std::string text = buf;
    if (options_.wall_offset_sigma_m != 0.0) {
      text += "; walls off by sigma " + std::to_string(options_.wall_offset_sigma_m) + " m.";
    }
    if (options_.vertical_edges) text += " Vertical edges mapped as points edge_NNN.";
    return text;
  }

  bool Opaque(int e) const {
    return !elements_[e].dynamic && elements_[e].laser != core::LaserResponse::kTransparent;
  }

  // A measured position: the true one plus the tape-measure error.
  Vec2 Measure(const Vec2& p) {
    if (sigma_ == 0.0) return p;
    const double dx = noise_.Normal(0.0, sigma_);
    const double dy = noise_.Normal(0.0, sigma_);
    return {p.x() + dx, p.y() + dy};
  }

  // Solids the laser sees at the beam height, one per element.
  void CollectSolids() {
    std::map<int, std::size_t> solid_of;
    const auto solid = [&](int e) -> Solid& {
      auto [it, added] = solid_of.try_emplace(e, solids_.size());
      if (added) solids_.push_back(Solid{e, {}, {}, {}});
      return solids_[it->second];
    };
    for (const auto& s : beam_.segments) {
      if (!Opaque(s.element)) continue;
      Solid& so = solid(s.element);
      so.outline.push_back({s.a_m, s.b_m});
      so.box.Add(s.a_m);
      so.box.Add(s.b_m);
    }
    for (const auto& c : beam_.circles) {
      if (!Opaque(c.element)) continue;
      Solid& so = solid(c.element);
      so.circles.push_back({c.center_m, c.radius_m});
      so.box.Add(c.center_m.array() - c.radius_m);
      so.box.Add(c.center_m.array() + c.radius_m);
    }
  }

  // One ghost point per place: a corner shared by two outline segments, a row
  // across an opening that ends on an outline. Closer points stay, so a glass
  // panel thinner than the spacing keeps its far face (a robot passing its
  // end must not see the panel 3 cm thinner than it is).
  void AddGhost(const Vec2& p) {
    for (const Vec2& g : ghosts_) {
      if ((g - p).norm() < kGhostMergeM) return;
    }
    ghosts_.push_back(RoundPosition(p));
  }

  // Distance from `o` along `dir` to the first navigation obstacle; +inf beyond
  // kOpeningSearchM.
  double RayDistance(const Vec2& o, const Vec2& dir) const {
    double best = std::numeric_limits<double>::infinity();
    const Vec2 e = o + kOpeningSearchM * dir;
    for (const auto& s : obstacles_.segments) {
      best = std::min(best, kOpeningSearchM * RaySegmentHit(o, e, s.a_m, s.b_m));
    }
    for (const auto& c : obstacles_.circles) {
      for (double t : LineCircleHits(o, e, c.center_m, c.radius_m)) {
        if (t >= 0.0 && t <= 1.0) best = std::min(best, kOpeningSearchM * t);
      }
    }
    return best;
  }

  void SampleOutline(const core::PlanarSection& section, int e) {
    for (const auto& s : section.segments) {
      if (s.element != e) continue;
      const double len = (s.b_m - s.a_m).norm();
      const int n = std::max(1, static_cast<int>(std::ceil(len / options_.ghost_spacing_m)));
      for (int k = 0; k <= n; ++k) AddGhost(s.a_m + (s.b_m - s.a_m) * (double(k) / n));
    }
    for (const auto& c : section.circles) {
      if (c.element != e) continue;
      const double len = 2.0 * std::numbers::pi * c.radius_m;
      const int n = std::max(3, static_cast<int>(std::ceil(len / options_.ghost_spacing_m)));
      for (int k = 0; k < n; ++k) {
        const double a = 2.0 * std::numbers::pi * k / n;
        AddGhost(c.center_m + c.radius_m * Vec2(std::cos(a), std::sin(a)));
      }
    }
  }

  // Ghost points (§6.3.1): rows across openings, and the outlines of what the
  // laser cannot see. They, and the floor's edge, join the navigation obstacles.
  void AddGhostPoints() {
    for (const auto& [name, place] : d_.places) {
      if (!IsOpening(name) || !place.pose) continue;
      const Vec2 p = place.pose->translation();
      const Vec2 u(-std::sin(place.pose->theta_rad), std::cos(place.pose->theta_rad));
      const double left = RayDistance(p, u), right = RayDistance(p, -u);
      if (!std::isfinite(left) || !std::isfinite(right)) {
        char buf[160];
        std::snprintf(buf, sizeof buf,
                      "opening '%s': no obstacle on both sides within %g m; not closed",
                      name.c_str(), kOpeningSearchM);
        warn_.push_back(buf);
        continue;
      }
      const double gap = left + right;
      const int n = std::max(1, static_cast<int>(std::ceil(gap / options_.ghost_spacing_m)));
      for (int k = 0; k < n; ++k) AddGhost(p - right * u + (k + 0.5) * (gap / n) * u);
    }
    std::vector<char> seen_at_beam(elements_.size(), 0);
    for (const auto& s : beam_.segments) seen_at_beam[s.element] |= Opaque(s.element);
    for (const auto& c : beam_.circles) seen_at_beam[c.element] |= Opaque(c.element);
    for (std::size_t e = 1; e < elements_.size(); ++e) {  // 0 is the floor
      if (elements_[e].dynamic || seen_at_beam[e]) continue;
      const int element = static_cast<int>(e);
      bool in_low = false, in_beam = false;
      for (const auto& s : low_.segments) in_low |= s.element == element;
      for (const auto& c : low_.circles) in_low |= c.element == element;
      for (const auto& s : beam_.segments) in_beam |= s.element == element;
      for (const auto& c : beam_.circles) in_beam |= c.element == element;
      if (in_low) {
        SampleOutline(low_, element);
      } else if (in_beam) {
        SampleOutline(beam_, element);
      }
    }
    for (std::size_t i = 0; i < ghosts_.size(); ++i) {
      map_.ghost_points.push_back({Numbered("ghost_", static_cast<int>(i) + 1), ghosts_[i]});
      obstacles_.circles.push_back({ghosts_[i], 0.0});
    }
    // The robot stays on the floor.
    const Vec2 f0 = d_.floor.min_m, f1 = d_.floor.max_m;
    const Vec2 corners[4] = {f0, {f1.x(), f0.y()}, f1, {f0.x(), f1.y()}};
    for (int k = 0; k < 4; ++k) obstacles_.segments.push_back({corners[k], corners[(k + 1) % 4]});
  }

  // The floor a robot can reach from the places; the places that become nodes.
  void FindReachableFloor() {
    const double cap =
        std::max(radius_ + kCellM, std::min(0.5 * options_.via_spacing_m, kMaxClearanceM));
    free_ = std::make_unique<nav::FreeSpaceGrid>(d_.floor.min_m, d_.floor.max_m, obstacles_, cap,
                                                 kCellM);
    std::vector<std::size_t> seeds;
    for (const auto& [name, place] : d_.places) {
      if (IsOpening(name)) continue;
      const Vec2 p = place.pose ? place.pose->translation() : AreaCentroid(*place.area);
      std::size_t i;
      const bool free_here = free_->CellOf(p, &i) && free_->clearance(i) >= radius_;
      if (free_here) seeds.push_back(i);
      if (place.pose) {
        node_places_.emplace_back(name, p);
        if (!free_here) {
          warn_.push_back("place '" + name + "' is closer than the robot radius to an obstacle");
        }
      } else if (free_here) {
        node_places_.emplace_back(name, p);
      } else {
        warn_.push_back("area '" + name + "': its centroid is not free; no node there");
      }
    }
    if (seeds.empty()) {
      warn_.push_back("the world has no free place: all free floor counts as reachable");
      for (std::size_t i = 0; i < static_cast<std::size_t>(free_->nx()) * free_->ny(); ++i) {
        if (free_->clearance(i) < radius_) continue;
        bool solid = false;
        for (const Solid& so : solids_) solid = solid || so.Contains(free_->Center(i));
        if (!solid) seeds.push_back(i);
      }
    }
    free_->Flood(seeds, radius_);
  }

  // Length of a face or outline a laser sees (samples: points and outward normals).
  double Visible(const std::vector<std::pair<Vec2, Vec2>>& samples, double step) const {
    return LaserView(solids_).VisibleLength(samples, step, *free_);
  }

  // The pieces of one face outside every other opaque solid (checked
  // kClipOffsetM in front of it), as parameter spans along a -> b.
  std::vector<std::pair<double, double>> Unburied(const core::SectionSegment& s,
                                                  const Vec2& out_normal) const {
    const Vec2 a = s.a_m + kClipOffsetM * out_normal, b = s.b_m + kClipOffsetM * out_normal;
    const Box2 box = SegmentBox(a, b);
    std::vector<double> cuts = {0.0, 1.0};
    std::vector<const Solid*> near;
    for (const Solid& other : solids_) {
      if (other.element == s.element || !other.box.Overlaps(box, 0.0)) continue;
      near.push_back(&other);
      for (const auto& o : other.outline) {
        const double t = RaySegmentHit(a, b, o.a_m, o.b_m);
        if (t > 0.0 && t < 1.0) cuts.push_back(t);
      }
      for (const auto& c : other.circles) {
        for (double t : LineCircleHits(a, b, c.center_m, c.radius_m)) {
          if (t > 0.0 && t < 1.0) cuts.push_back(t);
        }
      }
    }
    std::sort(cuts.begin(), cuts.end());
    std::vector<std::pair<double, double>> spans;
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      if (cuts[k + 1] - cuts[k] <= 0.0) continue;
      const Vec2 mid = a + (b - a) * (0.5 * (cuts[k] + cuts[k + 1]));
      bool hidden = false;
      for (const Solid* o : near) hidden = hidden || o->Contains(mid);
      if (hidden) continue;
      if (!spans.empty() && spans.back().second == cuts[k]) {
        spans.back().second = cuts[k + 1];
      } else {
        spans.emplace_back(cuts[k], cuts[k + 1]);
      }
    }
    return spans;
  }

  // Faces -> visible pieces -> groups on one line -> segments and
  // multi-segment lines with tape-measure noise (eq. 5.17, eq. B.4).
  void MapFaces() {
    element_seen_.assign(elements_.size(), 0);
    std::vector<LineGroup> groups;
    for (const auto& s : beam_.segments) {
      if (!Opaque(s.element)) continue;
      const Vec2 ab = s.b_m - s.a_m;
      const double len = ab.norm();
      if (len < kMinPieceM) continue;
      const Vec2 out_normal(ab.y() / len, -ab.x() / len);  // solid on the left of a -> b
      for (const auto& [t0, t1] : Unburied(s, out_normal)) {
        const Vec2 pa = s.a_m + t0 * ab, pb = s.a_m + t1 * ab;
        const double piece = (pb - pa).norm();
        if (piece < kMinPieceM) continue;
        std::vector<std::pair<Vec2, Vec2>> samples;
        const int n = std::max(1, static_cast<int>(std::floor(piece / kSampleStepM)));
        for (int k = 0; k < n; ++k)
          samples.emplace_back(pa + (pb - pa) * ((k + 0.5) / n), out_normal);
        if (Visible(samples, piece / n) < kMinVisibleM - 1e-12) continue;
        element_seen_[s.element] = 1;
        if (elements_[s.element].laser == core::LaserResponse::kRetroReflective) continue;
        AddToGroup(&groups, pa, pb);
      }
    }
    int line_count = 0;
    for (LineGroup& g : groups) AddLineFeature(g, Numbered("line_", ++line_count));
  }

  static void AddToGroup(std::vector<LineGroup>* groups, const Vec2& a, const Vec2& b) {
    const Vec2 ab = b - a;
    const Vec2 normal = Vec2(-ab.y(), ab.x()).normalized();  // into the solid
    LineGroup* group = nullptr;
    for (LineGroup& g : *groups) {
      if (g.normal.dot(normal) > 1.0 - 1e-9 && std::abs(g.normal.dot(a) - g.r) < kCollinearM &&
          std::abs(g.normal.dot(b) - g.r) < kCollinearM) {
        group = &g;
        break;
      }
    }
    if (group == nullptr) {
      groups->push_back({normal, normal.dot(a), {}});
      group = &groups->back();
    }
    const Vec2 along = AlongDir(group->normal);
    group->spans.emplace_back(std::min(along.dot(a), along.dot(b)),
                              std::max(along.dot(a), along.dot(b)));
  }

  void AddLineFeature(LineGroup& g, const std::string& id) {
    std::sort(g.spans.begin(), g.spans.end());
    std::vector<std::pair<double, double>> merged;
    for (const auto& span : g.spans) {
      if (!merged.empty() && span.first <= merged.back().second + kMergeGapM) {
        merged.back().second = std::max(merged.back().second, span.second);
      } else {
        merged.push_back(span);
      }
    }
    // Measured corners, with tape-measure noise, and the line fitted through them.
    const Vec2 along = AlongDir(g.normal);
    const Vec2 foot = g.r * g.normal;
    std::vector<Vec2> corners;
    for (const auto& [s0, s1] : merged) {
      corners.push_back(Measure(foot + s0 * along));
      corners.push_back(Measure(foot + s1 * along));
    }
    const double w = options_.wall_offset_sigma_m;  // each end of the wall off along its normal
    if (w > 0.0) {
      const double e_first = wall_offsets_.Normal(0.0, w);
      ShiftWall(g.normal, along, e_first, wall_offsets_.Normal(0.0, w), &corners);
    }
    const auto [alpha_fit, r_fit] = FitLine(corners, g.normal);
    core::Line line;
    line.alpha_rad = RoundAlpha(alpha_fit);
    line.r_m = core::RoundDecimals(r_fit, kPositionDecimals);
    Eigen::Matrix2d covariance = FitCovariance(corners, g.normal, recorded_sigma_);
    // The surveyor states the method's accuracy, the ends' errors included.
    if (w > 0.0) covariance += WallEndCovariance(corners, g.normal, along, w);
    line.covariance = RoundCovariance(covariance);
    if (line.r_m == 0.0) {
      throw std::runtime_error("map line " + id +
                               " passes through the world origin (r = 0), which eq. B.4 cannot "
                               "represent; move the world's origin off the wall faces");
    }
    const Vec2 n = line.normal();
    const Vec2 dir = AlongDir(n);
    const auto project = [&](const Vec2& p) {
      return core::Point2Uncertain{RoundPosition(p - (n.dot(p) - line.r_m) * n), point_cov_};
    };
    std::vector<std::pair<core::Point2Uncertain, core::Point2Uncertain>> members;
    for (std::size_t k = 0; k < merged.size(); ++k) {
      core::Point2Uncertain a = project(corners[2 * k]);
      core::Point2Uncertain b = project(corners[2 * k + 1]);
      if (dir.dot(a.position_m) > dir.dot(b.position_m)) std::swap(a, b);
      if (!members.empty() && dir.dot(a.position_m) < dir.dot(members.back().second.position_m)) {
        a.position_m = members.back().second.position_m;  // noise made neighbours overlap
      }
      if (dir.dot(b.position_m) - dir.dot(a.position_m) <= 0.0) continue;
      members.emplace_back(a, b);
    }
    if (members.size() == 1) {
      map_.segments.push_back({id, line, members[0].first, members[0].second});
    } else if (members.size() > 1) {
      map_.multi_segment_lines.push_back({id, line, members});
    }
  }

  // Columns become points, retro-reflective elements beacons (§3.3, §6.3.5.1).
  void MapColumnsAndBeacons() {
    for (const auto& c : beam_.circles) {
      if (!Opaque(c.element)) continue;
      std::vector<std::pair<Vec2, Vec2>> samples;
      const int n = std::max(
          12, static_cast<int>(std::ceil(2.0 * std::numbers::pi * c.radius_m / kSampleStepM)));
      for (int k = 0; k < n; ++k) {
        const double a = 2.0 * std::numbers::pi * (k + 0.5) / n;
        const Vec2 u(std::cos(a), std::sin(a));
        samples.emplace_back(c.center_m + c.radius_m * u, u);
      }
      if (Visible(samples, 2.0 * std::numbers::pi * c.radius_m / n) < kMinVisibleM - 1e-12) {
        continue;
      }
      element_seen_[c.element] = 1;
      const core::Point2Uncertain centre{RoundPosition(Measure(c.center_m)), point_cov_};
      if (elements_[c.element].laser == core::LaserResponse::kRetroReflective) {
        map_.beacons.push_back(
            {elements_[c.element].id, centre, core::RoundDecimals(c.radius_m, kPositionDecimals)});
      } else {
        map_.points.push_back(
            {elements_[c.element].id, centre, core::RoundDecimals(c.radius_m, kPositionDecimals)});
      }
    }
    for (std::size_t e = 0; e < elements_.size(); ++e) {
      if (!element_seen_[e] || elements_[e].laser != core::LaserResponse::kRetroReflective) {
        continue;
      }
      Vec2 sum = Vec2::Zero();
      double total = 0.0;
      for (const auto& s : beam_.segments) {
        if (s.element != static_cast<int>(e)) continue;
        const double len = (s.b_m - s.a_m).norm();
        sum += len * 0.5 * (s.a_m + s.b_m);
        total += len;
      }
      if (total <= 0.0) continue;  // a retro column: done above
      map_.beacons.push_back(
          {elements_[e].id,
           core::Point2Uncertain{RoundPosition(Measure(sum / total)), point_cov_}});
    }
  }

  // Vertical edges (§4.2, Fig. 4.2) a robot's free space sees, when asked.
  void MapVerticalEdges() {
    if (!options_.vertical_edges) return;
    core::RandomStream noise(options_.seed, core::RandomStream::StreamId("map_vertical_edges"));
    const LaserView view(solids_);
    int k = 0;
    for (const SurveyedEdge& e : SurveyVerticalEdges(world_, VerticalEdgeSurveyOptions{})) {
      if (!view.SeenAlong(e.position_m, e.outward, *free_)) continue;
      Vec2 p = e.position_m;
      if (sigma_ > 0.0) p += Vec2(noise.Normal(0.0, sigma_), noise.Normal(0.0, sigma_));
      map_.points.push_back({Numbered("edge_", ++k), {RoundPosition(p), point_cov_}, 0.0});
    }
  }

  // Topology (§6.3.1): station nodes and the places' nodes, then the roadmap
  // of via nodes and collision-free edges (nav::BuildRoadmap).
  void BuildTopology() {
    std::vector<core::MapNode> nodes;
    for (const auto& [name, place] : d_.places) {
      if (IsStation(name, place) && place.pose) {
        core::Pose2 pose = *place.pose;
        pose.x_m = core::RoundDecimals(pose.x_m, kPositionDecimals);
        pose.y_m = core::RoundDecimals(pose.y_m, kPositionDecimals);
        nodes.push_back({name, pose, true});
      }
    }
    for (const auto& [name, p] : node_places_) {
      if (IsStation(name, d_.places.at(name)) && d_.places.at(name).pose) continue;
      const core::Pose2 pose = d_.places.at(name).pose.value_or(core::Pose2{p.x(), p.y(), 0.0});
      nodes.push_back({name,
                       {core::RoundDecimals(pose.x_m, kPositionDecimals),
                        core::RoundDecimals(pose.y_m, kPositionDecimals), pose.theta_rad},
                       false});
    }
    nav::RoadmapOptions roadmap_options;
    roadmap_options.robot_radius_m = radius_;
    roadmap_options.via_spacing_m = options_.via_spacing_m;
    roadmap_options.position_decimals = kPositionDecimals;
    nav::Roadmap roadmap =
        nav::BuildRoadmap(std::move(nodes), *free_, obstacles_, roadmap_options, &warn_);
    map_.nodes = std::move(roadmap.nodes);
    map_.edges = std::move(roadmap.edges);
  }

  const sim::World& world_;
  const sim::WorldDescription& d_;
  const MapDerivationOptions& options_;
  std::vector<std::string>& warn_;
  const double radius_;
  const double sigma_;
  const double recorded_sigma_;
  const Eigen::Matrix2d point_cov_;
  core::RandomStream noise_;
  core::RandomStream wall_offsets_;
  const core::PlanarSection beam_;
  const core::PlanarSection low_;
  const std::vector<core::SectionElement>& elements_;
  MapObstacles obstacles_;  // navigation obstacles, then ghost points and the floor's edge

  core::RobotMap map_;
  std::vector<Solid> solids_;
  std::vector<Vec2> ghosts_;
  std::unique_ptr<nav::FreeSpaceGrid> free_;
  std::vector<std::pair<std::string, Vec2>> node_places_;  // places that become nodes
  std::vector<char> element_seen_;
};

}  // namespace

core::RobotMap DeriveRobotMap(const sim::World& world, const MapDerivationOptions& options,
                              std::vector<std::string>* warnings) {
  options.Validate();
  std::vector<std::string> ignored;
  return MapDeriver(world, options, warnings != nullptr ? warnings : &ignored).Derive();
}

core::RobotMap KeepLinesAlongDirection(const core::RobotMap& map, double direction_rad,
                                       double tolerance_rad) {
  if (!std::isfinite(direction_rad)) {
    throw std::invalid_argument("direction_rad must be finite");
  }
  if (!(tolerance_rad > 0.0 && tolerance_rad <= 0.5 * std::numbers::pi)) {
    throw std::invalid_argument("tolerance_rad must be in (0, pi/2]");
  }
  // Angle between the line's direction and `direction_rad`, as undirected lines: [0, pi/2].
  const auto along = [&](const core::Line& line) {
    const double d =
        std::abs(core::NormalizeAngle(line.alpha_rad + 0.5 * std::numbers::pi - direction_rad));
    return std::min(d, std::numbers::pi - d) <= tolerance_rad;
  };
  core::RobotMap kept = map;
  std::erase_if(kept.lines, [&](const core::MapLine& l) { return !along(l.line); });
  std::erase_if(kept.segments, [&](const core::MapSegment& s) { return !along(s.line); });
  std::erase_if(kept.multi_segment_lines,
                [&](const core::MapMultiSegmentLine& m) { return !along(m.line); });
  // Vertical edges (radius 0) are the camera's, not the laser's: they stay.
  std::erase_if(kept.points, [](const core::MapPoint& p) { return p.radius_m != 0.0; });
  const bool edges = !kept.points.empty();
  kept.beacons.clear();
  char buf[200];
  std::snprintf(buf, sizeof buf,
                " Kept only the lines within %g deg of the direction %g deg "
                "(--keep-direction); %s dropped.",
                tolerance_rad * 180.0 / std::numbers::pi, direction_rad * 180.0 / std::numbers::pi,
                edges ? "columns and beacons (vertical edges kept)" : "points and beacons");
  kept.description += buf;
  return kept;
}

}  // namespace pavilion::scenarios
